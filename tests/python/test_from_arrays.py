"""Scene.from_arrays, principled_to_phong, render_settings and Progressive: what the Blender add-on
(blender/symphong_blender) builds its scenes and renders with.

The central check: a scene given as arrays renders bit for bit as the same scene written as an OBJ + MTL +
JSON file (normals, texture coordinates, an EXR texture given as a file and as an array, point, spot,
directional and quad lights, an environment map given as a file and as an array, the camera)."""
import pathlib

import numpy as np
import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]

# A floor (textured, smooth normals given per vertex), a glossy tilted quad and a back wall, in OBJ order.
POSITIONS = np.array([
    [-2, 0, -2], [2, 0, -2], [2, 0, 2], [-2, 0, 2],           # floor 0-3
    [-0.5, 0.2, 0], [0.5, 0.2, 0], [0.5, 1.0, -0.4], [-0.5, 1.0, -0.4],  # tilted quad 4-7
    [-2, 0, -2], [-2, 2, -2], [2, 2, -2], [2, 0, -2],         # back wall 8-11
])
UVS = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
NORMALS = np.array([[0, 1, 0], [0, 0, 1]], dtype=float)
# Triangles as OBJ faces: (vertex, uv, normal) per corner, 0-based; uv/normal -1 for none.
FACES = [
    ([0, 3, 2], [0, 3, 2], [0, 0, 0], 0), ([0, 2, 1], [0, 2, 1], [0, 0, 0], 0),
    ([4, 5, 6], [-1] * 3, [-1] * 3, 1), ([4, 6, 7], [-1] * 3, [-1] * 3, 1),
    ([8, 11, 10], [-1] * 3, [1, 1, 1], 2), ([8, 10, 9], [-1] * 3, [1, 1, 1], 2),
]
LIGHTS = [
    {"type": "point", "position": [0.5, 1.5, 1.0], "intensity": [3, 2.5, 2]},
    {"type": "spot", "position": [-1, 1.8, 1], "target": [0, 0, 0], "intensity": 6, "angle": 35, "inner": 20},
    {"type": "directional", "direction": [-0.3, -1, -0.2], "irradiance": 0.5},
    {"type": "quad", "corner": [-0.4, 1.9, -0.4], "edge1": [0.8, 0, 0], "edge2": [0, 0, 0.8], "radiance": 4},
]
CAMERA = {"position": [0, 1.2, 4], "target": [0, 0.5, 0], "up": [0, 1, 0], "fov": 45}
SETTINGS = dict(spp=8, width=48, height=40, seed=3)


def checker(n=8):
    """A float RGB texture whose texels differ in every channel, in half precision (the texture reader
    reads EXR through OpenEXR's half RGBA interface)."""
    y, x = np.mgrid[0:n, 0:n]
    return np.stack([0.2 + 0.6 * ((x + y) % 2), 0.1 + 0.05 * x, 0.3 + 0.04 * y], axis=2).astype(np.float16).astype(np.float32)


def sky(w=16, h=8):
    y, x = np.mgrid[0:h, 0:w]
    return np.stack([0.2 + 0.1 * x / w, 0.3 + 0.5 * (1 - y / h), 0.6 + 0.02 * x], axis=2).astype(np.float16).astype(np.float32)


