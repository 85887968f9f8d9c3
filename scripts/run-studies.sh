#!/usr/bin/env bash
# Regenerates the estimator studies committed under docs/study/ (21 minutes on 2 cores on 2026-12-02, on a quiet
# machine: efficiency divides by render time): the built-in Cornell box, its diffuse, glossy (n = 100,
# 1000) and all-glossy variants, and McGuire's glossy box from the shared scenes; every estimator under the
# sobol sampler (the default; docs/performance.md compares the samplers), the symmetric ones in branch and
# spread mode, phong also split 2 ways at the first hit (the same work per camera sample
# as symmetric-mix's branch mode, an orbit of 2), 5 repeats, one variance-budget pair per variant. Extra arguments go to every `symphong study` run. Large files
# (reference EXR, raw heat maps, SVG copies of the plots, the renders' EXRs that report.html holds) are
# removed from docs/study; `symphong study`
# itself keeps them.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${SYMPHONG_BIN:-build/release/symphong}  # SYMPHONG_BIN: a copy, so that rebuilding during a long run changes nothing
[ -x "$bin" ] || bash scripts/setup.sh

scenes=(cornell scenes/cornell-diffuse.json scenes/cornell-glossy-100.json scenes/cornell-glossy-1000.json
        scenes/cornell-all-glossy.json scenes/mcguire-glossy.json)
args=(--estimators cosine,stratified,phong,symmetric,symmetric-shifted,symmetric-mix --samplers sobol
      --symmetric-modes branch,spread --splits 2 --split-estimators phong --spp 4,16,64 --repeats 5 --budget-pairs 1
      --reference-spp 4096)
rm -rf docs/study/cornell-glossy-10  # no longer studied
for scene in "${scenes[@]}"; do
  name=$(basename "$scene" .json)
  out=docs/study/$name
  echo "== $scene -> $out"
  rm -rf "$out/renders" "$out/heatmaps"
  "$bin" study "$scene" --out "$out" "${args[@]}" "$@"
  rm -f "$out"/reference.exr "$out"/heatmaps/*.f32 "$out"/plot_study.py "$out"/*.svg "$out"/renders/*.exr  # report.html holds the renders
done

# One page that answers the question across scenes, computed from each study's results.json.
/usr/bin/python3 scripts/study-report.py "${scenes[@]}"
rm -f docs/study/README.md
echo "docs/study/report.md written"
