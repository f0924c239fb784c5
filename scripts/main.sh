#!/usr/bin/env bash
# The main job: set up a fresh Debian 12, build, and run the station on the simulated glove and
# the bundled 3,203-point sphere, writing the sculpted model, its event log and the run's summary to out/.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
bash scripts/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)"
mkdir -p out
# The station on the simulated glove: three fingers squeeze the bundled 3,203-point sphere.
# The scene writes its event log to out/sphere-squeeze.lcmlog.
./build/tools/sculpt run scenes/sphere-squeeze.toml --duration 5 --quiet \
  --out out/sphere_sculpted.ply --json out/sphere_sculpted.json
echo "main: the sculpted model is out/sphere_sculpted.ply, its log out/sphere-squeeze.lcmlog, the summary out/sphere_sculpted.json"
