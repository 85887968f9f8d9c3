#!/usr/bin/env bash
# Blender's exports of one normal-mapped plane (tests/data/blender/normalmap, made by make_normal_map.py)
# rendered by symphong, each compared with the glTF export and with Cycles' own picture of the scene
# (cycles_reference.exr). Never run in CI; no Blender needed (the exports are in the repository).
#
#   bash scripts/blender-roundtrip/normalmap.sh      # W=96 H=96 SPP=256 by default, WORK=out/normalmap
set -euo pipefail
cd "$(dirname "$0")/../.."
data=tests/data/blender/normalmap
work=${WORK:-out/normalmap}
spp=${SPP:-256} width=${W:-96} height=${H:-96}
bin=${SYMPHONG_BIN:-build/release/symphong}
[ -x "$bin" ] || { echo "normalmap: $bin is missing: build symphong first"; exit 1; }
mkdir -p "$work"
ratio() {  # mean test / reference from symphong compare
  "$bin" compare "$1" "$2" | sed -n 's/^mean test \/ reference .* = \([0-9.]*\)$/\1/p'
}
echo "| export | mean / glTF's | FLIP against glTF's | mean / Cycles' |"
echo "|---|---:|---:|---:|"
for f in scene.glb scene_tangents.glb scene.fbx scene_tspace.fbx obj_camera.json scene_strength05.glb scene_strength05.fbx; do
  out="$work/${f//./_}.exr"
  "$bin" render "$data/$f" -W "$width" -H "$height" -s "$spp" --seed 7 -o "$out" >/dev/null 2>&1
  flip=$("$bin" compare "$out" "$work/scene_glb.exr" | sed -n 's/^FLIP *\([0-9.]*\).*/\1/p')
  echo "| $f | $(ratio "$out" "$work/scene_glb.exr") | $flip | $(ratio "$out" "$data/cycles_reference.exr") |"
done
