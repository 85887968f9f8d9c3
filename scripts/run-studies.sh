#!/usr/bin/env bash
# Regenerates the estimator studies committed under docs/study/ and the page that answers across them
# (docs/study/report.md, with the regime map docs/study/regime-map.png), in about 14 minutes on 2 cores (21 before the throughput work of issue 33)
# (docs/performance.md has the measured time of each run). Two sets of scenes:
#   - the six boxes (docs/study/<name>/): the built-in Cornell box, its diffuse, glossy (n = 100, 1000) and
#     all-glossy variants, and McGuire's glossy box; every estimator family, at 4 and 16 spp, 96x96;
#   - the regime scenes (docs/study/regime/<name>/, scenes/regime/): a glossy sphere and floor under a small
#     or a large area light, a smooth sky, or the sky with a sun, at n = 1, 10, 100, 1000, two albedo
#     variants and the Stanford bunny; phong and symmetric-mix only, at 16 spp, 128x96, without plots and pages.
# Every study compares at equal paths per camera sample (`symmetric-mix` with an orbit of R = 2, 4, 8
# against `phong` split R ways; its spread mode against plain `phong`), divides by CPU time (--cost cpu:
# a busy machine does not bend it) and adds paired repeats at the top spp until every comparison is
# decided within +-10% (--target-interval 0.1) or the scene's --time runs out.
# Extra arguments go to every `symphong study` run. Large files (reference EXR, raw heat maps, SVG copies
# of the plots, the renders' EXRs that report.html holds) are removed from docs/study; `symphong study`
# itself keeps them.
#   SYMPHONG_STUDY_OUT=DIR bash scripts/run-studies.sh   writes into DIR instead of docs/study (a second run to
#   compare with the committed one: scripts/study-report.py --compare DIR).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${SYMPHONG_BIN:-build/release/symphong}  # SYMPHONG_BIN: a copy, so that rebuilding during a long run changes nothing
[ -x "$bin" ] || bash scripts/setup.sh
top=${SYMPHONG_STUDY_OUT:-docs/study}
start=$(date +%s)

source scripts/study-scenes.sh  # boxes, regime

pairs=(--symmetric-modes branch,spread --splits 2,4,8 --split-estimators phong --orbits 2,4,8
       --cost cpu --target-interval 0.1 --max-repeats 200 --page-top-spp-only)
box_args=(--estimators cosine,phong,paper,symmetric,symmetric-mix "${pairs[@]}" --spp 4,16 --repeats 6 --time 150
          -W 96 -H 96 --reference-spp 4096 --budget-pairs 1)
# The regime scenes without plots or report.html (one spp: no convergence to plot; their pages would add 23 MB
# to the repository per regeneration): report.md, details.md and the results.
regime_args=(--estimators phong,symmetric-mix "${pairs[@]}" --spp 16 --repeats 6 --time 90 -W 128 -H 96 --reference-spp 2048
             --no-plots --no-page)

run() {  # run OUT SCENE ARGS...
  local out=$1 scene=$2
  shift 2
  echo "== $scene -> $out ($(( $(date +%s) - start )) s so far)"
  rm -rf "$out/renders" "$out/heatmaps"
  "$bin" study "$scene" --out "$out" "$@"
  rm -f "$out"/reference.exr "$out"/heatmaps/*.f32 "$out"/plot_study.py "$out"/*.svg "$out"/renders/*.exr  # report.html holds the renders
}
for scene in "${boxes[@]}"; do run "$top/$(basename "$scene" .json)" "$scene" "${box_args[@]}" "$@"; done
for scene in "${regime[@]}"; do
  out="$top/regime/$(basename "$scene" .json)"
  run "$out" "$scene" "${regime_args[@]}" "$@"
  rm -rf "$out/renders" "$out/heatmaps" "$out"/*.png  # no page shows them
done
elapsed=$(( $(date +%s) - start ))

# One page that answers the question across scenes, computed from each study's results.json.
/usr/bin/python3 scripts/study-report.py --out "$top" --minutes "$(( (elapsed + 30) / 60 ))" \
  "${boxes[@]}" -- "${regime[@]}"
echo "$top/report.md written ($elapsed s)"
