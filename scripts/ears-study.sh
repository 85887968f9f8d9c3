#!/usr/bin/env bash
# Measures --splitting ears against plain phong and fixed first-hit splitting (phong+split2, +split8) with
# the study (CPU-time cost, paired repeats until each comparison is decided within 10% or 40 s), on six
# scenes of the study: the boxes and regime scenes named below. Prints a Markdown table of efficiency
# ratios against phong (docs/performance.md "Efficiency-aware splitting" holds its output).
#   bash scripts/ears-study.sh [OUT] [SAMPLER] [SPP]     (default /tmp/ears-study, sobol, 16)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-/tmp/ears-study} sampler=${2:-sobol} spp=${3:-16}
bin=${SYMPHONG_BIN:-build/release/symphong}  # SYMPHONG_BIN: a copy, so that rebuilding during the run changes nothing
[ -x "$bin" ] || bash scripts/setup.sh
scenes=(cornell scenes/cornell-glossy-100.json scenes/regime/sky-n10.json scenes/regime/small-n10.json
        scenes/regime/large-n100.json scenes/regime/albedo-diffuse.json)
for scene in "${scenes[@]}"; do
  "$bin" study "$scene" --estimators phong --samplers "$sampler" --splittings none,ears --splits 2,8 --split-estimators phong \
    --cost cpu --spp "$spp" --repeats 6 --target-interval 0.1 --max-repeats 30 --time 40 -W 128 -H 96 --reference-spp 1024 \
    --no-plots --no-page --out "$out/$(basename "$scene" .json)" >/dev/null
done
/usr/bin/python3 - "$out" "$sampler" "$spp" "${scenes[@]}" <<'PY'
import json, sys, os
out, sampler, spp, scenes = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
print(f"| scene ({sampler}, {spp} spp) | phong+ears | phong+split2 | phong+split8 |")
print("|---|---:|---:|---:|")
for s in scenes:
    r = json.load(open(os.path.join(out, os.path.basename(s).removesuffix(".json"), "results.json")))
    cells = {}
    for c in r["comparisons"]:
        if c["against"] == "phong":
            m = c["mse"]
            cells[c["variant"]] = f'{m["ratio"]:.2f}x [{m["lo"]:.2f}, {m["hi"]:.2f}] {m["verdict"]}'
    print(f"| {os.path.basename(s)} | " + " | ".join(cells.get(v, "-") for v in ["phong+ears", "phong+split2", "phong+split8"]) + " |")
PY
