#!/usr/bin/env bash
# Build the libFuzzer targets (fuzz/CMakeLists.txt) in build-fuzz/ with clang, ASan and UBSan,
# and run each from its seeds in fuzz/seeds/. A failure leaves the input that caused it in
# build-fuzz/findings/ and exits 1, naming the target and the file.
#
#   scripts/fuzz.sh                 each target for 60 s, from a random seed (a search)
#   scripts/fuzz.sh --seconds N     each target for N s
#   scripts/fuzz.sh --check         each target on a fixed number of inputs from the seeds alone
#                                   and libFuzzer's seed 1 (the test command's pass, about 2.5
#                                   minutes with the build). Nearly the same search each run, not
#                                   bit for bit: coverage feedback hashes addresses, and two runs
#                                   here kept 178 and 176 inputs of 50,000.
# New inputs go to build-fuzz/corpus/<target>/, kept between searches, so that one goes on from
# where the last stopped; --check uses a corpus of its own, emptied first.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd -P)"
cd "$root"

mode=search seconds=60
while [[ $# -gt 0 ]]; do
  case "$1" in
    --seconds) mode=search seconds="$2"; shift 2 ;;
    --check) mode=check; shift ;;
    *) echo "fuzz: unknown argument '$1' (--seconds N or --check)" >&2; exit 2 ;;
  esac
done
command -v clang++ >/dev/null || { echo "fuzz: clang++ not found (scripts/setup.sh installs it)" >&2; exit 1; }

jobs="$(nproc)"
# Warnings as errors, as in every pass, less two that only clang raises on this code: GCC's
# pragmas name warning groups clang does not know, and clang notes that the weight solver's
# 8-lane vector helpers would pass differently with AVX-512 (internal functions, one ABI).
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_COMPILER=clang \
  -DCMAKE_CXX_COMPILER=clang++ -DSCULPT_FUZZ=ON -DSCULPT_NATIVE=OFF -DSCULPT_BUILD_TESTS=OFF \
  -DSCULPT_BUILD_BENCHMARKS=OFF -DCMAKE_CXX_FLAGS="-Werror -Wno-unknown-warning-option -Wno-psabi" >/dev/null
targets=(fuzz_read_ply fuzz_read_off fuzz_read_xyz fuzz_scene fuzz_log_replay fuzz_transfer)
cmake --build build-fuzz -j"$jobs" --target "${targets[@]}" make_log_seed

seeds="build-fuzz/seeds"
mkdir -p "$seeds/log" build-fuzz/findings
build-fuzz/fuzz/make_log_seed "$seeds/log/session.lcmlog"
seed_dirs() {
  case "$1" in
    fuzz_read_ply) echo fuzz/seeds/ply ;;
    fuzz_read_off) echo fuzz/seeds/off ;;
    fuzz_read_xyz) echo fuzz/seeds/xyz ;;
    fuzz_scene) echo scenes ;;  # the bundled scenes: every table and most keys
    fuzz_log_replay) echo "$seeds/log" ;;
    fuzz_transfer) echo "" ;;   # structured input: any bytes make records
  esac
}
# --check: inputs per target, each about 10 s here (the log target reads a file per input).
check_runs() {
  case "$1" in
    fuzz_read_ply | fuzz_read_off | fuzz_read_xyz) echo 200000 ;;
    fuzz_scene) echo 100000 ;;
    fuzz_log_replay) echo 15000 ;;
    fuzz_transfer) echo 40000 ;;
  esac
}

export ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1
for target in "${targets[@]}"; do
  corpus="build-fuzz/corpus/$target"
  [[ "$mode" == check ]] && corpus="build-fuzz/check-corpus/$target" && rm -rf "$corpus"
  mkdir -p "$corpus"
  if [[ "$mode" == check ]]; then
    args=(-seed=1 -runs="$(check_runs "$target")")
  else
    args=(-max_total_time="$seconds")
  fi
  start=$SECONDS
  # shellcheck disable=SC2046 # seed_dirs gives zero or one folder, split on purpose
  if ! "build-fuzz/fuzz/$target" "${args[@]}" -max_len=16384 -timeout=10 -rss_limit_mb=4096 \
    -artifact_prefix="build-fuzz/findings/$target-" "$corpus" $(seed_dirs "$target") \
    >"build-fuzz/$target.log" 2>&1; then
    tail -n 40 "build-fuzz/$target.log"
    echo "fuzz: $target failed; the input is in build-fuzz/findings/ (log: build-fuzz/$target.log)"
    exit 1
  fi
  echo "fuzz: $target: $(grep -Eo '^Done [0-9]+ runs' "build-fuzz/$target.log" | grep -Eo '[0-9]+') inputs in $((SECONDS - start)) s, no finding"
done
