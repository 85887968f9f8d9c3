#!/usr/bin/env bash
# The Blender round trip (issue 20, item 4). Never run in CI: it needs Blender (Debian's, 3.4.1).
#
#   bash scripts/blender-roundtrip/run.sh                # make the scene in Blender, export, render, compare
#   bash scripts/blender-roundtrip/run.sh --no-blender   # render and compare the files already in tests/data/blender
#
# 1. make_scene.py (in Blender) builds the scene and writes its exports and its twin (twin.obj/.mtl/.json)
#    into DATA (default tests/data/blender).
# 2. assimp_dump (assimp_dump.cpp, compiled here by hand) prints what Assimp reads from each export:
#    DATA/assimp-5.2/<file>.txt (and --raw for the PLY), with each PLY's declared face count.
# 3. symphong renders the twin and every export (SPP samples, W x H pixels; exports with a camera both
#    with their own camera and with the twin's, the others with the twin's) into WORK (default
#    out/blender-roundtrip), and `symphong compare --regions` measures each against the twin, region by
#    region (the twin's objects under the pixel centres, roundtrip.py masks).
# 4. prints the table of mean ratios (also WORK/table.md) and WORK/loaded.md (what symphong's loader makes
#    of each export: camera, materials, warnings).
#
# Environment: DATA, WORK, SPP (64), W (64), H (64), SYMPHONG_BIN (build/release/symphong).
set -euo pipefail
cd "$(dirname "$0")/../.."
here=scripts/blender-roundtrip
data=${DATA:-tests/data/blender}
work=${WORK:-out/blender-roundtrip}
spp=${SPP:-64} width=${W:-64} height=${H:-64}
bin=${SYMPHONG_BIN:-build/release/symphong}
py=/usr/bin/python3
export PYTHONPATH=$PWD/build/release/python${PYTHONPATH:+:$PYTHONPATH}
[ -x "$bin" ] || { echo "roundtrip: $bin is missing: build symphong first (cmake --preset release && cmake --build --preset release)"; exit 1; }
mkdir -p "$data" "$work"

if [ "${1:-}" != "--no-blender" ]; then
  if ! command -v blender >/dev/null; then
    echo "roundtrip: installing Blender from Debian (apt-get install blender)"
    DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends blender >/dev/null
  fi
  echo "roundtrip: $(blender -b --factory-startup --version 2>/dev/null | head -1): make_scene.py -> $data"
  blender -b --factory-startup --python-exit-code 1 -P $here/make_scene.py -- "$data" >"$work/blender.log" 2>&1 ||
    { tail -30 "$work/blender.log"; exit 1; }
  grep '^make_scene' "$work/blender.log"
fi

# What Assimp reads (evidence for the loader's conversions).
if g++ -std=c++17 -O1 -o "$work/assimp_dump" $here/assimp_dump.cpp -lassimp; then
  mkdir -p "$data/assimp-5.2"
  for f in scene.glb scene.gltf scene.fbx scene.dae scene.obj scene.ply; do
    "$work/assimp_dump" "$data/$f" >"$data/assimp-5.2/$f.txt" 2>&1 || true
  done
  "$work/assimp_dump" --raw "$data/scene.ply" >"$data/assimp-5.2/scene.ply.raw.txt" 2>&1 || true
  declared=$(head -c 4096 "$data/scene.ply" | tr -d '\r' | awk '/^element face/ {print $3} /^end_header/ {exit}')
  echo "roundtrip: scene.ply declares $declared faces; Assimp: $(grep '^  total' "$data/assimp-5.2/scene.ply.raw.txt" | cut -c10-) (no post-processing);" \
       "$(grep '^  total' "$data/assimp-5.2/scene.ply.txt" | cut -c10-) (symphong's flags)"
else
  echo "roundtrip: assimp_dump did not compile (needs libassimp-dev); skipping the dumps"
fi

# Renders and comparisons.
"$py" $here/roundtrip.py scenes "$data" "$work"
mapfile -t masks < <("$py" $here/roundtrip.py masks "$data" "$width" "$height" "$work")
[ ${#masks[@]} -gt 0 ] || { echo "roundtrip: no region masks (roundtrip.py masks failed)"; exit 1; }
regions=$(IFS=';'; echo "${masks[*]}")
mkdir -p "$work/renders" "$work/compare" "$work/logs"
rm -f "$work"/compare/*
render() {  # label scene [render arguments]
  local label=$1 scene=$2
  shift 2
  # --splitting none: plain phong, as docs/validation.md's figures were measured (the default learns EARS's splitting)
  "$bin" render "$scene" --spp "$spp" --width "$width" --height "$height" --splitting none --output "$work/renders/$label.exr" "$@" \
    >"$work/logs/$label.log" 2>&1
}
render twin "$data/twin.json" || { cat "$work/logs/twin.log"; exit 1; }
while IFS=$'\t' read -r label scene extra; do
  # shellcheck disable=SC2086 (extra: zero or more words)
  if render "$label" "$scene" $extra; then
    "$bin" compare "$work/renders/$label.exr" "$work/renders/twin.exr" --regions "$regions" --json >"$work/compare/$label.json"
  else
    tail -1 "$work/logs/$label.log" >"$work/compare/$label.error"
  fi
  grep -i warn "$work/logs/$label.log" | sed "s/^/roundtrip: $label: /" || true
done < <("$py" $here/roundtrip.py renders "$data" "$work")

"$py" $here/roundtrip.py loaded "$data" "$work" >/dev/null
"$py" $here/roundtrip.py table "$work" | tee "$work/table.md"
echo "roundtrip: $spp spp, $width x $height; renders in $work/renders, what symphong loads in $work/loaded.md"
