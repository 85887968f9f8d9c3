#!/usr/bin/env bash
# Load time of a 1,000,000-triangle mesh in each format symphong reads: writes a height field as OBJ,
# converts it with Assimp's exporter (a few lines of C++ compiled here against libassimp), then times
# `symphong render FILE -W 16 -H 16 --spp 1` (parse + BVH build + a negligible render) twice per
# format, alternating. Figures in docs/performance.md ("Loading").
#   bash scripts/bench-load.sh [OUT_DIR]     (default /tmp/symphong-load; about 600 MB of files)
set -euo pipefail
cd "$(dirname "$0")/.."
bin=$PWD/build/release/symphong
out=${1:-/tmp/symphong-load}
mkdir -p "$out"
/usr/bin/python3 - "$out/grid1m.obj" <<'PY'
import math, sys
nx, nz = 708, 707  # 2 x 708 x 707 = 1,001,112 triangles
with open(sys.argv[1], "w") as f:
    for j in range(nz + 1):
        for i in range(nx + 1):
            x, z = i / nx, j / nz
            f.write(f"v {x:.6f} {0.05 * math.sin(12 * x) * math.cos(9 * z):.6f} {z:.6f}\n")
    w = nx + 1
    for j in range(nz):
        for i in range(nx):
            a = j * w + i + 1
            f.write(f"f {a} {a + 1} {a + w + 1}\nf {a} {a + w + 1} {a + w}\n")
PY
cat >"$out/export.cpp" <<'CPP'
#include <assimp/Exporter.hpp>
#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <cstdio>
int main(int, char** argv) {
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(argv[1], aiProcess_Triangulate);
    Assimp::Exporter exporter;
    if (scene && exporter.Export(scene, argv[2], argv[3]) == AI_SUCCESS) return 0;
    std::fprintf(stderr, "%s\n", scene ? exporter.GetErrorString() : importer.GetErrorString());
    return 1;
}
CPP
g++ -O1 -o "$out/export" "$out/export.cpp" -lassimp
for pair in "glb2 glb" "plyb ply" "collada dae" "3ds 3ds"; do
  set -- $pair
  "$out/export" "$out/grid1m.obj" "$1" "$out/grid1m.$2"
done
echo "| format | file size | load + BVH + 16x16 render, two runs | peak memory |"
echo "|---|---:|---:|---:|"
declare -A times mem
for round in 1 2; do
  for ext in obj glb ply dae 3ds; do
    /usr/bin/time -f "%e %M" -o "$out/time" "$bin" render "$out/grid1m.$ext" -W 16 -H 16 --spp 1 -o "$out/x.png" >/dev/null 2>&1
    read -r t m <"$out/time"
    times[$ext]+="${times[$ext]:+, }$t s"
    mem[$ext]=$((m / 1024))
  done
done
for ext in obj glb ply dae 3ds; do
  echo "| .$ext | $(($(stat -c %s "$out/grid1m.$ext") / 1000000)) MB | ${times[$ext]} | ${mem[$ext]} MB |"
done
