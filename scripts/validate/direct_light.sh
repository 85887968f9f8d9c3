#!/usr/bin/env bash
# The back-wall excess of docs/validation.md, settled: direct light on the classic Cornell box's back
# wall from symphong (--max-depth 1), from Cycles (max bounces 0) with its light sampling and without
# it, each against Lambert's closed form. Needs Blender (run.sh installs it). About 10 minutes on 2 cores.
#   bash scripts/validate/direct_light.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
export PYTHONPATH=$PWD/build/release/python
d=out/validate/direct-light
mkdir -p "$d"
threads=$(nproc)
/usr/bin/python3 scripts/validate/export_scene.py scenes/cornell-classic.json "$d/scene.json"
for seed in 1 2; do
  build/release/symphong render scenes/cornell-classic.json -W 256 -H 256 --spp 1024 --seed $seed --max-depth 1 --splitting none -t "$threads" \
    -o "$d/symphong-$seed.exr" >/dev/null
  blender -b --factory-startup -P scripts/validate/cycles_scene.py -- "$d/scene.json" "$d/cycles-$seed.exr" 256 256 1024 $seed "$threads" 0 \
    >"$d/cycles-$seed.log" 2>&1
  blender -b --factory-startup -P scripts/validate/cycles_scene.py -- "$d/scene.json" "$d/cycles-bsdf-$seed.exr" 256 256 4096 $seed "$threads" 0 \
    no-light-sampling >"$d/cycles-bsdf-$seed.log" 2>&1
done
/usr/bin/python3 scripts/validate/direct_light.py "$d"
