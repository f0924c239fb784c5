#!/usr/bin/env bash
# sculpt check --quick as CI runs it: exit status 0, and every case in the JSON with its
# must-be-zero counts at zero (non_finite, probe_inside, passed_through: the judging oracle's,
# a closed mesh's where the case has one, else the PCA plane's), each oracle's own counts beside
# them, and the sphere's cases judged by its hull.
# Usage: SCULPT=path/to/sculpt sculpt_check_test.sh   (ctest sets SCULPT)
set -uo pipefail
: "${SCULPT:?set SCULPT to the sculpt binary}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

"$SCULPT" check --quick --json "$work/check.json" >"$work/table" 2>"$work/err"
status=$?
cat "$work/table"
python3 - "$work/check.json" "$status" "$work/filtered" "$SCULPT" <<'PY'
import json, sys
doc = json.load(open(sys.argv[1]))
status = int(sys.argv[2])
bad = []
cases = doc["cases"]
if not cases:
    bad.append("no cases in the JSON")
for c in cases:
    if "skipped" in c:
        print(f"skip {c['name']}: {c['skipped']}")
        continue
    for key in ("non_finite", "probe_inside", "passed_through"):
        if c[key] != 0:
            bad.append(f"{c['name']}: {key} = {c[key]}")
    for key in ("max_condition", "max_relative_residual", "max_displacement_ratio", "min_jacobian", "max_miss", "guards",
                "oracle", "pca_probe_inside", "pca_passed_through", "mesh_probe_inside", "mesh_passed_through"):
        if key not in c:
            bad.append(f"{c['name']}: no {key}")
    if c["group"] == "sphere_340_pushes" and c["oracle"] != "mesh":
        bad.append(f"{c['name']}: judged by {c['oracle']}, not the sphere's hull")
if doc["summary"]["cases"] != len(cases):
    bad.append("summary counts %d cases, the array holds %d" % (doc["summary"]["cases"], len(cases)))
if status != 0:
    bad.append(f"sculpt check --quick exited {status}")
# --case runs and counts only the cases it names; one that names none is a usage error (it
# printed the whole suite's count with nothing run, and exit 0).
names = [c["name"] for c in cases]
part = "previous_on_point"
chosen = [n for n in names if part in n]
import subprocess
with open(sys.argv[3], "w") as out:
    status = subprocess.run([sys.argv[4], "check", "--quick", "--case", part, "--json", sys.argv[3] + ".json"],
                            stdout=out, stderr=subprocess.DEVNULL).returncode
filtered = json.load(open(sys.argv[3] + ".json"))
if status != 0 or [c["name"] for c in filtered["cases"]] != chosen or filtered["summary"]["cases"] != len(chosen) \
        or not chosen or filtered["summary"]["case_filter"] != part:
    bad.append(f"check --case {part}: exit {status}, {filtered['summary']['cases']} counted, "
               f"{len(filtered['cases'])} run, {len(chosen)} named")
none = subprocess.run([sys.argv[4], "check", "--quick", "--case", "no_such_case"], capture_output=True, text=True)
last = none.stderr.strip().split("\n")[-1]
if none.returncode != 2 or not last.startswith("sculpt check: error: ") or \
        f"--case 'no_such_case' matches none of the {len(cases)} case names" not in last:
    bad.append(f"check --case no_such_case: exit {none.returncode}, stderr {none.stderr!r}")
for b in bad:
    print("FAIL", b)
print(f"{len(cases)} cases, {len(bad)} problems")
sys.exit(1 if bad else 0)
PY
