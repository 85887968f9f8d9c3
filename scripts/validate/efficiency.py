"""Efficiency of symphong against Blender Cycles on the same diffuse scenes, at equal time: each
renderer renders the scene K times with K seeds; the mean over pixels of the per-pixel variance across
seeds is the MSE of one render (both renderers are unbiased here: docs/validation.md shows them within
0.6%, a bias whose square is 1e-3 of these variances); its cost is the render's CPU time (all threads),
as the study measures cost. Efficiency = 1 / (MSE x CPU seconds). Cycles gets the sample count that
makes its render take as long as symphong's plain `phong` render (one calibration render first), so
the MSEs are equal-time MSEs; the efficiency ratio also corrects for what is left of the difference.

    python3 scripts/validate/efficiency.py                 # 256x256, 64 spp, 8 seeds, two scenes; ~10 minutes on 2 cores
    python3 scripts/validate/efficiency.py --quick         # 64x64, 16 spp, 4 seeds: checks the pipeline
    python3 scripts/validate/efficiency.py --write-doc     # also writes the table into docs/performance.md
    python3 scripts/validate/efficiency.py --no-cycles --scenes cornell --size 512   # symphong's variants alone

Runs with Debian's python3 and NumPy; builds symphong (release preset) if needed; Blender from Debian
(`apt-get install blender`). Renders and times.json files go to out/efficiency/<scene>/.

symphong: `symphong render SCENE -W -H --spp --seed --max-depth 64 -t THREADS --splitting none` (`phong`,
`sobol`, NEE with MIS, one path a camera sample), and the same with `--splitting ears` (what the default,
`--splitting auto`, renders at these sample counts); timed from outside (fork to exit, so its
start-up and scene loading count). Cycles (cycles_timed.py): the settings of docs/validation.md
(CPU, no denoising, 64 bounces, no clamping, box pixel filter 1 px: the image symphong renders) with
its default sampling pattern, adaptive sampling off (`fixed`) and on (`adaptive`, Blender's default
threshold 0.01); timed inside Blender around each render call (its start-up not counted).

Uncertainty: the MSE's standard error by the jackknife over seeds, the time's from its spread over the
K renders; the ratio's interval is +-2 standard errors of its logarithm (delta method)."""
import argparse
import json
import math
import os
import pathlib
import platform
import resource
import subprocess
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENES = {
    "cornell-diffuse": "scenes/cornell-diffuse.json",
    "cornell-classic": "scenes/cornell-classic.json",
    "cornell": "cornell",  # the default scene (a glossy block: symphong only, with --no-cycles)
}
CYCLES_SCENES = ["cornell-diffuse", "cornell-classic"]  # all diffuse: the ones Cycles renders as symphong does
BEGIN, END = "<!-- efficiency-vs-cycles:begin -->", "<!-- efficiency-vs-cycles:end -->"


def run_timed(cmd):
    """Runs cmd; returns (wall seconds, CPU seconds of the child: user + system)."""
    wall = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - wall
    err = proc.stderr.read()
    proc.stderr.close()
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"efficiency: {' '.join(cmd)} failed:\n{err}")
    return wall, usage.ru_utime + usage.ru_stime


def read_images(paths):
    import symphong
    return np.stack([symphong.read_image(str(p)).astype(np.float64)[..., :3] for p in paths])


def mse_with_error(images):
    """Mean over pixels and channels of the per-pixel variance across the K renders, and its jackknife
    standard error over renders."""
    k = images.shape[0]
    full = images.var(axis=0, ddof=1).mean()
    total, total_sq = images.sum(axis=0), (images ** 2).sum(axis=0)
    loo = []
    for i in range(k):
        s, s2 = total - images[i], total_sq - images[i] ** 2
        loo.append(((s2 - s * s / (k - 1)) / (k - 2)).mean())
    loo = np.array(loo)
    se = math.sqrt((k - 1) / k * ((loo - loo.mean()) ** 2).sum())
    return float(full), se


def summarise(name, images, cpu, wall, extra):
    mse, mse_se = mse_with_error(images)
    cpu, wall = np.array(cpu), np.array(wall)
    t, t_se = float(cpu.mean()), float(cpu.std(ddof=1) / math.sqrt(len(cpu)))
    eff = 1.0 / (mse * t)
    log_se = math.hypot(mse_se / mse, t_se / t)
    return {"name": name, "mse": mse, "mse_se": mse_se, "cpu_s": t, "cpu_se": t_se, "wall_s": float(wall.mean()),
            "efficiency": eff, "log_se": log_se, "mean": float(images.mean()), **extra}


