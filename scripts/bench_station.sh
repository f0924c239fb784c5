#!/usr/bin/env bash
# The station measured in real time (issue 10): two million points in the 1 kHz loop with the
# region sized to the budget, and the displacement worker on and off, each from a `sculpt run
# --json` summary, beside T(100k), the bare kernel's five-finger pass over the 100k dragon
# (bench/, Bare5/100250) measured in the same run: real time is absolute, T says how fast this
# machine was while it ran.
#
#   scripts/bench_station.sh            # 60 s per run; DURATION=10 for a quick look
#
# Needs a Release build in build/ (or BUILD=...) with deform_bench, and the scans
# (scripts/fetch_scans.sh). Writes its scenes, logs and summaries under out/bench/, and the
# generated spheres (2,000,000 and 100,000 points) under out/.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${BUILD:-$root/build}"
out="$root/out/bench"
duration="${DURATION:-60}"
sculpt="$build/tools/sculpt"
mkdir -p "$out"

die() { echo "bench_station: $*" >&2; exit 1; }
[ -x "$sculpt" ] || die "$sculpt not found: build first (Release)"
[ -x "$build/bench/deform_bench" ] || die "$build/bench/deform_bench not found: build first (Release)"
[ -f "$root/data/scans/dragon_100250.ply" ] || die "data/scans/dragon_100250.ply not found: scripts/fetch_scans.sh"

model="$root/out/sphere_2m.ply"
[ -f "$model" ] || "$sculpt" generate sphere --points 2000000 --out "$model"
# The same points in Z order (sculpt order): the generator's golden spiral stores a ball's
# points a ring apart, the scan order a region frame pays for.
ordered="$root/out/sphere_2m_z.ply"
[ -f "$ordered" ] || "$sculpt" order "$model" --out "$ordered"

# A scene variant in out/bench/: model and outputs made absolute, then the given sed edits.
variant() {  # name source.toml sed-expressions...
  local name="$1" source="$2"
  shift 2
  sed -e "s#\"\.\./#\"$root/#" -e "s#$root/out/[a-z0-9-]*\.\(ply\|lcmlog\|json\)\"#$out/$name.\1\"#" "$@" \
    "$root/scenes/$source" >"$out/$name.toml"
}
variant bench-2m-t1 bench-2m.toml
variant bench-2m-t2 bench-2m.toml -e 's/^mode = "push"$/mode = "push"\nthreads = 2/'
variant bench-2m-z1 bench-2m.toml -e 's#/out/sphere_2m\.ply"#/out/sphere_2m_z.ply"#'
# The worker's case, a global frame (every point moves) over 100k points, in a stroke that
# keeps colliding: one finger one spacing into a 100k-point sphere, circling its equator once
# every 10 s (a repeated press would meet only the dent the first one left).
circle="$root/out/sphere_100k.ply"
[ -f "$circle" ] || "$sculpt" generate sphere --points 100000 --out "$circle"
circle_scene() {  # threads
  python3 - "$circle" "$out" "$1" <<'PY'
import math, sys
model, out, threads = sys.argv[1], sys.argv[2], sys.argv[3]
keys = [(0.0, 1.2, 0.0, 0.0), (1.0, 0.99, 0.0, 0.0)]
for k in range(1, 6 * 36 + 1):  # six turns, 10 degrees a keyframe
    a = math.radians(10 * k)
    keys.append((1.0 + 10.0 * k / 36, 0.99 * math.cos(a), 0.99 * math.sin(a), 0.0))
frames = ", ".join(f"[{t:.4f}, {x:.6f}, {y:.6f}, {z:.1f}]" for t, x, y, z in keys)
name = f"sphere100k-circle-t{threads}"
print(f"""[model]
path = "{model}"
[material]
G = 3e7
nu = 0.45
[deform]
mode = "push"
threads = {threads}
[heuristic]
region = "global"
[glove]
backend = "sim"
fingers = ["index"]
[glove.sim]
rate_hz = 80
[[glove.sim.script]]
finger = "index"
keyframes = [{frames}]
[loop]
rate_hz = 1000
realtime = "try"
lock_memory = true
[output]
model = "{out}/{name}.ply"
log = "{out}/{name}.lcmlog"
json = "{out}/{name}.json"
""", file=open(f"{out}/{name}.toml", "w"))
PY
}
circle_scene 1
circle_scene 2