@pytest.fixture
def files(sym, tmp_path):
    """The scene as files: scene.obj, scene.mtl, checker.exr, sky.exr, scene.json."""
    sym.write_image(str(tmp_path / "checker.exr"), checker())
    sym.write_image(str(tmp_path / "sky.exr"), sky())
    (tmp_path / "scene.mtl").write_text(
        "newmtl floor\nKd 0.8 0.8 0.8\nKs 0 0 0\nmap_Kd checker.exr\n"
        "newmtl glossy\nKd 0.3 0.2 0.1\nKs 0.4 0.4 0.4\nNs 80\n"
        "newmtl wall\nKd 0.5 0.6 0.7\nKs 0 0 0\nKe 0.1 0.1 0.1\n")
    lines = ["mtllib scene.mtl"]
    lines += [f"v {x} {y} {z}" for x, y, z in POSITIONS]
    lines += [f"vt {u} {v}" for u, v in UVS]
    lines += [f"vn {x} {y} {z}" for x, y, z in NORMALS]
    names = ["floor", "glossy", "wall"]
    current = None
    for v, t, n, m in FACES:
        if m != current:
            lines.append(f"usemtl {names[m]}")
            current = m
        corners = []
        for k in range(3):
            c = str(v[k] + 1)
            if t[k] >= 0 or n[k] >= 0:
                c += "/" + (str(t[k] + 1) if t[k] >= 0 else "")
            if n[k] >= 0:
                c += "/" + str(n[k] + 1)
            corners.append(c)
        lines.append("f " + " ".join(corners))
    (tmp_path / "scene.obj").write_text("\n".join(lines) + "\n")
    import json
    (tmp_path / "scene.json").write_text(json.dumps({
        "obj": "scene.obj", "name": "arrays", "camera": CAMERA, "lights": LIGHTS,
        "environment": {"map": "sky.exr", "scale": 0.5, "rotation": 30}}))
    return tmp_path


def f32(x):
    """A number as the OBJ reader (tinyobjloader, single precision) holds it."""
    return np.asarray(x, dtype=np.float32).astype(np.float64)


def arrays(texture, environment, materials=None):
    """from_arrays' arguments for the scene of `files` (corner attributes indexed per corner; the OBJ's numbers
    in single precision, as its reader holds them)."""
    tris = np.array([f[0] for f in FACES])
    uv_idx = np.array([[max(i, 0) for i in f[1]] for f in FACES])
    # Corners without a normal get a zero normal row (from_arrays then uses the triangle's own normal).
    normals = np.vstack([NORMALS, [[0, 0, 0]]])
    n_idx = np.array([[i if i >= 0 else 2 for i in f[2]] for f in FACES])
    mats = materials or [
        {"name": "floor", "rho_d": f32(0.8), "rho_s": 0, "diffuse_texture": texture},
        {"name": "glossy", "rho_d": f32((0.3, 0.2, 0.1)), "rho_s": f32(0.4), "n": 80},
        {"name": "wall", "rho_d": f32((0.5, 0.6, 0.7)), "rho_s": 0, "emission": f32(0.1)},
    ]
    return dict(positions=f32(POSITIONS), triangles=tris, material_ids=np.array([f[3] for f in FACES]),
                normals=normals, normal_indices=n_idx, uvs=UVS, uv_indices=uv_idx, materials=mats,
                lights=LIGHTS, camera=CAMERA, name="arrays",
                environment={"image": environment, "scale": 0.5, "rotation": 30})


def test_arrays_render_bit_for_bit_as_the_same_scene_from_files(sym, files):
    from_file = sym.load_scene(str(files / "scene.json"))
    expected, _ = sym.render(from_file, **SETTINGS)
    for texture, environment in [(str(files / "checker.exr"), str(files / "sky.exr")), (checker(), sky())]:
        kw = arrays(texture, environment)
        if isinstance(environment, str):
            kw["environment"] = {"map": environment, "scale": 0.5, "rotation": 30}
        scene = sym.Scene.from_arrays(**kw)
        assert scene.triangle_count == from_file.triangle_count
        assert scene.materials == from_file.materials
        assert scene.lights == from_file.lights
        assert scene.camera == from_file.camera
        image, _ = sym.render(scene, **SETTINGS)
        assert np.array_equal(image, expected), f"max difference {np.abs(image - expected).max()}"
    # The test can fail: another texel, or a light moved a little, changes the picture.
    changed = checker()
    changed[3, 4, 1] += 0.25
    image, _ = sym.render(sym.Scene.from_arrays(**arrays(changed, sky())), **SETTINGS)
    assert not np.array_equal(image, expected)


