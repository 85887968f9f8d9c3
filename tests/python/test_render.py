"""render(): shapes, dtype, bit-identity with the command line's EXR, stats, variance."""
import pathlib

import numpy as np
import pytest

from conftest import REPO


def test_shape_and_dtype(sym):
    img, stats = sym.render(sym.load_scene("cornell"), spp=4, width=64, height=48)
    assert img.shape == (48, 64, 3)
    assert img.dtype == np.float32
    assert img.flags.c_contiguous and img.flags.writeable
    assert np.isfinite(img).all() and (img >= 0).all()
    assert img.mean() > 0.01


def test_stats(sym):
    _, stats = sym.render("cornell", spp=3, width=20, height=10, seed=9, estimator="cosine", sampler="independent")
    assert stats["samples"] == 20 * 10 * 3
    assert stats["rays"] >= stats["samples"]
    assert stats["bad_samples"] == 0
    assert stats["seconds"] > 0
    assert stats["mrays_per_second"] == pytest.approx(stats["rays"] / stats["seconds"] / 1e6)
    assert stats["samples_per_second"] == pytest.approx(stats["samples"] / stats["seconds"])
    assert (stats["estimator"], stats["sampler"], stats["spp"], stats["width"], stats["height"], stats["seed"]) == (
        "cosine", "independent", 3, 20, 10, 9)


def test_default_splitting_is_reported_and_is_the_command_lines(sym, cli, tmp_path):
    """splitting="auto" (the default) learns EARS factors from 64 spp on, as `symphong render` does; stats
    name the splitting used."""
    out = tmp_path / "cli.exr"
    cli("render", "cornell", "--spp", 64, "-W", 21, "-H", 13, "--seed", 3, "-o", out)
    img, stats = sym.render("cornell", spp=64, width=21, height=13, seed=3)
    assert stats["splitting"] == "ears"
    assert img.tobytes() == sym.read_image(str(out)).tobytes()
    ears, _ = sym.render("cornell", spp=64, width=21, height=13, seed=3, splitting="ears")
    plain, plain_stats = sym.render("cornell", spp=64, width=21, height=13, seed=3, splitting="none")
    assert img.tobytes() == ears.tobytes() and img.tobytes() != plain.tobytes()
    assert plain_stats["splitting"] == "none"
    assert sym.render("cornell", spp=63, width=21, height=13)[1]["splitting"] == "none"
    assert sym.render("cornell", spp=64, width=21, height=13, split=2)[1]["splitting"] == "none"
    p = sym.Progressive("cornell", spp=64, width=21, height=13)
    assert p.stats()["splitting"] == "ears"


@pytest.mark.parametrize("estimator,sampler,extra", [
    ("phong", "independent", []),
    ("phong", "sobol", []),
    ("symmetric", "sobol", ["--symmetric-mode", "spread", "--symmetric-n", "2"]),
    ("cosine", "independent", ["--no-nee", "--max-depth", "3"]),
    ("symmetric-mix", "sobol", ["--symmetric-mode", "spread", "--symmetric-orbit", "8", "--split", "2"]),
    ("phong", "sobol", ["--joint-first-bounce", "--first-bounce-stream", "3"]),
])
def test_bit_identical_to_cli_exr(sym, cli, tmp_path, estimator, sampler, extra):
    out = tmp_path / "cli.exr"
    cli("render", "cornell", "-e", estimator, "--sampler", sampler, "--spp", 5, "-W", 37, "-H", 23, "--seed", 11, "-o", out, *extra)
    ref = sym.read_image(str(out))
    kwargs = dict(estimator=estimator, sampler=sampler, spp=5, width=37, height=23, seed=11)
    if "--symmetric-n" in extra:
        kwargs.update(symmetric_mode="spread", symmetric_n=2)
    if "--symmetric-orbit" in extra:
        kwargs.update(symmetric_mode="spread", symmetric_orbit=8, split=2)
    if "--joint-first-bounce" in extra:
        kwargs.update(joint_first_bounce=True, first_bounce_stream=3)
    if "--no-nee" in extra:
        kwargs.update(nee=False, max_depth=3)
    for threads in (1, 2, 0):
        img, _ = sym.render("cornell", threads=threads, **kwargs)
        assert img.tobytes() == ref.tobytes(), f"threads={threads}"


