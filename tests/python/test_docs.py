"""docs/python.md's worked example runs as printed and gives what the page says."""
import os
import pathlib
import re
import subprocess
import sys

DOC = pathlib.Path(__file__).resolve().parents[2] / "docs" / "python.md"


def example_code():
    text = DOC.read_text()
    section = text[text.index("## A worked example"):]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def test_worked_example_runs_as_printed(tmp_path):
    p = subprocess.run([sys.executable, "-c", example_code()], cwd=tmp_path, capture_output=True, text=True, timeout=600,
                       env={**os.environ, "MPLBACKEND": "Agg"})
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "convergence.png").stat().st_size > 10_000
    lines = p.stdout.strip().split("\n")
    assert lines[0].startswith("reference:")
    assert len(lines) == 1 + 2 * 4 + 1
    # The page quotes the example's output; the numbers that do not depend on timing must match it.
    quoted = DOC.read_text().split("Its output on the development machine")[1].split("```")[1]
    strip_times = lambda s: re.sub(r"in [0-9.]+ s|[0-9.]+ s, [0-9.]+ Mrays/s", "", s).strip()
    assert [strip_times(l) for l in lines] == [strip_times(l) for l in quoted.strip().split("\n")]
