#!/usr/bin/env bash
# sculpt report --quick (the bundled sphere's press) against facts that do not come from the
# report's own code:
#  - float against double: the float row's largest error lies between 1e-8 and 1e-4 of the
#    largest displacement (float carries 24 bits: about 6e-8 of a coordinate of the unit
#    sphere, far below the 0.08 press and far above double's 1e-16);
#  - fast 1/r (the processor's estimate, 2^-21 relative): its error against double is below
#    twice float's own (it adds one estimate's error, a few float roundings, to float's);
#  - the region: its error does not grow as the region grows, and at 40 spacings (2.4 on the
#    unit sphere of spacing 0.06: the whole model, diameter 2, and its band) it is that of float;
#  - the Pareto front: the non-dominated rows, computed here from the CSV, are exactly the rows
#    the report marks;
#  - the files: report.md, report.csv, a PNG, and a session row per reduced ratio;
#  - a log: the session recorded by `sculpt run` (real time) and given as a log is re-run from
#    its own glove samples: twice the same steps and float errors, and float's bound holds.
# Usage: SCULPT=path/to/sculpt sculpt_report_test.sh   (ctest sets SCULPT)
set -uo pipefail
: "${SCULPT:?set SCULPT to the sculpt binary}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

start=$(date +%s)
"$SCULPT" report --quick --out "$work/out" --json "$work/report.json" >"$work/table" 2>"$work/err"
status=$?
seconds=$(( $(date +%s) - start ))
cat "$work/table"
[ "$status" -eq 0 ] || { echo "FAIL sculpt report --quick exited $status"; cat "$work/err"; exit 1; }
# Refusals: one line on stderr and exit 2 for a missing session, a scene whose glove is not
# simulated (nothing to record), and no --out.
refuse() {
  local want="$1"; shift
  "$SCULPT" report "$@" >"$work/refused.out" 2>"$work/refused.err"
  local got=$?
  if [ "$got" -ne 2 ] || [ "$(wc -l <"$work/refused.err")" -ne 1 ] || ! grep -q -- "$want" "$work/refused.err"; then
    echo "FAIL sculpt report $*: exit $got (want 2), stderr:"; cat "$work/refused.err"; exit 1
  fi
}
refuse "give a scene" --out "$work/x"
cat >"$work/serial.toml" <<SCENE
[model]
path = "$(cd "$(dirname "$0")/../../data" && pwd)/sphere_3203.ply"
[glove]
backend = "serial"
fingers = ["index"]
[glove.serial]
device = "/dev/null"
SCENE
refuse "simulated glove" "$work/serial.toml" --out "$work/x"
refuse "out" --quick

# The quick scene with a durable log, run as a user would (4 s of real time: the 2.2 s script, the set-up and a margin), then reported.
scene_dir="$(dirname "$0")/../../tools/report"
sed "s|\.\./\.\./data/|$(cd "$scene_dir/../../data" && pwd)/|" "$scene_dir/quick-sphere.toml" >"$work/logged.toml"
printf '\n[output]\nlog = "logged.lcmlog"\n' >>"$work/logged.toml"
"$SCULPT" run "$work/logged.toml" --quiet --duration 4 >"$work/run.out" 2>&1 || { echo "FAIL sculpt run"; cat "$work/run.out"; exit 1; }
for k in 1 2; do
  "$SCULPT" report "$work/logged.lcmlog" --out "$work/from-log$k" --json "$work/from-log$k.json" >/dev/null \
    2>"$work/log.err" || { echo "FAIL sculpt report on the log"; cat "$work/log.err"; exit 1; }
done
python3 - "$work/out" "$seconds" "$work/from-log1.json" "$work/from-log2.json" <<'PY'
import csv, json, os, sys
out, seconds = sys.argv[1], int(sys.argv[2])
bad = []
# A log is re-run from its own samples: twice the same steps and the same float errors, bit for
# bit. (Not the script's steps: a loaded real-time run hands the loop some samples in pairs,
# and the station takes the newest.)
first, second = (json.load(open(p)) for p in sys.argv[3:5])
row = lambda doc, name: next(r for r in doc["rows"] if r["name"] == name)
print(f"log: {first['steps']} steps, then {second['steps']}")
if first["steps"] == 0 or first["steps"] != second["steps"]:
    bad.append(f"the log re-ran {first['steps']} steps, then {second['steps']}")
