#!/usr/bin/env bash
# The main job: set up a fresh Debian 12, build, and sculpt the bundled 3,203-point sphere with
# one collision frame of three fingers, writing the model and a JSON report to out/.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
bash scripts/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
mkdir -p out
./build/tools/sculpt deform --model data/sphere_3203.ply --out out/sphere_sculpted.ply \
  --contact 0,0,1.1:0,0,0.93 --contact 0.8,0,0.8:0.66,0,0.66 --contact -0.8,0,0.8:-0.66,0,0.66 \
  --json out/sphere_sculpted.json
echo "main: the sculpted model is out/sphere_sculpted.ply, its report out/sphere_sculpted.json"