t_ms() {
  "$build/bench/deform_bench" --benchmark_filter='^Bare5/100250$' --benchmark_repetitions=5 \
    --benchmark_report_aggregates_only=true --benchmark_out="$out/t.json" --benchmark_out_format=json >/dev/null 2>&1
  python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print([b["cpu_time"] / 1000 for b in d["benchmarks"] if b["name"].endswith("_median")][0])' "$out/t.json"
}

t_before="$(t_ms)"
for name in bench-2m-t1 bench-2m-t2 bench-2m-z1 sphere100k-circle-t1 sphere100k-circle-t2; do
  echo "bench_station: $name, $duration s" >&2
  # --replace-log: each run's log is this script's own, read below and made again next time.
  "$sculpt" run "$out/$name.toml" --duration "$duration" --quiet --replace-log --json "$out/$name.json" \
    >"$out/$name.out" 2>&1 ||
    die "$name failed: see $out/$name.out"
done
t_after="$(t_ms)"

python3 - "$out" "$t_before" "$t_after" "$root/scripts" <<'PY'
import json, os, sys
out, t0, t1 = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
sys.path.insert(0, sys.argv[4])
import lcm_log  # the run's own log: a SCULPT_TICK record for every tick of half the period or more


def slow_ticks(log):
    """Ticks over the 1 ms budget, (with a collision, without one), from the run's log."""
    if not os.path.exists(log):
        return None
    types = lcm_log.load_types(lcm_log.default_types_dir())
    with_collision = without = 0
    for _, _, channel, m in lcm_log.decoded(log, types):
        if channel == "SCULPT_TICK" and m.tick_time_us > 1000.0:
            if m.collisions > 0:
                with_collision += 1
            else:
                without += 1
    return with_collision, without


print(f"T(100k) = {t0:.3f} ms before the runs, {t1:.3f} ms after (Bare5/100250, CPU median of 5)")
# "colliding frames": the deformation's own wall time in the frames with a collision, which
# tells a slow frame from a tick the VM held up (its host reports no steal time, so those show
# on the tick's CPU clock too).
print("| run | points | threads | ticks | frames | overruns | tick median | p99 | p99.9 | max | CPU p99.9 | CPU max | wake-up p99 | colliding frames | their p99.9 | their max | ticks over 1 ms (colliding / not) | region points | index rebuilds |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for name, points in [("bench-2m-t1", "2,000,000"), ("bench-2m-t2", "2,000,000"), ("bench-2m-z1", "2,000,000 (Z order)"),
                     ("sphere100k-circle-t1", "100,000"), ("sphere100k-circle-t2", "100,000")]:
    d = json.load(open(f"{out}/{name}.json"))
    h = d["tick_time"]
    c = d["tick_cpu_time"]
    f = d["collision_frame_time"]
    counts = slow_ticks(f"{out}/{name}.lcmlog")
    slow = "no log" if counts is None else f"{counts[0]} / {counts[1]}"
    threads = name[-1]
    print(f"| {name[:-3]} | {points} | {threads} | {d['ticks']} | {d['frames']} | {d['overruns']} | "
          f"{h['median_us']:.1f} us | {h['p99_us']:.0f} us | {h['p999_us']:.0f} us | {h['max_us']:.0f} us | "
          f"{c['p999_us']:.0f} us | {c['max_us']:.0f} us | "
          f"{d['wake_jitter']['p99_us']:.0f} us | {f['count']} | {f['p999_us']:.0f} us | {f['max_us']:.0f} us | "
          f"{slow} | {d['max_region_points']} | {d['index_rebuilds']} |")
PY