def symphong_runs(spec, d, size, spp, seeds, threads, extra_args, tag):
    cpu, wall, paths = [], [], []
    for seed in seeds:
        out = d / f"{tag}-{seed}.exr"
        cmd = [str(ROOT / "build/release/symphong"), "render", spec, "-W", str(size), "-H", str(size), "--spp", str(spp),
               "--seed", str(seed), "--max-depth", "64", "-t", str(threads), "-o", str(out)] + extra_args
        w, c = run_timed(cmd)
        print(f"efficiency: {d.name}: symphong {tag} seed {seed}: {w:.2f} s wall, {c:.2f} s CPU", flush=True)
        cpu.append(c), wall.append(w), paths.append(out)
    return read_images(paths), cpu, wall


def cycles_runs(d, size, samples, seeds, threads, mode, tag):
    times = d / f"{tag}-times.json"
    sub = d / tag
    sub.mkdir(exist_ok=True)
    cmd = ["blender", "-b", "--factory-startup", "-P", str(ROOT / "scripts/validate/cycles_timed.py"), "--",
           str(d / "scene.json"), str(sub), str(size), str(size), str(samples), ",".join(map(str, seeds)), str(threads),
           mode, str(times)]
    log = d / f"{tag}.log"
    with open(log, "w") as f:
        if subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT).returncode != 0:
            sys.exit(f"efficiency: Blender failed; see {log}")
    t = json.load(open(times))
    for r in t["runs"]:
        print(f"efficiency: {d.name}: Cycles {tag} seed {r['seed']}: {r['wall_s']:.2f} s wall, {r['cpu_s']:.2f} s CPU", flush=True)
    images = read_images([sub / f"cycles-{s}.exr" for s in seeds])
    return images, [r["cpu_s"] for r in t["runs"]], [r["wall_s"] for r in t["runs"]], t["settings"]


def measure(key, spec, args, out):
    d = out / key
    d.mkdir(parents=True, exist_ok=True)
    seeds = list(range(1, args.seeds + 1))
    rows = []
    img, cpu, wall = symphong_runs(spec, d, args.size, args.spp, seeds, args.threads, ["--splitting", "none"], "phong")
    rows.append(summarise("symphong `phong --splitting none`", img, cpu, wall, {"spp": args.spp}))
    img, cpu, wall = symphong_runs(spec, d, args.size, args.spp, seeds, args.threads, ["--splitting", "ears"], "ears")
    rows.append(summarise("symphong `phong --splitting ears` (the default)", img, cpu, wall, {"spp": args.spp}))
    if args.no_cycles:
        return rows
    env_py = ROOT / "build/release/python"
    subprocess.run([sys.executable, str(ROOT / "scripts/validate/export_scene.py"), spec, str(d / "scene.json")], check=True,
                   env={**os.environ, "PYTHONPATH": str(env_py)})
    # Calibration: one Cycles render at symphong's sample count (a seed the measured runs do not use) gives its
    # CPU time per render; the measured runs take the sample count that matches symphong's default render.
    _, ccpu, _, _ = cycles_runs(d, args.size, args.spp, [1000], args.threads, "fixed", "calibrate")
    samples = max(1, round(args.spp * rows[0]["cpu_s"] / ccpu[0]))
    print(f"efficiency: {key}: Cycles {args.spp} spp took {ccpu[0]:.2f} s CPU; equal time at {samples} spp", flush=True)
    for mode in ("fixed", "adaptive"):
        img, cpu, wall, settings = cycles_runs(d, args.size, samples, seeds, args.threads, mode, f"cycles-{mode}")
        label = "Cycles, adaptive sampling off" if mode == "fixed" else "Cycles, adaptive sampling on (threshold 0.01)"
        rows.append(summarise(label, img, cpu, wall, {"spp": samples, "settings": settings}))
    return rows