def test_per_vertex_attributes_need_no_index_arrays(sym):
    tris = np.array([[0, 1, 2], [0, 2, 3]])
    pos = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    nrm = np.tile([0.0, 0.0, 2.0], (4, 1))  # normalised by from_arrays
    a = sym.Scene.from_arrays(pos, tris, normals=nrm, uvs=pos[:, :2], environment=1.0, camera={"position": [0.5, 0.5, 2], "target": [0.5, 0.5, 0]})
    b = sym.Scene.from_arrays(pos, tris, normals=nrm, normal_indices=tris, uvs=pos[:, :2], uv_indices=tris, environment=1.0,
                              camera={"position": [0.5, 0.5, 2], "target": [0.5, 0.5, 0]})
    ia, _ = sym.render(a, spp=2, width=16, height=16)
    ib, _ = sym.render(b, spp=2, width=16, height=16)
    assert np.array_equal(ia, ib)
    assert a.materials[0]["rho_d"] == (0.7, 0.7, 0.7)  # an OBJ without MTL's default


@pytest.mark.parametrize("kwargs, message", [
    (dict(positions=[[0, 0, float("nan")], [1, 0, 0], [0, 1, 0]]), r"positions\[0, 2\] = nan is not finite"),
    (dict(triangles=[[0, 1, 3]]), r"triangles\[0, 2\] = 3 is out of range \(positions has 3\)"),
    (dict(triangles=[[0, 1, -1]]), r"triangles\[0, 2\] = -1 is out of range"),
    (dict(positions=[[0, 0], [1, 0], [0, 1]]), r"positions: expected an array of shape \(N, 3\), got shape \(3, 2\)"),
    (dict(material_ids=[1]), r"material_ids\[0\] = 1 is out of range \(materials has 1\)"),
    (dict(material_ids=[0, 0]), r"material_ids: 2 entries, but triangles has 1"),
    (dict(normals=[[0, 0, 1]] * 2), r"normals: 2 rows, but positions has 3"),
    (dict(normals=[[0, 0, 1]], normal_indices=[[0, 0, 1]]), r"normal_indices\[0, 2\] = 1 is out of range \(normals rows has 1\)"),
    (dict(uvs=[[0, 0]] * 3, uv_indices=[[0, 1, 2]] * 2), r"uv_indices: 2 rows, but triangles has 1"),
    (dict(tangents=[[1, 0, 0]] * 3), r"tangents: expected an array of shape \(N, 4\)"),
    (dict(materials=[{"rho_d": [0.5, -0.1, 0.2]}]), r"materials\[0\].rho_d\[1\] = -0.1 is negative"),
    (dict(materials=[{"kd": 0.5}]), r"materials\[0\]: unknown key 'kd'"),
    (dict(materials=[{"rho_d": 0.5, "roughness": 0.2}]), r"materials\[0\]: give either Phong keys"),
    (dict(materials=[{"diffuse_texture": np.full((2, 2, 3), np.inf, np.float32)}]), r"materials\[0\].diffuse_texture\[0, 0, 0\] = inf"),
    (dict(lights=[{"type": "spot", "position": [0, 1, 0], "direction": [0, -1, 0], "intensity": 1, "angle": 120}]),
     r"lights\[0\].angle = 120 must lie in \(0, 90\]"),
    (dict(lights=[{"type": "laser"}]), r"lights\[0\].type 'laser' is not a light type"),
    (dict(environment={"image": np.zeros((4, 8))}), None),
    (dict(environment={"image": -np.ones((4, 8, 3), np.float32)}), r"environment.image\[0, 0, 0\] = -1 is not a finite value >= 0"),
    (dict(camera={"position": [0, 0, 1], "target": [0, 0, 1]}), r"camera position and target coincide"),
    (dict(camera={"fov": 0}), r"camera fov 0 must lie in \(0, 180\)"),
])
def test_bad_arrays_raise_value_errors_naming_the_array_and_element(sym, kwargs, message):
    args = dict(positions=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles=[[0, 1, 2]], environment=1.0)
    args.update(kwargs)
    if message is None:  # a grey (H, W) environment is valid
        sym.Scene.from_arrays(**args)
        return
    with pytest.raises(ValueError, match=message):
        sym.Scene.from_arrays(**args)


