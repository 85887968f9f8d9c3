"""scripts/validate/efficiency.py's arguments as docs/performance.md names them: its plain command (the
comparison with Cycles, `--write-doc`) gets past its own checks with the default scenes, and a scene that
Cycles cannot match is refused with exit 2 and the reason. Blender is hidden from it (a `which` that finds
nothing), so the run stops at its first step that needs Blender: no render is made."""
import os
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "validate" / "efficiency.py"


def run_without_blender(tmp_path, *args):
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    which = bin_dir / "which"
    which.write_text("#!/bin/sh\nexit 1\n")
    which.chmod(0o755)
    env = {**os.environ, "PATH": str(bin_dir)}
    return subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True, timeout=120, env=env)


def test_the_documented_command_passes_its_own_checks(tmp_path):
    doc = (ROOT / "docs" / "performance.md").read_text()
    assert "`python3 scripts/validate/efficiency.py --write-doc`" in doc
    p = run_without_blender(tmp_path, "--write-doc")
    assert p.returncode == 1, p.stderr
    assert "Blender is not installed" in p.stderr


def test_a_scene_cycles_cannot_match_is_refused_with_exit_2(tmp_path):
    p = run_without_blender(tmp_path, "--scenes", "cornell-diffuse,cornell")
    assert p.returncode == 2
    assert "--scenes cornell has a glossy block" in p.stderr


def test_an_unknown_scene_is_named(tmp_path):
    p = run_without_blender(tmp_path, "--no-cycles", "--scenes", "nowhere")
    assert p.returncode == 2
    assert "unknown scene 'nowhere'" in p.stderr