elif row(first, "float")["max_error"] != row(second, "float")["max_error"]:
    bad.append("the same log gave two float errors")
else:
    f1 = row(first, "float")
    if not (1e-8 <= f1["max_error"] / f1["max_displacement"] <= 1e-4):
        bad.append("from the log, the float row's error is not within [1e-8, 1e-4] of the largest displacement")
rows = list(csv.DictReader(open(os.path.join(out, "report.csv"))))
by = {r["name"]: r for r in rows}
num = lambda r, k: float(r[k])

f = by.get("float")
if f is None:
    bad.append("no float row")
else:
    ratio = num(f, "max_error") / num(f, "max_displacement")
    print(f"float: max error {num(f, 'max_error'):.3g}, largest displacement {num(f, 'max_displacement'):.3g}, ratio {ratio:.3g}")
    if not (1e-8 <= ratio <= 1e-4):
        bad.append(f"float row's error is {ratio:.3g} of the largest displacement, not within [1e-8, 1e-4]")

fast = by.get("fast 1/r")
if fast is None:
    bad.append("no fast 1/r row")
elif f is not None:
    print(f"fast 1/r: max error {num(fast, 'max_error'):.3g} against float's {num(f, 'max_error'):.3g}")
    if not (num(fast, "max_error") <= 2.0 * num(f, "max_error")):
        bad.append(f"fast 1/r's error {num(fast, 'max_error'):.3g} is not below twice float's {num(f, 'max_error'):.3g}")

regions = sorted((float(r["name"].split()[1]), num(r, "mean_error")) for r in rows
                 if r["group"] == "region" and r["name"] != "region auto")
if [k for k, _ in regions] != [5.0, 10.0, 20.0, 40.0]:
    bad.append(f"region rows at {[k for k, _ in regions]} spacings, not 5, 10, 20, 40")
elif f is not None:
    floor = num(f, "mean_error")  # float's own rounding: the only slack allowed
    for (k0, e0), (k1, e1) in zip(regions, regions[1:]):
        print(f"region {k0:g} sp: {e0:.3g}  ->  {k1:g} sp: {e1:.3g}")
        if e1 > e0 + floor:
            bad.append(f"region error grows from {e0:.3g} at {k0:g} sp to {e1:.3g} at {k1:g} sp")
    e40 = regions[-1][1]
    if not (0.5 * floor <= e40 <= 2.0 * floor):
        bad.append(f"region covering the sphere has error {e40:.3g}, not that of float alone ({floor:.3g})")

plotted = [r for r in rows if r["plotted"] == "1"]
front = set()
for r in plotted:
    t, e = num(r, "median_ms"), num(r, "mean_error")
    dominated = any(num(o, "median_ms") <= t and num(o, "mean_error") <= e and
                    (num(o, "median_ms") < t or num(o, "mean_error") < e) for o in plotted if o is not r)
    if not dominated:
        front.add(r["name"])
marked = {r["name"] for r in rows if r["pareto"] == "1"}
print(f"front: {sorted(front)}")
if not front:
    bad.append("empty Pareto front")
if front != marked:
    bad.append(f"the report marks {sorted(marked)} as the front, the CSV's own front is {sorted(front)}")

reduced = [r for r in rows if r["name"].startswith("reduced ")]
if len(reduced) != 4:
    bad.append(f"{len(reduced)} reduced-set rows, not 4")
for r in reduced:
    e = num(r, "mean_error")
    if not (0.0 < e < 0.05):
        bad.append(f"{r['name']}: mean error {e} at the session's end")

with open(os.path.join(out, "pareto.png"), "rb") as png:
    if png.read(8) != b"\x89PNG\r\n\x1a\n":
        bad.append("pareto.png is not a PNG")
md = open(os.path.join(out, "report.md")).read()
if "| float |" not in md or "pareto.png" not in md:
    bad.append("report.md lacks the float row or the plot")
if seconds >= 60:
    bad.append(f"--quick took {seconds} s (must stay under a minute)")
for b in bad:
    print("FAIL", b)
print(f"{len(rows)} rows in {seconds} s, {len(bad)} problems")
sys.exit(1 if bad else 0)
PY
