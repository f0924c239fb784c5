#!/usr/bin/env python3
"""Two deform_bench binaries compared the way issue 10 asks: alternated rounds, each frame over
T(100k) measured in the same run, medians over the rounds.

This machine's speed moves by up to 1.3x within minutes, so a change is judged by the median of
(frame / that run's Bare5/100250) over several rounds in which the two binaries take turns (and
take turns going first), never by one run of each.

    scripts/bench_ab.py OLD NEW 'dragon_100250.*/region20/float/5' --rounds 3

Copy the binaries out of the build tree first (cp build/bench/deform_bench /tmp/bench_new):
the two must not change under the rounds. Prints each benchmark's ratio per round for both,
their medians and the change, and the time medians in microseconds (wall time for rows timed by
the wall clock, CPU time for the rest).
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

YARDSTICK = "Bare5/100250"


WALL_SUFFIXES = ("/manual_time", "/real_time")


def run(binary, pattern, repetitions, min_time):
    """One run: {benchmark name: (median time in microseconds, over the yardstick's)}.

    A row timed by the wall clock (deform_bench's frames: by hand, or on two threads) is over the
    yardstick's wall time, any other over its CPU time. Names lose the time-type suffix, so that
    binaries from before and after the frames were timed by hand compare."""
    with tempfile.NamedTemporaryFile(suffix=".json") as out:
        command = [
            binary,
            f"--benchmark_filter=({pattern})|^{YARDSTICK}$",
            f"--benchmark_repetitions={repetitions}",
            f"--benchmark_min_time={min_time}",
            "--benchmark_report_aggregates_only=true",
            # deform_bench's console shows its own ratio table; the JSON goes to a file.
            f"--benchmark_out={out.name}",
            "--benchmark_out_format=json",
        ]
        done = subprocess.run(command, capture_output=True, text=True, check=False)
        if done.returncode != 0:
            sys.exit(f"bench_ab: {binary} failed ({done.returncode}): {done.stderr.strip()[:400]}")
        report = json.load(out)
    scale = {"ns": 1e-3, "us": 1.0, "ms": 1e3, "s": 1e6}
    medians = {}  # name: (cpu, real, wall)
    for b in report["benchmarks"]:
        # A row that skipped itself (a scan not fetched, a finger that missed) has no aggregates.
        if b.get("error_occurred"):
            sys.exit(f"bench_ab: {binary}: {b['run_name']}: {b.get('error_message', 'error')}")
        if b.get("aggregate_name") == "median":
            name, wall = b["run_name"], False
            for suffix in WALL_SUFFIXES:
                if name.endswith(suffix):
                    name, wall = name[: -len(suffix)], True
            unit = scale[b["time_unit"]]
            medians[name] = (b["cpu_time"] * unit, b["real_time"] * unit, wall)
    if YARDSTICK not in medians:
        sys.exit(f"bench_ab: {binary} ran no {YARDSTICK}")
    t_cpu, t_real, _ = medians[YARDSTICK]
    return {
        name: ((real if wall else cpu), (real / t_real if wall else cpu / t_cpu))
        for name, (cpu, real, wall) in medians.items()
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("old")
    parser.add_argument("new")
    parser.add_argument("pattern", help="a --benchmark_filter regex (the yardstick is added)")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--repetitions", type=int, default=5)
    parser.add_argument("--min-time", type=float, default=0.2)
    args = parser.parse_args()
    if args.rounds < 1 or args.repetitions < 1:
        sys.exit("bench_ab: --rounds and --repetitions must be at least 1")
    for binary in (args.old, args.new):
        if not (os.path.isfile(binary) and os.access(binary, os.X_OK)):
            sys.exit(f"bench_ab: {binary} is not an executable file")

    runs = {"old": [], "new": []}
    for r in range(args.rounds):
        order = ("old", "new") if r % 2 == 0 else ("new", "old")
        for which in order:
            runs[which].append(run(getattr(args, which), args.pattern, args.repetitions, args.min_time))
            print(f"round {r + 1}/{args.rounds}: {which} done", file=sys.stderr)

    names = [n for n in runs["old"][0] if n != YARDSTICK and all(n in m for m in runs["old"] + runs["new"])]
    if not names:
        sys.exit("bench_ab: the pattern matched no benchmark that both binaries ran")
    t = {w: [m[YARDSTICK][0] for m in runs[w]] for w in runs}
    print(f"T = {YARDSTICK}, CPU time: old {' '.join(f'{x:.0f}' for x in t['old'])} us, "
          f"new {' '.join(f'{x:.0f}' for x in t['new'])} us")
    print("| benchmark | old / T per round | new / T per round | old median | new median | change | "
          "old us | new us |")
    print("| --- | --- | --- | ---: | ---: | ---: | ---: | ---: |")
    for n in names:
        ratio = {w: [m[n][1] for m in runs[w]] for w in runs}
        old, new = statistics.median(ratio["old"]), statistics.median(ratio["new"])
        micro = {w: statistics.median(m[n][0] for m in runs[w]) for w in runs}
        print(f"| {n} | {' '.join(f'{x:.3f}' for x in ratio['old'])} | {' '.join(f'{x:.3f}' for x in ratio['new'])} "
              f"| {old:.3f} T | {new:.3f} T | {100 * (new / old - 1):+.1f} % | {micro['old']:.1f} | {micro['new']:.1f} |")


if __name__ == "__main__":
    main()
