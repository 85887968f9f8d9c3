#!/usr/bin/env bash
# Does the study's answer survive a busy machine? Runs the same small study twice, quiet and with two busy
# loops beside it (one per core of a 2-core machine), and compares each variant's efficiency ratio
# against `phong` between the two runs, with efficiency divided by CPU time (`--cost cpu`, the default)
# and by wall time (every row records both, so one study gives both). The images are bit for bit the
# same in both runs (same seeds): only the cost can move a ratio. Prints a Markdown table for
# docs/performance.md ("The study under load") and fails when a CPU-time ratio moves by more than 5%.
#   bash scripts/study-under-load.sh [OUT_DIR]     (default /tmp/symphong-load-study; about 4 minutes)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${SYMPHONG_BIN:-build/release/symphong}
[ -x "$bin" ] || bash scripts/setup.sh
out=${1:-/tmp/symphong-load-study}
rm -rf "$out"
mkdir -p "$out"
args=(cornell --estimators cosine,phong,symmetric-mix --symmetric-modes branch,spread --splits 2 --split-estimators phong
      --orbits 2 --spp 16 --repeats 8 -W 96 -H 96 --reference-spp 1024 --no-plots)

"$bin" study "${args[@]}" --out "$out/quiet" >/dev/null
mkdir -p "$out/busy" && cp "$out/quiet/reference.exr" "$out/quiet/reference.json" "$out/busy/"  # the cached reference: the same
busy() { while :; do :; done; }
busy & b1=$!
busy & b2=$!
trap 'kill $b1 $b2 2>/dev/null || true' EXIT
"$bin" study "${args[@]}" --out "$out/busy" >/dev/null
kill $b1 $b2 2>/dev/null || true
trap - EXIT

/usr/bin/python3 - "$out" <<'PY'
import json, math, sys
out = sys.argv[1]
runs = {name: json.load(open(f"{out}/{name}/results.json")) for name in ("quiet", "busy")}

def ratio(rows, a, b, cost):
    """Efficiency of a over b: mean(MSE_b) mean(cost_b) / (mean(MSE_a) mean(cost_a)), repeats paired by number."""
    ra = {r["repeat"]: r for r in rows if r["variant"] == a}
    rb = {r["repeat"]: r for r in rows if r["variant"] == b}
    common = sorted(set(ra) & set(rb))
    mean = lambda xs: sum(xs) / len(xs)
    return (mean([rb[i]["mse"] for i in common]) * mean([rb[i][cost] for i in common])) / \
           (mean([ra[i]["mse"] for i in common]) * mean([ra[i][cost] for i in common]))

variants = [v["label"] for v in runs["quiet"]["config"]["variants"] if v["label"] != "phong"]
same = all(q["mse"] == b["mse"] for q, b in zip(runs["quiet"]["rows"], runs["busy"]["rows"]))
print(f"Images bit for bit the same in both runs: {'yes' if same else 'NO'}\n")
print("| variant | CPU time: quiet | busy | change | wall time: quiet | busy | change |")
print("|---|---:|---:|---:|---:|---:|---:|")
worst = 0.0
for v in variants:
    cells = []
    for cost in ("cpu_seconds", "seconds"):
        q, b = ratio(runs["quiet"]["rows"], v, "phong", cost), ratio(runs["busy"]["rows"], v, "phong", cost)
        change = b / q - 1
        if cost == "cpu_seconds":
            worst = max(worst, abs(change))
        cells += [f"{q:.3f}x", f"{b:.3f}x", f"{100 * change:+.1f}%"]
    print(f"| `{v}` | " + " | ".join(cells) + " |")
tq = sum(r["seconds"] for r in runs["quiet"]["rows"])
tb = sum(r["seconds"] for r in runs["busy"]["rows"])
cq = sum(r["cpu_seconds"] for r in runs["quiet"]["rows"])
cb = sum(r["cpu_seconds"] for r in runs["busy"]["rows"])
print(f"\nRender time of the whole study: wall {tq:.1f} s quiet, {tb:.1f} s busy ({tb / tq:.2f}x); "
      f"CPU {cq:.1f} s quiet, {cb:.1f} s busy ({cb / cq:.2f}x).")
print(f"Largest change of a CPU-time ratio: {100 * worst:.1f}% (asked: at most 5%).")
sys.exit(0 if same and worst <= 0.05 else 1)
PY