def test_obj_scene_matches_cli(sym, cli, tmp_path, shared_scenes):
    obj = shared_scenes / "cornell-box-mcguire" / "CornellBox-Glossy.obj"
    out = tmp_path / "glossy.exr"
    cli("render", obj, "--spp", 2, "-W", 24, "-H", 24, "-o", out)
    img, _ = sym.render(sym.load_scene(str(obj)), spp=2, width=24, height=24)
    assert img.tobytes() == sym.read_image(str(out)).tobytes()


def test_seeds_differ_and_repeat(sym):
    scene = sym.load_scene("cornell")
    a, _ = sym.render(scene, spp=2, width=16, height=16, seed=1)
    b, _ = sym.render(scene, spp=2, width=16, height=16, seed=2)
    c, _ = sym.render(scene, spp=2, width=16, height=16, seed=1)
    assert not np.array_equal(a, b)
    assert np.array_equal(a, c)


def test_variance_matches_spread_between_seeds(sym):
    """The returned per-pixel variance of the mean agrees with the spread of two independent renders:
    E[(a - b)^2 / 2] = Var(mean). Pixel means of both compared within 4 standard errors."""
    scene = sym.load_scene("cornell")
    kw = dict(spp=8, width=48, height=48, estimator="cosine", sampler="independent")
    a, _, va = sym.render(scene, seed=1, variance=True, **kw)
    b, _, vb = sym.render(scene, seed=2, variance=True, **kw)
    assert va.shape == a.shape and va.dtype == np.float32 and (va >= 0).all()
    half_sq = ((a.astype(np.float64) - b) ** 2 / 2).ravel()
    predicted = ((va.astype(np.float64) + vb) / 2).ravel()
    diff = half_sq - predicted
    se = diff.std(ddof=1) / np.sqrt(diff.size)
    assert abs(diff.mean()) < 4 * se, (half_sq.mean(), predicted.mean(), se)
    assert predicted.mean() > 0


def test_scene_is_reused_and_not_consumed(sym):
    scene = sym.load_scene("cornell")
    for _ in range(3):
        img, _ = sym.render(scene, spp=1, width=8, height=8)
    assert img.shape == (8, 8, 3)
    assert scene.triangle_count == 32


def test_scene_attributes(sym, shared_scenes):
    scene = sym.load_scene("cornell")
    assert scene.name == "cornell" and scene.spec == "cornell"
    assert scene.triangle_count == 32
    names = [m["name"] for m in scene.materials]
    assert "light" in names and "red" in names
    light = scene.materials[names.index("light")]
    assert max(light["emission"]) > 0 and scene.has_emitter
    assert set(scene.camera) == {"position", "target", "up", "fov_y"}
    lo, hi = scene.bounds
    assert all(l < h for l, h in zip(lo, hi))
    assert "32 triangles" in repr(scene)
    bunny = sym.Scene(str(shared_scenes / "bunny" / "stanford-bunny.obj"))
    assert bunny.triangle_count > 1000
    assert bunny.sky is not None and scene.sky is None, "a bare model gets the default sky"
    assert [l["type"] for l in bunny.lights] == ["directional"] and bunny.lights[0]["direction"][1] < 0, "and its sun"
    assert any("default sky" in w for w in bunny.warnings), bunny.warnings
    assert scene.environment_map is None and scene.textures == []


