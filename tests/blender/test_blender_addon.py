"""The Blender add-on (blender/symphong_blender) in Debian's Blender, headless: CTest runs this file with label
`blender` when `blender` is installed (tests/CMakeLists.txt). Scenes are made by blender/tests/make_scenes.py.

- the README's headless command line writes the frame, and it agrees region by region with the scene's glTF
  export rendered by `symphong render` (and the HDR-lit diffuse sphere with Cycles at equal spp);
- what cannot be mapped (a Toon BSDF, Transmission, a volume, hair) is reported and the frame is still written;
- the conversion's camera (sensor fits, portrait and landscape), materials and triangles equal what Blender's
  glTF exporter and symphong's glTF reader make of the same scene;
- the render panel's settings are the module's settings schema (names, defaults, ranges, choices).

Tolerances come from the renders' noise: a region's ratio must lie within 4 standard errors of 1 (the standard
error of the ratio from the paired difference image's pixel variance) plus a stated allowance for what differs
by construction (none against the export but float rounding; Cycles' own sampling bias, 3%, as the issue asks).
"""
import json
import os
import pathlib
import shutil
import subprocess
import sys

import numpy as np
import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "blender" / "tests"))
from regions import ratio, regions  # noqa: E402  (shared with scripts/blender-addon/agreement.py)
BLENDER = os.environ.get("SYMPHONG_BLENDER", shutil.which("blender") or "blender")
BUILD = pathlib.Path(os.environ.get("SYMPHONG_BUILD_DIR", REPO / "build" / "release"))
BINARY = os.environ.get("SYMPHONG_BINARY", str(BUILD / "symphong"))
SIZE, SPP = 64, 64


@pytest.fixture(scope="module")
def sym():
    import symphong
    return symphong


@pytest.fixture(scope="module")
def env(tmp_path_factory):
    """Blender's environment: BLENDER_USER_SCRIPTS with addons/symphong_blender (a link to the checkout's), the
    module on PYTHONPATH (read by Blender under --python-use-system-env)."""
    scripts = tmp_path_factory.mktemp("user_scripts")
    (scripts / "addons").mkdir()
    (scripts / "addons" / "symphong_blender").symlink_to(REPO / "blender" / "symphong_blender")
    e = dict(os.environ)
    e["BLENDER_USER_SCRIPTS"] = str(scripts)
    e["PYTHONPATH"] = str(BUILD / "python")
    return e


def blender(env, *args, timeout=600):
    p = subprocess.run([BLENDER, *map(str, args)], env=env, capture_output=True, text=True, timeout=timeout)
    assert p.returncode == 0, f"blender {' '.join(map(str, args))} failed ({p.returncode}):\n{p.stdout[-3000:]}\n{p.stderr[-3000:]}"
    return p.stdout + p.stderr


@pytest.fixture(scope="module")
def scenes(env, tmp_path_factory):
    out = tmp_path_factory.mktemp("scenes")

    def make(name, size=SIZE, spp=SPP):
        if not (out / f"{name}.blend").exists():
            blender(env, "-b", "--factory-startup", "--python-use-system-env", "--python", REPO / "blender" / "tests" / "make_scenes.py",
                    "--", out, name, size, size, spp)
        return out
    return make


def headless(env, directory, name, engine="SYMPHONG"):
    """The README's command: BLENDER_USER_SCRIPTS=... blender -b scene.blend --addons symphong_blender -E SYMPHONG
    -o //out/frame_ -F OPEN_EXR -f 1 (with --python-use-system-env: the module from PYTHONPATH)."""
    log = blender(env, "-b", directory / f"{name}.blend", "--python-use-system-env", "--addons", "symphong_blender", "-E", engine,
                  "-o", f"//out/{name}-{engine}_", "-F", "OPEN_EXR", "-f", "1")
    frame = directory / "out" / f"{name}-{engine}_0001.exr"
    assert frame.exists(), log
    return frame, log


@pytest.mark.parametrize("name", ["cornell-diffuse", "cornell-glossy", "textured"])
def test_headless_frame_agrees_with_the_gltf_export(sym, env, scenes, name):
    directory = scenes(name)
    frame, log = headless(env, directory, name)
    image = sym.read_image(str(frame))
    assert image.shape == (SIZE, SIZE, 3)
    exported = directory / f"{name}-file.exr"
    subprocess.run([BINARY, "render", directory / f"{name}.glb", "--spp", str(SPP), "--width", str(SIZE), "--height", str(SIZE),
                    "-o", exported], check=True, capture_output=True)
    reference = sym.read_image(str(exported))
    masks = regions(sym.load_scene(str(directory / f"{name}.glb")), SIZE, SIZE)
    assert len(masks) >= 3
    for region, mask in masks.items():
        r, se = ratio(image, reference, mask)
        assert abs(r - 1) <= 4 * se + 1e-3, f"{name}, region {region}: ratio {r:.4f} +- {se:.4f}"
    assert "not mapped" not in log and "not rendered" not in log, log


