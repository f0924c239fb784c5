#!/usr/bin/env bash
# Every test: set up a fresh Debian 12, build with warnings as errors, run the suite, build and
# run it again in the minimal configuration (no LCM, USB or CAN), check the format and names,
# run the libFuzzer targets on a fixed set of inputs, then rebuild under AddressSanitizer +
# UndefinedBehaviorSanitizer and run the suite again (the parsers' fuzz tests are the point of
# that pass), then once more under ThreadSanitizer.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
bash scripts/setup.sh
jobs="$(nproc)"
# Each pass says how long it took, so that the command's 50-minute budget can be watched.
phase_start=$SECONDS
phase_done() {
  echo "test: $1 passed in $(((SECONDS - phase_start) / 60)) min $(((SECONDS - phase_start) % 60)) s"
  phase_start=$SECONDS
}

# The tests write into temporary folders and the build trees, never into the checkout: a user's
# out/ holds their sessions (tests once ran the bundled scene, whose log is out/'s). Checked
# after each pass against a stamp made before the first.
# Python's bytecode caches would land beside the scripts the tests import (scripts/__pycache__).
export PYTHONDONTWRITEBYTECODE=1
started_stamp="$(mktemp)"
checkout_untouched() {
  local touched
  touched="$(find "$root" -mindepth 1 \( -path "$root/build*" -o -path "$root/.git" \) -prune -o -newer "$started_stamp" -print)"
  if [[ -n $touched ]]; then
    echo "test: the tests wrote into the checkout:"
    echo "$touched"
    exit 1
  fi
}

# The test programs and the command line as unity builds (SCULPT_UNITY_DRIVERS: the top-level
# CMakeLists.txt says why); the libraries file by file, as the benchmarks time them.
# scripts/main.sh configures build/ alike (the shared_build_tree test), so the two share it.
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS=-Werror -DSCULPT_UNITY_DRIVERS=ON >/dev/null
cmake --build build -j"$jobs"
(cd build && ctest --output-on-failure -j"$jobs")
checkout_untouched
phase_done "Release build and tests"

# The minimal configuration: no LCM, USB or CAN. It must build clean, refuse what needs a
# left-out part with a clear message, and pass every test that does not need one (those skip
# or are compiled out, saying why). The deform library's tests are left to the first pass: no
# option reaches that library, which both passes compile with the same flags.
# The passes after the first compile the test programs and the command line's own sources at
# -O0 (SCULPT_DRIVER_FLAGS; CMakeLists.txt says why) and the libraries as their pass says.
# They build every target as a unity build (CMake joins each target's files into batches of
# eight): the headers (GoogleTest, Eigen, LCM) are read once per batch, not once per file, which
# took the three passes' builds from about 20 minutes to 8 here. A helper with the same name in
# two files of one target stops a unity build (a redefinition): give file-local helpers names of
# their own, or share them from a header.
unity="-DCMAKE_UNITY_BUILD=ON"
cmake -S . -B build-minimal -G Ninja -DCMAKE_BUILD_TYPE=Release -DSCULPT_WITH_LCM=OFF -DSCULPT_WITH_USB=OFF \
  -DSCULPT_WITH_CAN=OFF -DSCULPT_BUILD_BENCHMARKS=OFF -DSCULPT_BUILD_DEFORM_TESTS=OFF -DSCULPT_GUEST_TESTS=OFF \
  -DCMAKE_CXX_FLAGS=-Werror -DSCULPT_DRIVER_FLAGS=-O0 "$unity" >/dev/null
cmake --build build-minimal -j"$jobs"
(cd build-minimal && ctest --output-on-failure -j"$jobs")
checkout_untouched
phase_done "minimal configuration"

# The house style (.clang-format) and naming (.clang-tidy), over every source file.
git ls-files -z '*.cpp' '*.hpp' | xargs -0 clang-format --dry-run --Werror
# clang-tidy over every file the Release build compiles, from a compile command per file: a
# tree configured as the Release pass but file by file (that pass's unity batches would hide the
# files), with the LCM headers it generates and builds nothing else. GCC's pragmas and warning
# groups are unknown to clang and not this check's business.
cmake -S . -B build-tidy -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS=-Werror >/dev/null
cmake --build build-tidy --target sculpt_lcm_generate >/dev/null
run-clang-tidy -p build-tidy -quiet -j "$jobs" -extra-arg=-Wno-unknown-pragmas -extra-arg=-Wno-unknown-warning-option \
  "^$root/(base|deform|hal|logging|lcmtypes|rt|render|tools|tests)/" >/tmp/sculpt-tidy.log 2>&1 ||
  { grep -E "(error|warning):" /tmp/sculpt-tidy.log; echo "test: clang-tidy found names off the house style"; exit 1; }
phase_done "format and naming checks"

# libFuzzer over the model readers, the scene parser, the log as replay reads it and the
# transfer (scripts/fuzz.sh, under ASan and UBSan): a fixed number of inputs from the committed
# seeds and a fixed random seed, so that each run makes nearly the same search, long enough to
# find the log check's bug again in seconds. Its own tree, built by clang.
bash scripts/fuzz.sh --check
checkout_untouched
phase_done "libFuzzer regression check"

# The sanitizer passes keep line tables only (-g1, not -g): a report still names the file and
# line of each frame, and files compile 13 to 37 % faster (three of the heaviest, timed here).
cmake -S . -B build-sanitize -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG=-g1 -DSCULPT_SANITIZE=ON \
  -DSCULPT_NATIVE=OFF -DSCULPT_BUILD_BENCHMARKS=OFF -DCMAKE_CXX_FLAGS="-O1 -Werror" -DSCULPT_DRIVER_FLAGS=-O0 \
  "$unity" >/dev/null
cmake --build build-sanitize -j"$jobs"
(cd build-sanitize && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j"$jobs")
checkout_untouched
phase_done "AddressSanitizer + UndefinedBehaviorSanitizer"

# ThreadSanitizer over the whole suite but the deform tests that stay on one thread (the
# station, HIL and log tests are what it is for; tests/CMakeLists.txt says which deform files it
# builds): reports fail the test. The suppressions cover only uninstrumented third-party libraries (LCM, GLib, Mesa),
# each entry commented with why.
cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG=-g1 -DSCULPT_SANITIZE_THREAD=ON \
  -DSCULPT_NATIVE=OFF -DSCULPT_BUILD_BENCHMARKS=OFF -DCMAKE_CXX_FLAGS="-O1 -Werror" -DSCULPT_DRIVER_FLAGS=-O0 \
  "$unity" >/dev/null
cmake --build build-tsan -j"$jobs"
(cd build-tsan && TSAN_OPTIONS="suppressions=$root/tests/tsan_suppressions.txt second_deadlock_stack=1" \
  ctest --output-on-failure -j"$jobs")
checkout_untouched
phase_done "ThreadSanitizer"
echo "test: everything passed in $((SECONDS / 60)) min $((SECONDS % 60)) s"
