#!/usr/bin/env python3
"""The agreement table of docs/blender.md: scenes made in Blender by script (blender/tests/make_scenes.py)
rendered through the add-on (the headless command line of the README) against the same scene exported with
Blender's glTF exporter and rendered by `symphong render`, and, where the Phong mapping is exact (diffuse),
against Cycles at equal spp; and the conversion time of a 1,000,000-triangle mesh (blender/tests/conversion_time.py).

    python3 scripts/blender-addon/agreement.py [--size 128] [--spp 256] [--out out/blender-agreement] [--no-write]

Writes the tables into docs/blender.md between its markers (unless --no-write) and prints them. Regions: the
pixels whose centre sees each material, eroded by a pixel, and each material's image quadrants
(blender/tests/regions.py); ratio of mean luminance with its standard error from the paired difference image.
Needs Debian's blender and the built module (build/release/python) and program (build/release/symphong).
"""
import argparse
import datetime
import os
import pathlib
import platform
import re
import shutil
import subprocess
import sys
import tempfile
import time

REPO = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO / "build" / "release" / "python"))
sys.path.insert(0, str(REPO / "blender" / "tests"))
import symphong  # noqa: E402
from regions import ratio, regions  # noqa: E402

SCENES = [  # name, the exported file symphong renders (None: not compared), whether Cycles is compared (diffuse: exact)
    ("cornell-diffuse", "cornell-diffuse.glb", True),
    ("cornell-glossy", "cornell-glossy.glb", False),
    ("textured", "textured.glb", False),
    ("hdr", "hdr.json", True),
    # Blender's glTF exporter writes lights in photometric units (point: W x 683 / (4 pi) candela, sun: W/m^2 x 683
    # lux), which symphong's glTF reader takes as radiometric: the light scenes are compared with Cycles only.
    ("lights", None, True),
    ("spot", None, True),
]


