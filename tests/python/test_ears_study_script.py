"""scripts/ears-study.sh's arguments: a bad size or a scene that is not a file is refused with exit 2 and the value
named, before any study runs; `all` runs the 25 study scenes (the six boxes and every regime scene), each once,
and prints one row for each. The program is a stand-in (SYMPHONG_BIN) that records its scene and writes the
results.json that the script's table reads, so no render is made."""
import os
import pathlib
import subprocess

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "ears-study.sh"

FAKE = """#!/bin/sh
# symphong study SCENE ... --out DIR: records SCENE, writes DIR/results.json as a study would
scene=$2
while [ $# -gt 0 ]; do [ "$1" = --out ] && out=$2; shift; done
mkdir -p "$out"
echo "$scene" >> "$FAKE_LOG"
printf '{"comparisons":[{"against":"phong","variant":"phong+ears","mse":{"ratio":1.5,"lo":1.25,"hi":1.75,"verdict":"ahead"}}]}' > "$out/results.json"
"""


def run(tmp_path, *args):
    fake = tmp_path / "fake-symphong"
    fake.write_text(FAKE)
    fake.chmod(0o755)
    env = {**os.environ, "SYMPHONG_BIN": str(fake), "FAKE_LOG": str(tmp_path / "scenes.log")}
    return subprocess.run(["bash", str(SCRIPT), str(tmp_path / "out"), *args], capture_output=True, text=True, timeout=120,
                          env=env)


def test_a_bad_size_is_refused_with_its_value(tmp_path):
    p = run(tmp_path, "sobol", "16", "512x")
    assert p.returncode == 2
    assert "'512x'" in p.stderr
    assert not (tmp_path / "out").exists()


def test_a_scene_that_is_not_a_file_is_refused_before_any_study(tmp_path):
    p = run(tmp_path, "sobol", "16", "32x24", "64", "none", "cornell,scenes/no-such-scene.json")
    assert p.returncode == 2
    assert "scenes/no-such-scene.json" in p.stderr
    assert not (tmp_path / "scenes.log").exists()


def test_all_is_the_25_study_scenes(tmp_path):
    p = run(tmp_path, "sobol", "16", "32x24", "64", "none", "all")
    assert p.returncode == 0, p.stderr
    ran = (tmp_path / "scenes.log").read_text().split()
    boxes = ["cornell"] + [f"scenes/{n}.json" for n in
                           ["cornell-diffuse", "cornell-glossy-100", "cornell-glossy-1000", "cornell-all-glossy", "mcguire-glossy"]]
    regime = sorted(str(f.relative_to(ROOT)) for f in (ROOT / "scenes" / "regime").glob("*.json"))
    assert len(ran) == 25 == len(set(ran))
    assert sorted(ran) == sorted(boxes + regime)
    rows = [line for line in p.stdout.splitlines() if "1.50x [1.25, 1.75] ahead" in line]
    assert len(rows) == 25
