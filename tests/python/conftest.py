"""Shared fixtures of the Python module's tests (run by CTest: tests/CMakeLists.txt sets PYTHONPATH to the
built module and SYMPHONG_BINARY to the command-line program, so each test can compare the two)."""
import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def sym():
    import symphong
    return symphong


@pytest.fixture(scope="session")
def binary():
    path = os.environ.get("SYMPHONG_BINARY", str(REPO / "build" / "release" / "symphong"))
    if not os.path.exists(path):
        pytest.fail(f"the symphong program is not built at {path} (set SYMPHONG_BINARY)")
    return path


@pytest.fixture(scope="session")
def shared_scenes():
    """../shared/scenes beside the repository, or $SYMPHONG_SCENES; skipped when absent unless CI
    requires it (SYMPHONG_REQUIRE_SCENES)."""
    path = pathlib.Path(os.environ.get("SYMPHONG_SCENES", REPO.parent / "shared" / "scenes"))
    if not path.is_dir():
        if os.environ.get("SYMPHONG_REQUIRE_SCENES"):
            pytest.fail(f"shared scenes not found at {path}")
        pytest.skip("shared scenes not found beside the repository (set SYMPHONG_SCENES)")
    return path


@pytest.fixture
def cli(binary):
    """Runs the program; returns the CompletedProcess (text output)."""
    def run(*args, check=True):
        p = subprocess.run([binary, *map(str, args)], capture_output=True, text=True)
        if check and p.returncode != 0:
            raise AssertionError(f"symphong {' '.join(map(str, args))} failed ({p.returncode}): {p.stderr}")
        return p
    return run


def cli_error(proc):
    """The message of a failed run: stderr's one line without the 'symphong: error: ' prefix."""
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1, proc.stderr
    prefix = "symphong: error: "
    assert lines[0].startswith(prefix), lines[0]
    return lines[0][len(prefix):]