@pytest.mark.parametrize("name, exported", [("hdr", "hdr.json"), ("lights", "lights.glb")])
def test_diffuse_scenes_agree_with_cycles(sym, env, scenes, name, exported):
    """hdr: the environment texture's orientation (and the Mapping node's turn): a wrong one moves the sun patch
    and the sphere's lit side. lights: a point light, a sun and an area light (Cycles' power conventions; with
    the area light at P / (pi A) the walls were 27% too bright). Cycles with Diffuse BSDF (the twin) at the same
    spp; 3% allowed for what Cycles' sampling does differently (docs/validation.md), plus 4 standard errors."""
    directory = scenes(name)
    frame, _ = headless(env, directory, name)
    ours = sym.read_image(str(frame))
    cycles_frame, _ = headless(env, directory, f"{name}-cycles", engine="CYCLES")
    cycles = sym.read_image(str(cycles_frame))
    scene = sym.load_scene(str(directory / exported))
    masks = regions(scene, SIZE, SIZE)
    for region, mask in masks.items():  # quadrants included: the lit side must be the same side
        r, se = ratio(ours, cycles, mask)
        assert abs(r - 1) <= 0.03 + 4 * se, f"{name}, region {region}: symphong / Cycles {r:.4f} +- {se:.4f}"
    if name == "hdr":  # the environment as the camera sees it (pixels whose neighbours miss every surface too)
        miss = scene.primary_hits(SIZE, SIZE) < 0
        sky = miss.copy()
        for dy, dx in ((0, 1), (0, -1), (1, 0), (-1, 0)):
            sky &= np.roll(miss, (dy, dx), axis=(0, 1))
        assert sky.sum() > 100
        assert np.allclose(ours[sky].mean(axis=0), cycles[sky].mean(axis=0), rtol=0.02)


def test_unmappable_things_are_reported_and_the_frame_is_written(sym, env, scenes):
    directory = scenes("odd")
    frame, log = headless(env, directory, "odd")
    for words in ["toon", "ShaderNodeBsdfToon", "Transmission is not mapped", "volumes are not rendered", "hair system 'hair' is not rendered"]:
        assert words in log, f"{words!r} not reported:\n{log}"
    assert np.isfinite(sym.read_image(str(frame))).all()


def test_conversion_equals_the_gltf_exporter_and_reader(sym, env, scenes, tmp_path):
    """Cameras under each sensor fit, landscape and portrait; materials' Phong numbers; triangle counts."""
    directory = scenes("cornell-glossy")
    log = blender(env, "-b", directory / "cornell-glossy.blend", "--python-use-system-env", "--addons", "symphong_blender", "--python",
                  REPO / "tests" / "blender" / "inspect_conversion.py", "--", tmp_path)
    rows = [json.loads(line[len("INSPECT "):]) for line in log.splitlines() if line.startswith("INSPECT ")]
    assert len(rows) == 4, log
    fovs = set()
    for row in rows:
        built, read = row["camera"]
        for key in ("position", "target", "up"):
            assert built[key] == pytest.approx(read[key], abs=1e-5), row["variant"]
        assert built["fov_y"] == pytest.approx(read["fov_y"], rel=1e-5), row["variant"]
        fovs.add(round(built["fov_y"], 3))
        assert row["triangles"][0] == row["triangles"][1]
        assert np.ravel(row["bounds"][0]) == pytest.approx(np.ravel(row["bounds"][1]), abs=1e-5)
        by_name = {m["name"]: m for m in row["materials"][1]}
        for m in row["materials"][0]:
            g = by_name[m["name"]]
            for key in ("rho_d", "rho_s", "emission"):
                assert m[key] == pytest.approx(g[key], rel=1e-5, abs=1e-7), (m["name"], key)
            if max(m["rho_s"]) > 0:
                assert m["n"] == pytest.approx(g["n"], rel=1e-4), m["name"]
    assert len(fovs) == 4  # the four variants frame differently: the test sees the sensor fit


def test_panel_settings_are_the_module_schema(sym, env):
    code = ("import bpy, json; s = bpy.context.scene.symphong; props = {}\n"
            "for p in s.bl_rna.properties:\n"
            "    if p.identifier in {'rna_type', 'name'}: continue\n"
            "    d = {'type': p.type, 'default': getattr(p, 'default', None)}\n"
            "    if p.type in {'INT', 'FLOAT'}: d.update(min=p.hard_min, max=p.hard_max)\n"
            "    if p.type == 'ENUM': d.update(items=[i.identifier for i in p.enum_items], default=p.default)\n"
            "    props[p.identifier] = d\n"
            "print('PANEL ' + json.dumps(props))\n")
    log = blender(env, "-b", "--factory-startup", "--python-use-system-env", "--addons", "symphong_blender", "--python-expr", code)
    panel = json.loads(next(line for line in log.splitlines() if line.startswith("PANEL "))[6:])
    schema = {f["name"]: f for f in sym.render_settings()}
    own = {"width", "height", "time", "target_error", "target_region", "pass_spp", "checkpoint", "checkpoint_interval", "resume"}
    assert set(panel) == set(schema) - own
    for name, p in panel.items():
        f = schema[name]
        if f["choices"]:
            assert p["items"] == [str(c) for c in f["choices"]] and p["default"] == str(f["default"]), name
        elif f["type"] == "bool":
            assert p["type"] == "BOOLEAN" and p["default"] == f["default"], name
        elif f["type"] in {"int", "float"}:
            assert p["default"] == pytest.approx(f["default"]), name
            if f["min"] is not None:
                assert p["min"] == pytest.approx(f["min"]), name
            if f["max"] is not None:
                assert p["max"] == pytest.approx(min(f["max"], 2**31 - 1)), name
