"""Renders one exported scene with Cycles once per seed in a single Blender process and times each render
(wall and this process's CPU time, which counts all of Cycles' threads). Runs inside Blender:

    blender -b --factory-startup -P cycles_timed.py -- SCENE.json OUT_DIR WIDTH HEIGHT SAMPLES SEEDS THREADS MODE TIMES.json

SEEDS is a comma-separated list; each render goes to OUT_DIR/cycles-<seed>.exr. MODE is `fixed` (the
settings of cycles_scene.py: every pixel gets SAMPLES samples) or `adaptive` (the same with Cycles'
adaptive sampling as Blender 3.4 ships it: noise threshold 0.01, minimum samples automatic, SAMPLES the
most a pixel gets). The scene is built once (cycles_scene.build); the first render's time includes
Cycles' first scene sync, as every later render's includes its own sync (Cycles rebuilds it per render
in background mode). TIMES.json gets, per seed, wall and CPU seconds of bpy.ops.render.render alone
(EXR writing included, scene building not), and the settings as Blender read them back."""
import json
import os
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cycles_scene  # noqa: E402


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    if len(args) != 9:
        sys.exit("usage: cycles_timed.py -- SCENE.json OUT_DIR WIDTH HEIGHT SAMPLES SEEDS THREADS MODE TIMES.json")
    desc_path, out_dir = args[0], args[1]
    width, height, samples = (int(a) for a in args[2:5])
    seeds = [int(s) for s in args[5].split(",")]
    threads, mode, times_path = int(args[6]), args[7], args[8]
    if mode not in ("fixed", "adaptive"):
        sys.exit(f"cycles_timed: MODE must be fixed or adaptive, not '{mode}'")
    d = json.load(open(desc_path))
    scene = cycles_scene.build(d)
    cycles_scene.configure(scene, width, height, samples, seeds[0], threads)
    cy = scene.cycles
    if mode == "adaptive":
        cy.use_adaptive_sampling = True
        cy.adaptive_threshold = 0.01
        cy.adaptive_min_samples = 0
    runs = []
    for seed in seeds:
        cy.seed = seed
        scene.render.filepath = os.path.join(out_dir, f"cycles-{seed}.exr")
        wall, cpu = time.perf_counter(), time.process_time()
        bpy.ops.render.render(write_still=True)
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        runs.append({"seed": seed, "wall_s": wall, "cpu_s": cpu})
        print(f"cycles_timed: seed {seed}: {wall:.3f} s wall, {cpu:.3f} s CPU", flush=True)
    settings = {"blender": bpy.app.version_string, "samples": cy.samples, "sampling_pattern": cy.sampling_pattern,
                "adaptive_sampling": cy.use_adaptive_sampling, "adaptive_threshold": cy.adaptive_threshold,
                "max_bounces": cy.max_bounces, "threads": scene.render.threads, "filter": cy.pixel_filter_type,
                "filter_width": cy.filter_width, "denoising": cy.use_denoising}
    with open(times_path, "w") as f:
        json.dump({"mode": mode, "settings": settings, "runs": runs}, f, indent=1)


main()