def blender(env, *args):
    p = subprocess.run(["blender", *map(str, args)], env=env, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"blender {' '.join(map(str, args))} failed:\n{p.stdout[-2000:]}\n{p.stderr[-2000:]}")
    return p.stdout


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=128)
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--out", default=str(REPO / "out" / "blender-agreement"))
    ap.add_argument("--no-write", action="store_true", help="print the tables, leave docs/blender.md alone")
    a = ap.parse_args()
    out = pathlib.Path(a.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    scripts = pathlib.Path(tempfile.mkdtemp(prefix="symphong-blender-"))
    (scripts / "addons").mkdir()
    (scripts / "addons" / "symphong_blender").symlink_to(REPO / "blender" / "symphong_blender")
    env = dict(os.environ, BLENDER_USER_SCRIPTS=str(scripts), PYTHONPATH=str(REPO / "build" / "release" / "python"))
    binary = REPO / "build" / "release" / "symphong"
    lines = []
    timings = []
    for name, exported, cycles in SCENES:
        blender(env, "-b", "--factory-startup", "--python-use-system-env", "--python", REPO / "blender" / "tests" / "make_scenes.py", "--",
                out, name, a.size, a.size, a.spp)
        t = time.perf_counter()
        log = blender(env, "-b", out / f"{name}.blend", "--python-use-system-env", "--addons", "symphong_blender", "-E", "SYMPHONG",
                      "-o", f"//frames/{name}-addon_", "-F", "OPEN_EXR", "-f", "1")
        addon_seconds = time.perf_counter() - t
        addon = symphong.read_image(str(out / "frames" / f"{name}-addon_0001.exr"))
        t = time.perf_counter()
        file = None
        if exported is not None:
            subprocess.run([binary, "render", out / exported, "--spp", str(a.spp), "--width", str(a.size), "--height", str(a.size), "-o",
                            out / "frames" / f"{name}-file.exr"], check=True, capture_output=True)
            file = symphong.read_image(str(out / "frames" / f"{name}-file.exr"))
        file_seconds = time.perf_counter() - t
        ref = None
        if cycles:
            t = time.perf_counter()
            blender(env, "-b", out / f"{name}-cycles.blend", "-E", "CYCLES", "-o", f"//frames/{name}-cycles_", "-F", "OPEN_EXR", "-f", "1")
            cycles_seconds = time.perf_counter() - t
            ref = symphong.read_image(str(out / "frames" / f"{name}-cycles_0001.exr"))
        scene = symphong.load_scene(str(out / (exported or f"{name}.glb")))  # the glTF's geometry and camera: the regions
        masks = regions(scene, a.size, a.size)
        timings.append(f"{name}: add-on {addon_seconds:.1f} s (Blender's start included)"
                       + (f", `symphong render` {file_seconds:.1f} s" if file is not None else "")
                       + (f", Cycles {cycles_seconds:.1f} s" if cycles else ""))
        against = ([f"`{exported}`"] if file is not None else []) + (["Cycles with Diffuse BSDF"] if cycles else [])
        lines.append(f"\n**{name}** (against {' and '.join(against)}):\n")
        lines.append("| region | pixels | " + ("add-on / file | " if file is not None else "") + ("add-on / Cycles | " if cycles else "") + "|")
        lines.append("|---|---:|" + ("---:|" if file is not None else "") + ("---:|" if cycles else "") + "---|")
        for region, mask in masks.items():
            cells, flag = [region, str(int(mask.sum()))], False
            if file is not None:
                r, se = ratio(addon, file, mask)
                cells.append(f"{r:.4f} ± {se:.4f}")
                flag = abs(r - 1) > 0.02
            if cycles:
                rc, sec = ratio(addon, ref, mask)
                cells.append(f"{rc:.4f} ± {sec:.4f}")
                flag = flag or abs(rc - 1) > 0.03
            lines.append("| " + " | ".join(cells) + " | " + ("**outside**" if flag else "") + " |")
        reports = [l for l in log.splitlines() if "symphong:" in l and ("not" in l or "rendered as" in l)]
        if reports:
            lines.append("\nReported: " + "; ".join(r.split("symphong: ", 1)[1] for r in reports))
    t = subprocess.run(["blender", "-b", "--factory-startup", "--python-use-system-env", "--addons", "symphong_blender", "--python",
                        REPO / "blender" / "tests" / "conversion_time.py", "--", "5"], env=env, capture_output=True, text=True)
    conversion = [l[len("CONVERSION "):] for l in t.stdout.splitlines() if l.startswith("CONVERSION ")]
    load = os.getloadavg()
    header = (f"Command: `python3 scripts/blender-addon/agreement.py --size {a.size} --spp {a.spp}`; {datetime.date.today()}, "
              f"Blender {blender(env, '--version').splitlines()[0].split()[1]}, symphong {symphong.__version__}, "
              f"{os.cpu_count()} cores ({platform.processor() or platform.machine()}), load average {load[0]:.1f} at the end. "
              f"{a.size} x {a.size}, {a.spp} spp everywhere, seed 1 (add-on and file: the same seed, but the triangles come in "
              f"another order, so the noise differs). Ratios of mean luminance ± standard error; **outside** marks a region "
              f"beyond 2% (file) or 3% (Cycles).")
    text = "\n".join([header, *lines, "", "Times: " + "; ".join(timings) + ".", "",
                      "Conversion of a 1,000,000-triangle mesh (`blender/tests/conversion_time.py`, 5 repeats):", "", "```",
                      *conversion, "```"])
    print(text)
    if not a.no_write:
        doc = REPO / "docs" / "blender.md"
        body = doc.read_text()
        new = re.sub(r"(<!-- agreement:begin -->\n).*?(\n<!-- agreement:end -->)", lambda m: m.group(1) + text + m.group(2), body, flags=re.S)
        doc.write_text(new)
    shutil.rmtree(scripts)


if __name__ == "__main__":
    main()
