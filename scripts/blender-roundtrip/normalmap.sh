#!/usr/bin/env bash
# Blender's exports of one normal-mapped plane (tests/data/blender/normalmap, made by make_normal_map.py)
# rendered by symphong, each compared with the glTF export and with Cycles' own picture of the scene
# (cycles_reference.exr), and the picture docs/images/normalmap-vs-cycles.png. Never run in CI; no Blender
# needed (the exports are in the repository).
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
for run in scene.glb scene_tangents.glb scene.fbx scene_tspace.fbx obj_camera.json scene_strength05.glb scene_strength05.fbx \
           "scene.glb --bump-shadowing"; do
  read -r f flag <<<"$run"
  out="$work/${f//./_}${flag:+_shadowing}.exr"
  "$bin" render "$data/$f" $flag -W "$width" -H "$height" -s "$spp" --seed 7 --splitting none -o "$out" >/dev/null 2>&1
  flip=$("$bin" compare "$out" "$work/scene_glb.exr" | sed -n 's/^FLIP *\([0-9.]*\).*/\1/p')
  echo "| $run | $(ratio "$out" "$work/scene_glb.exr") | $flip | $(ratio "$out" "$data/cycles_reference.exr") |"
done

# The picture of docs/validation.md: symphong's glTF render as it is and with --bump-shadowing, each with
# its signed relative error against Cycles, and Cycles' own.
"$bin" compare "$work/scene_glb.exr" "$data/cycles_reference.exr" --error-map "$work/error.png" >/dev/null
"$bin" compare "$work/scene_glb_shadowing.exr" "$data/cycles_reference.exr" --error-map "$work/error_shadowing.png" >/dev/null
PYTHONPATH=$PWD/build/release/python /usr/bin/python3 - "$work" "$data" <<'PY'
import sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import symphong
work, data = sys.argv[1], sys.argv[2]
tone = lambda x: np.clip(np.asarray(x) / 0.6, 0, 1) ** (1 / 2.2)
panels = [
    (tone(symphong.read_image(f"{work}/scene_glb.exr")), "symphong (scene.glb)"),
    (plt.imread(f"{work}/error.png"), "its signed relative error vs Cycles"),
    (tone(symphong.read_image(f"{data}/cycles_reference.exr")), "Blender Cycles 3.4"),
    (tone(symphong.read_image(f"{work}/scene_glb_shadowing.exr")), "symphong --bump-shadowing"),
    (plt.imread(f"{work}/error_shadowing.png"), "its signed relative error vs Cycles"),
]
fig, ax = plt.subplots(2, 3, figsize=(9, 6.4), dpi=100)
for a in ax.flat:
    a.axis("off")
for a, (img, title) in zip(ax.flat, panels):
    a.imshow(img, interpolation="nearest")
    a.set_title(title, fontsize=9)
plt.tight_layout()
plt.savefig("docs/images/normalmap-vs-cycles.png")
print("normalmap: docs/images/normalmap-vs-cycles.png")
PY
