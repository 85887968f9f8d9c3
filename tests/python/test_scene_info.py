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


def test_a_scenes_render_settings_are_the_flags_it_names(sym, cli, tmp_path):
    """A JSON scene's "render" object renders the image that the same settings as flags give, bit for bit,
    in the program and in the module; what the user gives wins."""
    scene = tmp_path / "s.json"
    scene.write_text('{"builtin": "cornell", "render": {"spp": 4, "width": 16, "height": 12, "estimator": "cosine", "max_depth": 3}}')
    cli("render", scene, "-o", tmp_path / "a.exr")
    cli("render", "-e", "cosine", "-s", 4, "-W", 16, "-H", 12, "-d", 3, "-o", tmp_path / "b.exr")
    assert (tmp_path / "a.exr").read_bytes() == (tmp_path / "b.exr").read_bytes()
    img, stats = sym.render(str(scene), progress=False)
    assert (stats["spp"], stats["width"], stats["height"], stats["estimator"]) == (4, 16, 12, "cosine")
    assert (img == sym.read_image(str(tmp_path / "a.exr"))).all()
    img, stats = sym.render(str(scene), spp=2, progress=False)
    assert stats["spp"] == 2
    out = cli("render", scene, "-s", 2, "-o", tmp_path / "c.exr").stdout
    assert "2 spp" in out