def test_wrong_types_raise_type_errors(sym):
    with pytest.raises(TypeError, match="triangles: expected an array of integers, got dtype float64"):
        sym.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0.0, 1.0, 2.0]])
    with pytest.raises(TypeError):
        sym.Scene.from_arrays([["a", "b", "c"]], [[0, 0, 0]])


def test_missing_texture_file_is_a_warning_as_in_files(sym, tmp_path):
    scene = sym.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], environment=1.0,
                                  materials=[{"diffuse_texture": str(tmp_path / "gone.png")}])
    assert any("gone.png" in w for w in scene.warnings)


def test_principled_materials_map_as_the_gltf_reader_maps_blenders_export(sym):
    """tests/data/blender/scene.glb: Blender's glTF export of Principled materials (README there). The
    module's mapping, from_arrays' Principled keys and the glTF reader give the same Phong numbers."""
    glb = sym.load_scene(str(REPO / "tests" / "data" / "blender" / "scene.glb"))
    by_name = {m["name"]: m for m in glb.materials}
    principled = {  # Blender's numbers, tests/data/blender/README.md
        "white": ((0.725, 0.71, 0.68), 0.0, 0.0, 1.0),
        "glossy": ((0.75, 0.55, 0.25), 0.0, 0.5, 0.2),
    }
    for name, (base, metallic, specular, roughness) in principled.items():
        mapped = sym.principled_to_phong(base, metallic, specular, roughness)
        assert mapped["rho_d"] == pytest.approx(by_name[name]["rho_d"], rel=1e-6)
        assert mapped["rho_s"] == pytest.approx(by_name[name]["rho_s"], rel=1e-6, abs=1e-12)
        if max(mapped["rho_s"]) > 0:
            assert mapped["n"] == pytest.approx(by_name[name]["n"], rel=1e-6)
        scene = sym.Scene.from_arrays([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], environment=1.0, materials=[
            {"name": name, "base_color": base, "metallic": metallic, "specular": specular, "roughness": roughness}])
        m = scene.materials[0]
        assert (m["rho_d"], m["rho_s"], m["n"]) == (mapped["rho_d"], mapped["rho_s"], mapped["n"])
    # The glossy one: F0 = 0.08 x 0.5, rho_d = base (1 - F0), n = 2 / alpha^2 - 2 with alpha = 0.2^2.
    g = sym.principled_to_phong((0.75, 0.55, 0.25), 0.0, 0.5, 0.2)
    assert g["rho_s"] == pytest.approx((0.04,) * 3)
    assert g["rho_d"] == pytest.approx((0.72, 0.528, 0.24))
    assert g["n"] == pytest.approx(2 / 0.04 ** 2 - 2)


def test_uint8_colour_textures_are_srgb_decoded_and_data_maps_are_not(sym):
    """A uint8 colour map is decoded through the sRGB curve (as an 8-bit PNG is), a normal map is not; the
    picture of a flat-lit quad tells them apart."""
    pos = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    tris = np.array([[0, 1, 2], [0, 2, 3]])
    grey = np.full((2, 2, 3), 128, np.uint8)
    cam = {"position": [0.5, 0.5, 1], "target": [0.5, 0.5, 0], "fov": 30}

    def mean(texture):
        s = sym.Scene.from_arrays(pos, tris, uvs=pos[:, :2], environment=1.0, camera=cam,
                                  materials=[{"rho_d": 1.0, "diffuse_texture": texture}])
        return float(sym.render(s, spp=4, width=8, height=8, max_depth=1)[0].mean())

    srgb = ((128 / 255 + 0.055) / 1.055) ** 2.4
    assert mean(grey) == pytest.approx(srgb, rel=1e-4)
    assert mean({"image": grey, "srgb": False}) == pytest.approx(128 / 255, rel=1e-4)


