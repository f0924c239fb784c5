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
# (scripts/fetch_scans.sh). Writes its scenes, logs and summaries under out/bench/.
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

# A scene variant in out/bench/: model and outputs made absolute, then the given sed edits.
variant() {  # name source.toml sed-expressions...
  local name="$1" source="$2"
  shift 2
  sed -e "s#\"\.\./#\"$root/#" -e "s#$root/out/[a-z0-9-]*\.\(ply\|lcmlog\|json\)\"#$out/$name.\1\"#" "$@" \
    "$root/scenes/$source" >"$out/$name.toml"
}
variant bench-2m-t1 bench-2m.toml
variant bench-2m-t2 bench-2m.toml -e 's/^mode = "push"$/mode = "push"\nthreads = 2/'
# The dragon with every point moving (a global frame, the worker's case), the press repeated.
dragon=(-e 's/^region = "auto".*/region = "global"/' -e 's/^duration_s = .*/repeat = true/')
variant dragon-global-t1 dragon-press.toml "${dragon[@]}"
variant dragon-global-t2 dragon-press.toml "${dragon[@]}" -e 's/^mode = "push"$/mode = "push"\nthreads = 2/'

t_ms() {
  "$build/bench/deform_bench" --benchmark_filter='^Bare5/100250$' --benchmark_repetitions=5 \
    --benchmark_report_aggregates_only=true --benchmark_out="$out/t.json" --benchmark_out_format=json >/dev/null 2>&1
  python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print([b["cpu_time"] / 1000 for b in d["benchmarks"] if b["name"].endswith("_median")][0])' "$out/t.json"
}

t_before="$(t_ms)"
for name in bench-2m-t1 bench-2m-t2 dragon-global-t1 dragon-global-t2; do
  echo "bench_station: $name, $duration s" >&2
  "$sculpt" run "$out/$name.toml" --duration "$duration" --quiet --json "$out/$name.json" >"$out/$name.out" 2>&1 ||
    die "$name failed: see $out/$name.out"
done
t_after="$(t_ms)"

python3 - "$out" "$t_before" "$t_after" <<'PY'
import json, sys
out, t0, t1 = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
print(f"T(100k) = {t0:.3f} ms before the runs, {t1:.3f} ms after (Bare5/100250, CPU median of 5)")
print("| run | points | threads | ticks | frames | overruns | tick median | p99 | p99.9 | max | region points | index rebuilds |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for name, points in [("bench-2m-t1", "2,000,000"), ("bench-2m-t2", "2,000,000"),
                     ("dragon-global-t1", "100,250"), ("dragon-global-t2", "100,250")]:
    d = json.load(open(f"{out}/{name}.json"))
    h = d["tick_time"]
    threads = name[-1]
    print(f"| {name[:-3]} | {points} | {threads} | {d['ticks']} | {d['frames']} | {d['overruns']} | "
          f"{h['median_us']:.1f} us | {h['p99_us']:.0f} us | {h['p999_us']:.0f} us | {h['max_us']:.0f} us | "
          f"{d['max_region_points']} | {d['index_rebuilds']} |")
PY
