#!/usr/bin/env bash
# Renders diffuse scenes with symphong and with Blender Cycles (installed here from Debian if missing;
# never needed by CI) and writes the comparison into docs/validation.md (between its validate markers)
# and docs/images/validation/. Renders go to out/validate/.
#
#   bash scripts/validate/run.sh            # 2048 spp (symphong) and 4096 spp (Cycles), two seeds each
#   bash scripts/validate/run.sh --quick    # 64 / 128 spp: checks the pipeline in a minute
#
# Scenes: the classic all-diffuse Cornell box (scenes/cornell-classic.json), the built-in Cornell box
# made diffuse (scenes/cornell-diffuse.json) and McGuire's CornellBox-Original.obj (../shared/scenes).
set -euo pipefail
cd "$(dirname "$0")/../.."
ours_spp=2048 cycles_spp=4096 size=256 seeds=(1 2)
if [ "${1:-}" = "--quick" ]; then ours_spp=64 cycles_spp=128; fi
threads=$(nproc)
py=/usr/bin/python3

if ! command -v blender >/dev/null; then
  echo "validate: installing Blender from Debian (apt-get install blender)"
  DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends blender >/dev/null
fi
if [ ! -x build/release/symphong ] || ! ls build/release/python/symphong*.so >/dev/null 2>&1; then
  echo "validate: building symphong (cmake --preset release)"
  cmake --preset release >/dev/null && cmake --build --preset release >/dev/null
fi
export PYTHONPATH=$PWD/build/release/python
out=out/validate
mkdir -p "$out"
blender_version=$(blender -b --factory-startup --version 2>/dev/null | head -1)

declare -A spec title
keys=(cornell-classic cornell-diffuse mcguire-original)
spec[cornell-classic]=scenes/cornell-classic.json
title[cornell-classic]="The classic all-diffuse Cornell box"
spec[cornell-diffuse]=scenes/cornell-diffuse.json
title[cornell-diffuse]="The built-in Cornell box, made diffuse"
spec[mcguire-original]=../shared/scenes/cornell-box-mcguire/CornellBox-Original.obj
title[mcguire-original]="McGuire's CornellBox-Original.obj (automatic camera)"

seconds() { local ns=$(($(date +%s%N) - $1)); printf "%d.%03d" $((ns / 1000000000)) $((ns % 1000000000 / 1000000)); }
for key in "${keys[@]}"; do
  d=$out/$key
  mkdir -p "$d"
  "$py" scripts/validate/export_scene.py "${spec[$key]}" "$d/scene.json"
  ours_t=() cycles_t=()
  for seed in "${seeds[@]}"; do
    echo "validate: $key: symphong, $ours_spp spp, seed $seed"
    t=$(date +%s%N)
    # --splitting none: plain phong, as docs/validation.md's figures were measured (the default learns EARS's splitting)
    build/release/symphong render "${spec[$key]}" -W $size -H $size --spp $ours_spp --seed "$seed" --max-depth 64 \
      -t "$threads" --splitting none -o "$d/symphong-$seed.exr" >/dev/null
    ours_t+=("$(seconds "$t")")
    echo "validate: $key: Cycles, $cycles_spp spp, seed $seed"
    t=$(date +%s%N)
    blender -b --factory-startup -P scripts/validate/cycles_scene.py -- "$d/scene.json" "$d/cycles-$seed.exr" \
      $size $size $cycles_spp "$seed" "$threads" >"$d/cycles-$seed.log" 2>&1 || { tail "$d/cycles-$seed.log"; exit 1; }
    cycles_t+=("$(seconds "$t")")
  done
  "$py" - "$d/info.json" "${spec[$key]}" "${title[$key]}" $ours_spp $cycles_spp "${ours_t[*]}" "${cycles_t[*]}" "${seeds[*]}" <<'PY'
import json, sys
path, spec, title, ours, cycles, ot, ct, seeds = sys.argv[1:]
json.dump({"spec": spec, "title": title, "symphong_spp": int(ours), "cycles_spp": int(cycles),
           "symphong_seconds": [float(x) for x in ot.split()], "cycles_seconds": [float(x) for x in ct.split()],
           "seeds": [int(s) for s in seeds.split()]}, open(path, "w"))
PY
done

"$py" - "$out/run.json" "bash scripts/validate/run.sh${1:+ $1}" "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)" \
  "$blender_version" <<'PY'
import json, sys
path, command, machine, blender = sys.argv[1:]
json.dump({"command": command, "machine": machine, "blender": blender,
           "cycles_settings": "CPU, no adaptive sampling, no denoising, max/diffuse/glossy/transmission/transparent bounces 64, "
                              "no clamping (direct and indirect 0), light threshold 0, filter glossy 0, box pixel filter 1 px, "
                              "Diffuse BSDF roughness 0, emission from front faces only (Mix on Geometry.Backfacing), black world, "
                              "standard view transform, 32-bit float EXR",
           "symphong_settings": "default estimator (phong) and sampler (sobol), --max-depth 64, light sampling with MIS"},
          open(path, "w"))
PY
"$py" scripts/validate/compare.py "$out" docs/validation.md docs/images/validation "${keys[@]}"
echo "validate: wrote docs/validation.md and docs/images/validation/"
