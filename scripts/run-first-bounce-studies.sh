#!/usr/bin/env bash
# The side studies behind docs/estimators.md sections 10-11 and docs/sampling.md (about 10 minutes on 2
# cores), each a `symphong study` under the sobol sampler at 64 spp with 5 repeats, written to
# docs/study/first-bounce/<study>/<scene>/ (results.json and report.md; images removed), and one table per
# study printed by scripts/first-bounce-table.py:
#   splits  - phong split K = 2, 4, 8 ways at the first hit, on the original and the glossy-100 box;
#   orbits  - symmetric-mix with an orbit of R = 1, 2, 4, 8 copies, traced together (branch) or spread, same scenes;
#   joint   - cosine, phong and symmetric-mix with and without the joint 4D pixel + first-bounce pattern, on
#             the six study scenes.
# Extra arguments go to every `symphong study` run.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${SYMPHONG_BIN:-build/release/symphong}  # SYMPHONG_BIN: a copy, so that rebuilding during a long run changes nothing
[ -x "$bin" ] || bash scripts/setup.sh
root=docs/study/first-bounce
common=(--samplers sobol --spp 64 --repeats 5 --reference-spp 2048 --no-plots)

run() {  # run OUT SCENE ARGS...
  local out=$1 scene=$2
  shift 2
  echo "== $out"
  "$bin" study "$scene" --out "$out" "${common[@]}" "$@" "${extra[@]}" >/dev/null
  rm -rf "$out"/renders "$out"/heatmaps "$out"/reference.exr "$out"/*.png
}
extra=("$@")

for scene in cornell scenes/cornell-glossy-100.json; do
  name=$(basename "$scene" .json)
  run "$root/splits/$name" "$scene" --estimators phong --splits 2,4,8 --split-estimators phong
  for orbit in 1 2 4 8; do
    run "$root/orbits/$name-orbit$orbit" "$scene" --estimators phong,symmetric-mix --symmetric-modes branch,spread \
        --symmetric-orbit "$orbit"
  done
done
for scene in cornell scenes/cornell-diffuse.json scenes/cornell-glossy-100.json scenes/cornell-glossy-1000.json \
             scenes/cornell-all-glossy.json scenes/mcguire-glossy.json; do
  name=$(basename "$scene" .json)
  run "$root/joint/$name-padded" "$scene" --estimators cosine,phong,symmetric-mix --symmetric-modes spread
  run "$root/joint/$name-joint" "$scene" --estimators cosine,phong,symmetric-mix --symmetric-modes spread --joint-first-bounce
done
/usr/bin/python3 scripts/first-bounce-table.py "$root"
