"""Every error type and message: loading errors carry the command line's message; bad keyword
arguments raise ValueError naming the argument; nothing is written on failure."""
import numpy as np
import pytest

from conftest import cli_error


def test_missing_scene_is_file_not_found_with_cli_message(sym, cli, tmp_path):
    missing = tmp_path / "nowhere.obj"
    with pytest.raises(FileNotFoundError) as e:
        sym.load_scene(str(missing))
    assert str(e.value) == cli_error(cli("render", missing, "-o", tmp_path / "x.png", check=False))
    assert not (tmp_path / "x.png").exists()


def test_json_naming_a_missing_obj_is_file_not_found(sym, cli, tmp_path):
    scene = tmp_path / "s.json"
    scene.write_text('{"obj": "gone.obj"}\n')
    with pytest.raises(FileNotFoundError) as e:
        sym.load_scene(str(scene))
    assert str(e.value) == cli_error(cli("render", scene, check=False))
    assert "gone.obj" in str(e.value)


@pytest.mark.parametrize("name,text", [
    ("syntax.json", '{\n  "builtin": "cornell",\n  "camera": {"fov": 40,}\n}\n'),
    ("unknown-key.json", '{"builtin": "cornell", "lamps": []}\n'),
    ("bad-value.json", '{"builtin": "cornell", "materials": {"red": {"kd": [1, -1, 0]}}}\n'),
    ("face.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"),
    ("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"),
    ("scene.txt", "hello\n"),
])
def test_bad_scene_is_value_error_with_cli_message(sym, cli, tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(ValueError) as e:
        sym.load_scene(str(path))
    assert str(e.value) == cli_error(cli("render", path, "-o", tmp_path / "x.png", check=False))
    assert str(path) in str(e.value)


def test_malformed_shared_scenes(sym, cli, shared_scenes):
    for obj in sorted((shared_scenes / "malformed").glob("*.obj")):
        with pytest.raises(ValueError) as e:
            sym.load_scene(str(obj))
        assert str(e.value) == cli_error(cli("render", obj, check=False)), obj


@pytest.mark.parametrize("kwargs,message", [
    (dict(spp=0), "spp = 0 must lie in [1, 1000000]"),
    (dict(width=0), "width = 0 must lie in [1, 16384]"),
    (dict(height=20000), "height = 20000 must lie in [1, 16384]"),
    (dict(width=16384, height=16384), "image size 16384x16384 is too large"),
    (dict(max_depth=-1), "max_depth = -1 must lie in [0, 1024]"),
    (dict(threads=-2), "threads = -2 must lie in [0, 4096]"),
    (dict(seed=-1), "seed = -1 must lie in [0, 2**64 - 1]"),
    (dict(seed=2 ** 64), "seed = 18446744073709551616 must lie in [0, 2**64 - 1]"),
    (dict(estimator="nope"), "estimator: unknown estimator 'nope'"),
    (dict(sampler="halton"), "sampler: unknown sampler 'halton'"),
    (dict(symmetric_mode="sideways"), "symmetric_mode:"),
    (dict(symmetric_n=0), "symmetric_n = 0 must lie in [1, 4096]"),
    (dict(symmetric_orbit=3), "symmetric_orbit: 3 is not one of 1, 2, 4, 8"),
    (dict(split=0), "split = 0 must lie in [1, 64]"),
    (dict(first_bounce_stream=-1), "first_bounce_stream = -1 must lie in [0, 1000000]"),
])
def test_bad_render_arguments_are_value_errors(sym, kwargs, message):
    with pytest.raises(ValueError) as e:
        sym.render("cornell", **kwargs)
    assert str(e.value).startswith(message), str(e.value)


def test_largest_seed_is_accepted(sym):
    img, stats = sym.render("cornell", spp=1, width=4, height=4, seed=2 ** 64 - 1)
    assert stats["seed"] == 2 ** 64 - 1


def test_wrong_types_are_type_errors(sym):
    with pytest.raises(TypeError):
        sym.render("cornell", spp="many")
    with pytest.raises(TypeError):
        sym.render(42)
    with pytest.raises(TypeError):
        sym.render("cornell", 4)  # options are keyword-only
    with pytest.raises(TypeError):
        sym.furnace(n="ten")


def test_scene_spec_string_errors_like_load_scene(sym, tmp_path):
    with pytest.raises(FileNotFoundError):
        sym.render(str(tmp_path / "none.json"))


def test_write_image_errors(sym, tmp_path):
    img = np.zeros((4, 4, 3), np.float32)
    with pytest.raises(ValueError, match=r"\.tiff"):
        sym.write_image(str(tmp_path / "x.tiff"), img)
    with pytest.raises(ValueError, match=r"shape must be \(H, W, 3\) or \(H, W\), got \(4, 4, 4\)"):
        sym.write_image(str(tmp_path / "x.exr"), np.zeros((4, 4, 4)))
    bad = img.copy()
    bad[2, 3, 1] = np.nan
    with pytest.raises(ValueError, match=r"pixel \(x 3, y 2\) has the non-finite value nan"):
        sym.write_image(str(tmp_path / "x.exr"), bad)
    with pytest.raises(ValueError, match="exposure"):
        sym.write_image(str(tmp_path / "x.png"), img, exposure=0)
    with pytest.raises(ValueError, match="no pixels"):
        sym.write_image(str(tmp_path / "x.exr"), np.zeros((0, 4, 3)))
    assert list(tmp_path.iterdir()) == []  # nothing written, not even a temporary file
    (tmp_path / "file").write_text("a file, not a directory")
    with pytest.raises(ValueError, match="file/x.exr"):
        sym.write_image(str(tmp_path / "file" / "x.exr"), img)


def test_read_image_errors(sym, tmp_path):
    with pytest.raises(FileNotFoundError, match="no such file"):
        sym.read_image(str(tmp_path / "none.exr"))
    (tmp_path / "junk.exr").write_bytes(b"not an exr")
    with pytest.raises(ValueError, match="junk.exr"):
        sym.read_image(str(tmp_path / "junk.exr"))


def test_furnace_errors(sym):
    with pytest.raises(ValueError, match="estimator: unknown estimator 'nope'"):
        sym.furnace(estimators="cosine,nope", repeats=10)
    with pytest.raises(ValueError, match="environment: unknown environment 'moon'"):
        sym.furnace(environments=["moon"], repeats=10)
    with pytest.raises(ValueError, match=r"rho_d = 1.5 must lie in \[0, 1\]"):
        sym.furnace(rho_d=1.5, repeats=10)
    with pytest.raises(ValueError, match=r"theta = 90 must lie in \[0, 90\)"):
        sym.furnace(theta=[30, 90], repeats=10)
    with pytest.raises(ValueError, match=r"repeats = 1 must lie in \[2, 100000000\]"):
        sym.furnace(repeats=1)
    with pytest.raises(ValueError, match="sampler: unknown sampler 'x'"):
        sym.furnace(sampler="x", repeats=10)


def test_study_errors(sym, tmp_path):
    with pytest.raises(ValueError, match=r"spp = 0 must lie in"):
        sym.study(spp=[0], out=str(tmp_path / "s"))
    with pytest.raises(ValueError, match="--estimators: unknown estimator 'nope'"):
        sym.study(estimators="nope", out=str(tmp_path / "s"))
    with pytest.raises(FileNotFoundError):
        sym.study(str(tmp_path / "none.obj"), out=str(tmp_path / "s"), plots=False)
    with pytest.raises(ValueError, match="symmetric_modes"):
        sym.study(symmetric_modes="up", out=str(tmp_path / "s"))