def test_textures_and_environment_map(sym):
    scene = sym.load_scene(str(REPO / "scenes" / "textured.json"))
    env = scene.environment_map
    assert env is not None and env["file"].endswith("sky.hdr") and (env["width"], env["height"]) == (512, 256)
    assert env["filter"] == "bilinear" and env["scale"] == 1.0
    files = sorted(pathlib.Path(t["file"]).name for t in scene.textures)
    assert files == ["checker.png", "globe.png", "holes.png", "planks-gloss.png", "planks.png"], files
    assert all(t["wrap"] == ("repeat", "repeat") for t in scene.textures)


def test_names(sym):
    assert "symmetric" in sym.estimators() and "phong" in sym.estimators()
    assert "sobol" in sym.samplers() and "independent" in sym.samplers()
    assert "constant" in sym.environments()


def test_help_documents_every_estimator(sym):
    doc = sym.render.__doc__
    for name in sym.estimators():
        assert name in doc
    for name in sym.samplers():
        assert name in doc
    for f in (sym.load_scene, sym.furnace, sym.study, sym.write_image, sym.read_image, sym.Scene):
        assert f.__doc__ and len(f.__doc__) > 80, f


def test_write_image_roundtrip(sym, tmp_path):
    rng = np.random.default_rng(3)
    img = rng.random((5, 7, 3)).astype(np.float32)
    sym.write_image(str(tmp_path / "x.exr"), img)
    assert np.array_equal(sym.read_image(str(tmp_path / "x.exr")), img)
    grey = rng.random((4, 6))
    sym.write_image(str(tmp_path / "g.exr"), grey)
    back = sym.read_image(str(tmp_path / "g.exr"))
    assert np.array_equal(back[..., 1], grey.astype(np.float32))
    sym.write_image(str(tmp_path / "x.png"), img, exposure=2.0)
    assert (tmp_path / "x.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    sym.write_image(str(tmp_path / "h.exr"), img, exr_half=True)
    assert np.allclose(sym.read_image(str(tmp_path / "h.exr")), img, rtol=1e-3)


def test_mesh_is_the_geometry_rendered(sym):
    scene = sym.load_scene(str(REPO / "scenes" / "cornell-classic.json"))
    mesh = scene.mesh()
    assert mesh["positions"].shape == (scene.vertex_count, 3)
    assert mesh["triangles"].shape == (scene.triangle_count, 3)
    assert mesh["material"].shape == (scene.triangle_count,)
    assert mesh["triangles"].max() < scene.vertex_count
    names = [m["name"] for m in scene.materials]
    light = [i for i, m in enumerate(mesh["material"]) if names[m] == "light"]
    assert len(light) == 2
    for t in light:  # the light faces down: its front face is counter-clockwise seen from below
        a, b, c = (mesh["positions"][i] for i in mesh["triangles"][t])
        normal = np.cross(b - a, c - a)
        assert normal[1] < 0 and abs(normal[0]) < 1e-9 and abs(normal[2]) < 1e-9
        assert a[1] == b[1] == c[1] == 554


def test_primary_hits_name_the_surface_under_each_pixel(sym):
    scene = sym.load_scene(str(REPO / "scenes" / "cornell-classic.json"))
    mesh = scene.mesh()
    hits = scene.primary_hits(48, 48)
    assert hits.shape == (48, 48) and hits.dtype == np.int64
    z = lambda t: mesh["positions"][mesh["triangles"][t]][:, 2]  # noqa: E731
    assert (z(hits[14, 24]) == 555).all(), "above the blocks, the middle column sees the back wall"
    names = [m["name"] for m in scene.materials]
    assert names[mesh["material"][hits[24, 1]]] == "red" and names[mesh["material"][hits[24, 46]]] == "green"
    assert (hits[1:-1, 1:-1] >= 0).all(), "inside its border, the image sees only the inside of the box"
    assert (hits[:, 0] == -1).all(), "the outermost columns look past the open front: misses are -1"
    assert (sym.load_scene("cornell").primary_hits(4, 4) >= 0).all()
    with pytest.raises(ValueError, match="width"):
        scene.primary_hits(0, 4)
