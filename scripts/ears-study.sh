#!/usr/bin/env bash
# Measures --splitting ears against plain phong and fixed first-hit splitting (phong+split2, +split8) with
# the study (CPU-time cost, paired repeats until each comparison is decided within 10% or 40 s), on six
# scenes of the study: the boxes and regime scenes named below. Prints a Markdown table of efficiency
# ratios against phong (docs/performance.md "Efficiency-aware splitting" holds its output).
#   bash scripts/ears-study.sh [OUT] [SAMPLER] [SPP] [WxH] [REFERENCE_SPP] [SPLITS] [SCENES]
# defaults /tmp/ears-study, sobol, 16, 128x96, 1024, 2,8, six; SPLITS "none" leaves the fixed splits out (at a large
# size they double the run for columns that do not change the EARS column). SCENES: "six" (the six below),
# "all" (the 25 study scenes of scripts/study-scenes.sh, which run-studies.sh runs), or scene
# names and paths separated by commas.
#   SYMPHONG_BIN=/tmp/copy bash scripts/ears-study.sh /tmp/ears-512 sobol 64 512x512 2048 none
#   bash scripts/ears-study.sh /tmp/ears-all sobol 64 128x96 1024 none all
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-/tmp/ears-study} sampler=${2:-sobol} spp=${3:-16} size=${4:-128x96} reference=${5:-1024} splits=${6:-2,8}
[[ $size =~ ^([0-9]+)x([0-9]+)$ ]] || { echo "ears-study.sh: size '$size' is not WxH (e.g. 512x512)" >&2; exit 2; }
width=${BASH_REMATCH[1]} height=${BASH_REMATCH[2]}
split_args=(--splits "$splits" --split-estimators phong)
[ "$splits" = none ] && split_args=()
bin=${SYMPHONG_BIN:-build/release/symphong}  # SYMPHONG_BIN: a copy, so that rebuilding during the run changes nothing
[ -x "$bin" ] || bash scripts/setup.sh
case ${7:-six} in
  six) scenes=(cornell scenes/cornell-glossy-100.json scenes/regime/sky-n10.json scenes/regime/small-n10.json
               scenes/regime/large-n100.json scenes/regime/albedo-diffuse.json) ;;
  all) source scripts/study-scenes.sh && scenes=("${boxes[@]}" "${regime[@]}") ;;
  *) IFS=, read -r -a scenes <<< "$7" ;;
esac
for scene in "${scenes[@]}"; do
  [ "$scene" = cornell ] || [ -f "$scene" ] || { echo "ears-study.sh: scene '$scene' is not a file (nor the built-in cornell)" >&2; exit 2; }
done
for scene in "${scenes[@]}"; do
  "$bin" study "$scene" --estimators phong --samplers "$sampler" --splittings none,ears "${split_args[@]}" \
    --cost cpu --spp "$spp" --repeats 6 --target-interval 0.1 --max-repeats 30 --time 40 -W "$width" -H "$height" \
    --reference-spp "$reference" --no-plots --no-page --out "$out/$(basename "$scene" .json)" >/dev/null
done
/usr/bin/python3 - "$out" "$sampler" "$spp" "$size" "${scenes[@]}" <<'PY'
import json, sys, os
out, sampler, spp, size, scenes = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5:]
print(f"| scene ({sampler}, {spp} spp, {size}) | phong+ears | phong+split2 | phong+split8 |")
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
