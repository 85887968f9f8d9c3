"""Helpers of run.sh (the Blender round trip); /usr/bin/python3 with PYTHONPATH=build/release/python.

    roundtrip.py scenes DATA WORK         writes WORK/scenes/<label>.json: each export with the twin's camera
    roundtrip.py renders DATA WORK        lists the renders: label, scene, extra arguments (tab-separated)
    roundtrip.py masks DATA W H WORK      writes WORK/masks/<region>.png (255 inside, 0 outside), W x H
    roundtrip.py loaded DATA WORK         writes WORK/loaded.md: what symphong makes of each export today
    roundtrip.py table WORK               prints the table of WORK/compare/<label>.json (mean ratios per region)

Regions are the twin's objects (twin-regions.json) under each pixel centre (Scene.primary_hits on
twin.json), eroded by one pixel so that no pixel mixes two surfaces.
"""
import json
import os
import pathlib
import sys

import numpy as np

# Every export, in table order: (label, file, how it is rendered). "own": the file itself with its own
# camera; "twin camera": a JSON scene with the file as "mesh" (or "obj") and twin.json's camera.
# "seed 2": the twin itself with another seed, the noise of a comparison at this sample count.
RENDERS = [
    ("twin-seed2", "twin.json", "seed 2"),
    ("glb", "scene.glb", "own"),
    ("glb+twin-camera", "scene.glb", "twin camera"),
    ("gltf", "scene.gltf", "own"),
    ("gltf+twin-camera", "scene.gltf", "twin camera"),
    ("fbx", "scene.fbx", "own"),
    ("fbx+twin-camera", "scene.fbx", "twin camera"),
    ("dae", "scene.dae", "own"),
    ("dae+twin-camera", "scene.dae", "twin camera"),
    ("obj+twin-camera", "scene.obj", "twin camera"),
    ("ply+twin-camera", "scene.ply", "twin camera"),
]
REGION_ORDER = ["back", "floor", "ceiling", "left", "right", "glossy", "light", "checker", "checker-u0v0", "checker-u1v0",
                "checker-u0v1", "checker-u1v1"]


def scenes(data, work):
    """The JSON scenes of the "twin camera" renders. An export in other units (Blender's FBX is in
    centimetres: its nodes scale by 100) gets the twin's camera mapped by the scale and offset that take
    the twin's bounding box to the export's, so that it frames the same view."""
    import symphong

    data, work = pathlib.Path(data).resolve(), pathlib.Path(work).resolve()
    twin = json.load(open(data / "twin.json"))
    tlo, thi = (np.array(b) for b in symphong.load_scene(str(data / "twin.json")).bounds)
    (work / "scenes").mkdir(parents=True, exist_ok=True)
    for label, file, how in RENDERS:
        if how != "twin camera":
            continue
        camera = dict(twin["camera"])
        try:
            lo, hi = (np.array(b) for b in symphong.load_scene(str(data / file)).bounds)
            scale = float(np.max(hi - lo) / np.max(thi - tlo))
            offset = lo - scale * tlo
            if abs(scale - 1) > 1e-3 or np.max(np.abs(offset)) > 1e-3 * np.max(hi - lo):
                for key in ("position", "target"):
                    camera[key] = (scale * np.array(camera[key]) + offset).round(6).tolist()
                print(f"roundtrip: {label}: {file} is {scale:g} x the twin's size; the twin camera is scaled to match", file=sys.stderr)
        except Exception:  # noqa: BLE001 (the render then reports why the file does not load)
            pass
        key = "obj" if file.endswith(".obj") else "mesh"
        spec = {key: os.path.relpath(data / file, work / "scenes"), "name": label, "camera": camera}
        with open(work / "scenes" / f"{label}.json", "w") as f:
            json.dump(spec, f, indent=1)
            f.write("\n")


def renders(data, work):
    """One line per render for run.sh: label, scene file, extra render arguments (tab-separated)."""
    for label, file, how in RENDERS:
        scene = f"{work}/scenes/{label}.json" if how == "twin camera" else f"{data}/{file}"
        print(f"{label}\t{scene}\t{'--seed 2' if how == 'seed 2' else ''}")


def erode(mask):
    m = mask.copy()
    m[1:, :] &= mask[:-1, :]
    m[:-1, :] &= mask[1:, :]
    m[:, 1:] &= mask[:, :-1]
    m[:, :-1] &= mask[:, 1:]
    m[0, :] = m[-1, :] = m[:, 0] = m[:, -1] = False
    return m


