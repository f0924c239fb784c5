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
python3 - "$work/check.json" "$status" <<'PY'
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
for b in bad:
    print("FAIL", b)
print(f"{len(cases)} cases, {len(bad)} problems")
sys.exit(1 if bad else 0)
PY
