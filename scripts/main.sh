#!/usr/bin/env bash
# The main job: set up a fresh Debian 12, build, and run the station on the simulated glove and
# the bundled 3,203-point sphere, writing the sculpted model, its event log and the run's summary to out/.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
bash scripts/setup.sh
# Configured as scripts/test.sh configures its Release pass, so that the two README commands
# share one build tree in either order instead of each recompiling the other's (every flag
# differed: -Werror changes every compile command). Only what this job runs is built here.
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS=-Werror -DSCULPT_UNITY_DRIVERS=ON >/dev/null
cmake --build build -j"$(nproc)" --target sculpt
mkdir -p out
# The station on the simulated glove: three fingers squeeze the bundled 3,203-point sphere.
# The scene writes its event log to out/sphere-squeeze.lcmlog; --replace-log lets this job's
# own earlier log go (without it a run refuses to erase a log that holds a session).
./build/tools/sculpt run scenes/sphere-squeeze.toml --duration 5 --quiet --replace-log \
  --out out/sphere_sculpted.ply --json out/sphere_sculpted.json
# Pictures of the result, headless (OSMesa): the sphere before and after from the thumb's side,
# and both from each finger's side coloured by how far each point moved, with the session's
# fingertip paths, probes and force arrows (drawn 3x long: the press is 8% of the radius).
sphere_view=(--up z --azimuth 90 --elevation 10)
./build/tools/sculpt render data/sphere_3203.ply --out out/sphere_before.png "${sphere_view[@]}" --size 640x560
./build/tools/sculpt render out/sphere_sculpted.ply --out out/sphere_after.png "${sphere_view[@]}" --size 640x560
./build/tools/sculpt render out/sphere_sculpted.ply --compare data/sphere_3203.ply --log out/sphere-squeeze.lcmlog \
  --arrow-scale 3 --views 3 "${sphere_view[@]}" --size 400x360 --out out/sphere_compare.png
echo "main: the sculpted model is out/sphere_sculpted.ply, its log out/sphere-squeeze.lcmlog, the summary out/sphere_sculpted.json, pictures out/sphere_{before,after,compare}.png"