def test_render_settings_are_the_schema_of_render(sym):
    settings = {s["name"]: s for s in sym.render_settings()}
    assert {"estimator", "sampler", "spp", "split", "symmetric_mode", "symmetric_orbit", "symmetric_n", "max_depth", "seed"} <= settings.keys()
    assert settings["spp"]["default"] == 64 and settings["spp"]["min"] == 1 and settings["spp"]["max"] == 1e6
    assert settings["estimator"]["choices"] == sym.estimators()
    assert settings["sampler"]["choices"] == sym.samplers()
    assert settings["symmetric_orbit"]["choices"] == [1, 2, 4, 8]
    assert settings["nee"]["default"] is True
    scene = sym.load_scene("cornell")
    for s in settings.values():  # each default is accepted as it stands; each range is render()'s own
        if s["name"] in {"time", "target_error", "target_region", "pass_spp", "checkpoint", "checkpoint_interval", "resume"}:
            continue
        sym.Progressive(scene, **{s["name"]: s["default"]})
        if s["type"] in {"int", "float"} and s["min"] is not None and s["min"] > -1e300:
            below = s["min"] - 1 if s["type"] == "int" else s["min"] - 0.5
            with pytest.raises(ValueError, match=s["name"]):
                sym.Progressive(scene, **{s["name"]: int(below) if s["type"] == "int" else below})


def test_progressive_passes_give_the_one_pass_image(sym):
    scene = sym.load_scene("cornell")
    kw = dict(spp=8, width=32, height=32, seed=5)
    p = sym.Progressive(scene, **kw)
    first = p.advance(1)
    assert p.samples_reached == 1 and first.shape == (32, 32, 3)
    p.advance(3)
    last = p.advance(100)  # at most the render's spp
    assert p.samples_reached == 8
    expected, _ = sym.render(scene, **kw)
    assert np.array_equal(last, expected)
    assert not np.array_equal(first, expected)
    assert p.stats()["spp_reached"] == 8
    with pytest.raises(ValueError, match="Progressive: time"):
        sym.Progressive(scene, time=10)


def test_progressive_passes_under_ears_give_the_one_pass_image(sym):
    """One path tracer serves every advance(); under --splitting ears it carries the learning from epoch to
    epoch and pass to pass (the probe, records on in all but the last epoch): passes that cut epochs in two
    still give the one-pass image bit for bit."""
    scene = sym.load_scene("cornell")
    kw = dict(spp=16, width=32, height=32, seed=3, splitting="ears")
    p = sym.Progressive(scene, **kw)
    for upTo in (1, 3, 5, 11, 100):
        last = p.advance(upTo)
    assert p.samples_reached == 16
    expected, _ = sym.render(scene, **kw)
    assert np.array_equal(last, expected)
    plain, _ = sym.render(scene, **dict(kw, splitting="none"))
    assert not np.array_equal(expected, plain)


def test_progressive_cancel_from_another_thread_stops_the_pass(sym):
    """What the Blender add-on does on Esc: cancel() from a watcher thread while advance() renders. A pass stops
    after the tiles in flight (16 x 16 pixels each): here 64 tiles of 2048 samples per pixel, about a minute
    on 2 cores, cancelled after half a second."""
    import threading
    import time
    p = sym.Progressive(sym.load_scene("cornell"), spp=2048, width=128, height=128, threads=2)
    threading.Timer(0.5, p.cancel).start()
    t = time.perf_counter()
    image = p.advance(2048)
    elapsed = time.perf_counter() - t
    assert p.samples_reached < 2048 and image.shape == (128, 128, 3)
    done = p.samples_done
    assert 0 < done < 128 * 128 * 2048 / 2, f"{done} samples taken before the pass stopped ({elapsed:.1f} s)"
    # The render goes on from where it stopped.
    p.advance(1)
    assert p.samples_reached >= 1