def table(key, rows):
    base = next((r for r in rows if r["name"].startswith("Cycles, adaptive sampling off")), rows[0])
    against = "Cycles (adaptive off)" if base["name"].startswith("Cycles") else "symphong `phong`"
    lines = [f"**{key}** (`{SCENES[key]}`):", "",
             f"| renderer | spp | CPU s / render | wall s | MSE | efficiency 1/(MSE x CPU s) | vs {against}, +-2 SE |",
             "|---|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        ratio = r["efficiency"] / base["efficiency"]
        se = math.hypot(r["log_se"], base["log_se"]) if r is not base else 0.0
        interval = f"{ratio:.2f}x [{ratio * math.exp(-2 * se):.2f}, {ratio * math.exp(2 * se):.2f}]" if r is not base else "1"
        lines.append(f"| {r['name']} | {r['spp']} | {r['cpu_s']:.2f} ± {r['cpu_se']:.2f} | {r['wall_s']:.2f} | "
                     f"{r['mse']:.3g} ± {r['mse_se']:.2g} | {r['efficiency']:.4g} | {interval} |")
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--size", type=int, default=256)
    ap.add_argument("--spp", type=int, default=64)
    ap.add_argument("--seeds", type=int, default=8)
    ap.add_argument("--threads", type=int, default=os.cpu_count())
    ap.add_argument("--scenes", default=None,
                    help=f"comma-separated, of {', '.join(SCENES)} (default: {','.join(CYCLES_SCENES)}, the ones Cycles can match)")
    ap.add_argument("--quick", action="store_true", help="64x64, 16 spp, 4 seeds")
    ap.add_argument("--write-doc", action="store_true", help="write the table into docs/performance.md")
    ap.add_argument("--no-cycles", action="store_true", help="symphong's variants alone (no Blender needed; any scene of --scenes)")
    ap.add_argument("--out", default=str(ROOT / "out/efficiency"))
    args = ap.parse_args()
    if args.quick:
        args.size, args.spp, args.seeds = 64, 16, 4
    if args.seeds < 3:
        ap.error("--seeds must be at least 3 (the jackknife needs it)")
    keys = (args.scenes or ",".join(CYCLES_SCENES)).split(",")
    for k in keys:
        if k not in SCENES:
            ap.error(f"--scenes: unknown scene '{k}' (known: {', '.join(SCENES)})")
    if args.write_doc and args.no_cycles:
        ap.error("--write-doc writes the comparison with Cycles: not with --no-cycles")
    if not args.no_cycles and "cornell" in keys:
        ap.error("--scenes cornell has a glossy block, which Cycles cannot match: use it with --no-cycles")
    if not args.no_cycles and subprocess.run(["which", "blender"], stdout=subprocess.DEVNULL).returncode != 0:
        sys.exit("efficiency: Blender is not installed (apt-get install blender)")
    if not (ROOT / "build/release/symphong").exists():
        subprocess.run(["cmake", "--preset", "release"], cwd=ROOT, check=True)
        subprocess.run(["cmake", "--build", "--preset", "release"], cwd=ROOT, check=True)
    sys.path.insert(0, str(ROOT / "build/release/python"))
    os.chdir(ROOT)
    out = pathlib.Path(args.out)
    results = {k: measure(k, SCENES[k], args, out) for k in keys}
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), platform.machine())
    argv = " ".join(sys.argv[1:])
    blender = "no Blender"
    if not args.no_cycles:
        settings = results[keys[0]][2]["settings"]
        blender = f"Blender {settings['blender']} (Cycles sampling pattern {settings['sampling_pattern']})"
    head = [f"Command: `python3 scripts/validate/efficiency.py{(' ' + argv) if argv else ''}`; "
            f"{time.strftime('%Y-%m-%d')}, symphong {commit}, {blender}, {os.cpu_count()} cores ({cpu}), {args.threads} threads each, "
            f"{args.size}x{args.size}, {args.seeds} seeds a renderer, load average {os.getloadavg()[0]:.1f} at the end.", ""]
    body = []
    for k in keys:
        body += table(k, results[k]) + [""]
    text = "\n".join(head + body)
    print(text)
    json.dump(results, open(out / "results.json", "w"), indent=1)
    if args.write_doc:
        doc = ROOT / "docs/performance.md"
        s = doc.read_text()
        if BEGIN not in s or END not in s:
            sys.exit(f"efficiency: {doc} has no {BEGIN} ... {END} markers")
        a, b = s.index(BEGIN) + len(BEGIN), s.index(END)
        doc.write_text(s[:a] + "\n" + text + "\n" + s[b:])
        print(f"efficiency: wrote {doc}")


if __name__ == "__main__":
    main()