def masks(data, width, height, work):
    import symphong
    from PIL import Image

    data, work = pathlib.Path(data), pathlib.Path(work)
    scene = symphong.load_scene(str(data / "twin.json"))
    hits = scene.primary_hits(int(width), int(height))
    regions = json.load(open(data / "twin-regions.json"))["regions"]
    out = work / "masks"
    out.mkdir(parents=True, exist_ok=True)
    for old in out.glob("*.png"):
        old.unlink()
    for name in REGION_ORDER + sorted(set(regions) - set(REGION_ORDER)):
        if name not in regions:
            continue
        m = erode(np.isin(hits, regions[name]))
        if m.sum() < 4:
            print(f"roundtrip: region {name}: {m.sum()} pixels after erosion; left out", file=sys.stderr)
            continue
        Image.fromarray((m * 255).astype(np.uint8), "L").save(out / f"{name}.png")
        print(f"{out / name}.png")


def loaded(data, work):
    """What symphong's loader makes of each export: counts, bounds, camera, materials, warnings."""
    import symphong

    data, work = pathlib.Path(data), pathlib.Path(work)
    lines = ["# What symphong makes of each export (symphong.load_scene)", ""]
    for file in ["twin.json", "scene.glb", "scene.gltf", "scene.fbx", "scene.dae", "scene.obj", "scene.ply"]:
        lines.append(f"## {file}")
        try:
            s = symphong.load_scene(str(data / file))
        except Exception as e:  # noqa: BLE001 (report whatever it is)
            lines += [f"load failed: {type(e).__name__}: {e}", ""]
            continue
        lo, hi = s.bounds
        lines.append(f"- triangles {s.triangle_count}, vertices {s.vertex_count}, bounds {np.round(lo, 4).tolist()} - "
                     f"{np.round(hi, 4).tolist()}")
        cam = s.camera
        lines.append("- camera: position {}, target {}, up {}, fov_y {:.4f}".format(
            *(np.round(cam[k], 4).tolist() for k in ("position", "target", "up")), cam["fov_y"]))
        for m in s.materials:
            lines.append("- material '{}': rho_d {}, rho_s {}, n {:g}, emission {}".format(
                m["name"], np.round(m["rho_d"], 4).tolist(), np.round(m["rho_s"], 4).tolist(), m["n"],
                np.round(m["emission"], 4).tolist()))
        for t in s.textures:
            lines.append(f"- texture {t}")
        for light in s.lights:
            lines.append(f"- light {light}")
        for w in s.warnings:
            lines.append(f"- warning: {w}")
        lines.append("")
    (work / "loaded.md").write_text("\n".join(lines))
    print("\n".join(lines))


def table(work):
    work = pathlib.Path(work)
    results = {}
    for label, _, _ in RENDERS:
        f = work / "compare" / f"{label}.json"
        if f.exists():
            results[label] = json.load(open(f))
        elif (work / "compare" / f"{label}.error").exists():
            results[label] = {"error": (work / "compare" / f"{label}.error").read_text().strip()}
    names = []
    for r in results.values():
        for reg in r.get("regions", []):
            name = pathlib.Path(reg["name"].rsplit("=", 1)[0]).stem
            if name not in names:
                names.append(name)
    labels = list(results)
    print("mean luminance ratio, export / OBJ twin (symphong compare --regions ... --json); twin-seed2: the twin with"
          " another seed (the comparison's noise)")
    print("| region | pixels | " + " | ".join(labels) + " |")
    print("|---|---:|" + "---:|" * len(labels))
    rows = ["image"] + names
    for row in rows:
        cells, pixels = [], ""
        for label in labels:
            r = results[label]
            if "error" in r:
                cells.append("error")
                continue
            if row == "image":
                reg = r["image"]
            else:
                reg = next((x for x in r["regions"] if pathlib.Path(x["name"].rsplit("=", 1)[0]).stem == row), None)
            if reg is None:
                cells.append("-")
                continue
            pixels = str(reg["pixels"])
            cells.append(f"{reg['mean_ratio']:.4f}")
        print(f"| {row} | {pixels} | " + " | ".join(cells) + " |")
    for label, r in results.items():
        if "error" in r:
            print(f"{label}: {r['error']}")


if __name__ == "__main__":
    cmd, args = sys.argv[1], sys.argv[2:]
    {"scenes": scenes, "renders": renders, "masks": masks, "loaded": loaded, "table": table}[cmd](*args)
