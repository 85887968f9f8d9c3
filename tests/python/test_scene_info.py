"""Scene.info() is the text `symphong info` prints (one describeScene() behind both), for scenes with every
kind of light and environment."""
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("spec", ["cornell", "tests/golden/lights.json", "tests/golden/sky.json", "scenes/textured.json",
                                  "tests/data/fbx/box.fbx"])
def test_info_is_the_command_lines(sym, cli, spec, monkeypatch):
    monkeypatch.chdir(ROOT)
    printed = cli("info", spec).stdout
    assert sym.load_scene(spec).info() == printed
    assert "lights" in printed and "environment" in printed
