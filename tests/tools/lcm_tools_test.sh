#!/usr/bin/env bash
# LCM's own tools and the project's scripts against a real station run (issue 13):
#  - a Java program on Debian's lcm.jar and the generated sculpt_lcm_types.jar (the classes
#    lcm-spy loads) decodes every channel live from a running station and from its durable log;
#  - scripts/lcm_log.py's counts and values match the station's JSON summary and the Java
#    reader, and it reports a cut log with the byte offset;
#  - scripts/plot_session.py draws the session; scripts/spy.sh starts lcm-spy on Java 17 under
#    Xvfb and finds every type.
# Usage: SCULPT=… SOURCE=… BUILD=… lcm_tools_test.sh   (ctest sets them). Exit 77: skipped.
set -uo pipefail
: "${SCULPT:?}" "${SOURCE:?}" "${BUILD:?}"
types_jar="$BUILD/lcmtypes/sculpt_lcm_types.jar"
lcm_jar=/usr/share/java/lcm.jar
py=/usr/bin/python3  # Debian's, where python3-matplotlib is
for need in "$types_jar" "$lcm_jar" /usr/share/java/jchart2d.jar; do
  [[ -f "$need" ]] || { echo "SKIP: $need not found (liblcm-java, libjchart2d-java and a JDK: scripts/setup.sh)"; exit 77; }
done
command -v javac >/dev/null || { echo "SKIP: no javac"; exit 77; }
"$py" -c 'import matplotlib' 2>/dev/null || { echo "SKIP: no python3-matplotlib"; exit 77; }

work="$(mktemp -d)"
trap 'kill $(jobs -p) 2>/dev/null; rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
pass() { echo "ok: $*"; }

url="udpm://239.255.76.67:$((21000 + $$ % 20000))?ttl=0"
sed -e "s|\.\./data/|$SOURCE/data/|; s|\.\./out/|$work/|" "$SOURCE/scenes/sphere-press.toml" >"$work/press.toml"
cat >>"$work/press.toml" <<TOML

[lcm]
url = "$url"
publish = true

[haptic]
sink = "lcm"
max_force = 4.0

[haptic.lcm]
url = "$url"
TOML

javac -nowarn -cp "$lcm_jar:$types_jar" -d "$work" "$SOURCE/tests/java/DecodeSculptLcm.java" || { echo "FAIL: javac"; exit 1; }
java_run() { java -Djava.net.preferIPv4Stack=true -cp "$lcm_jar:$types_jar:$work" DecodeSculptLcm "$@"; }

# Live: the decoder listens first (a late subscriber misses messages), then the station runs.
java_run live "$url" 20 >"$work/live.txt" 2>"$work/live.err" &
decoder=$!
for _ in $(seq 100); do grep -q listening "$work/live.txt" 2>/dev/null && break; sleep 0.1; done
"$SCULPT" run "$work/press.toml" --duration 3.6 --quiet >"$work/run.txt" 2>&1 || fail "sculpt run: $(cat "$work/run.txt")"
wait "$decoder"
live_status=$?
cat "$work/live.err"
java_run log "$work/sphere-press.lcmlog" >"$work/log.txt" 2>"$work/log.err"
log_status=$?
cat "$work/log.err"
"$SOURCE/scripts/lcm_log.py" "$work/sphere-press.lcmlog" --types "$BUILD/lcmtypes/python" >"$work/py.json" ||
  fail "lcm_log.py on the whole log"

"$py" - "$work/sphere-press.json" "$work/live.txt" "$live_status" "$work/log.txt" "$log_status" "$work/py.json" <<'PY' || failures=$((failures + 1))
import json, sys
summary = json.load(open(sys.argv[1]))
def counts(path):
    out = {}
    for line in open(path):
        parts = line.split()
        if len(parts) == 2 and parts[0] != "listening":
            out[parts[0]] = int(parts[1])
    return out
live, live_status = counts(sys.argv[2]), int(sys.argv[3])
logged, log_status = counts(sys.argv[4]), int(sys.argv[5])
py = json.load(open(sys.argv[6]))
log = summary["recording"]["log"]
expected = {"SCULPT_SESSION": 1, "SCULPT_GLOVE": log["glove_samples"], "SCULPT_FINGERTIP": log["fingertips"],
            "SCULPT_TICK": log["ticks"], "SCULPT_COLLISION": log["collisions"], "SCULPT_HAPTIC": log["haptic"],
            "SCULPT_CHECK": log["checks"]}
bad = []
def check(ok, what):
    print(("ok: " if ok else "FAIL: ") + what)
    if not ok: bad.append(what)
check(all(v > 0 for v in expected.values()), f"the station recorded every channel: {expected}")
check(log_status == 0 and logged.get("undecodable") == 0, "the Java classes decode every event of the durable log")
for channel, n in expected.items():
    check(logged.get(channel) == n, f"Java reads {channel} x {logged.get(channel)} from the log, the summary says {n}")
    check(py["channels"].get(channel) == n, f"lcm_log.py reads {channel} x {py['channels'].get(channel)}, the summary says {n}")
check(expected["SCULPT_TICK"] + log["ticks_left_out"] == summary["ticks"] and log["ticks_left_out"] > 0
      and expected["SCULPT_COLLISION"] == summary["collisions"],
      "the log's ticks (with the quiet ones it left out) and collisions are the run's")
check(py["collisions_per_finger"] == summary["collisions_per_finger"],
      f"collisions per finger {py['collisions_per_finger']} as the summary's {summary['collisions_per_finger']}")
check(0 < py["peak_haptic_force"] <= 4.0 + 1e-6, f"peak haptic force {py['peak_haptic_force']:.6g} N, at most the scene's 4")
check(py["damage"] is None, "the complete log has no damage")
# Live over UDP: what was published is decoded; UDP may drop a few on a loaded machine.
check(live_status == 0 and live.get("undecodable") == 0, "the Java classes decode every live message")
expected["SCULPT_TICK"] = summary["ticks"]  # the live channel carries every tick
for channel in ("SCULPT_TICK", "SCULPT_COLLISION", "SCULPT_FINGERTIP", "SCULPT_HAPTIC"):
    n = live.get(channel, 0)
    check(0 < n <= expected[channel] and n >= 0.9 * expected[channel],
          f"live {channel}: {n} of {expected[channel]} decoded")
sys.exit(1 if bad else 0)
PY

# A log cut inside its last event, as a crash leaves it: every complete event, and the offset.
size=$(stat -c %s "$work/sphere-press.lcmlog")
head -c $((size - 7)) "$work/sphere-press.lcmlog" >"$work/cut.lcmlog"
"$SOURCE/scripts/lcm_log.py" "$work/cut.lcmlog" --types "$BUILD/lcmtypes/python" >"$work/cut.json" || fail "lcm_log.py on a cut log"
"$py" - "$work/py.json" "$work/cut.json" <<'PY' && pass "a cut log: every complete event read, the cut named by offset" || fail "cut log"
import json, sys
whole, cut = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
assert cut["damage"] is not None and "byte offset" in cut["damage"]["what"], cut["damage"]
assert sum(cut["channels"].values()) == sum(whole["channels"].values()) - 1, (cut["channels"], whole["channels"])
PY
# The log's checks, read by Python too: every event of the whole log checked and matching; a
# byte changed in a collision's payload afterwards is named by its offset.
"$py" - "$work/sphere-press.lcmlog" "$work/flipped.lcmlog" "$work/flipped.expect" <<'PY'
import struct, sys
data = bytearray(open(sys.argv[1], 'rb').read())
pos = 0
while pos < len(data):
    _, _, _, cl, dl = struct.unpack('>IqqiI', data[pos:pos + 28])
    if data[pos + 28:pos + 28 + cl] == b'SCULPT_COLLISION':
        data[pos + 28 + cl + dl - 1] ^= 1
        break
    pos += 28 + cl + dl
open(sys.argv[2], 'wb').write(bytes(data))
open(sys.argv[3], 'w').write(str(pos))
PY
"$SOURCE/scripts/lcm_log.py" "$work/flipped.lcmlog" --types "$BUILD/lcmtypes/python" >"$work/flipped.json" || fail "lcm_log.py on a flipped log"
"$py" - "$work/py.json" "$work/flipped.json" "$(cat "$work/flipped.expect")" <<'PY' && pass "lcm_log.py reads the log's checks: all match, and a changed byte is named" || fail "lcm_log.py checks"
import json, sys
whole, flipped, at = json.load(open(sys.argv[1])), json.load(open(sys.argv[2])), int(sys.argv[3])
events = sum(n for c, n in whole["channels"].items() if c != "SCULPT_CHECK")
assert whole["checks"] == {"checked": events, "failed": [], "unchecked": 0}, (whole["checks"], events)
assert [f["offset"] for f in flipped["checks"]["failed"]] == [at], flipped["checks"]
PY
printf 'not a log at all' >"$work/junk.lcmlog"
"$SOURCE/scripts/lcm_log.py" "$work/junk.lcmlog" --types "$BUILD/lcmtypes/python" >/dev/null 2>"$work/junk.err" &&
  fail "lcm_log.py accepted bytes that are not a log" ||
  { grep -q "not an LCM log" "$work/junk.err" && pass "bytes that are not a log: exit 1, $(cat "$work/junk.err")" ||
    fail "junk log: $(cat "$work/junk.err")"; }

# The plot.
"$SOURCE/scripts/plot_session.py" "$work/sphere-press.lcmlog" --types "$BUILD/lcmtypes/python" --out "$work/plot.png" >"$work/plot.txt" 2>&1
if [[ $(head -c 8 "$work/plot.png" 2>/dev/null | od -An -tx1 | tr -d ' \n') == 89504e470d0a1a0a && $(stat -c %s "$work/plot.png") -gt 10000 ]]; then
  pass "plot_session.py: $(cat "$work/plot.txt")"
else
  fail "plot_session.py: $(cat "$work/plot.txt")"
fi
"$SOURCE/scripts/plot_session.py" "$work/sphere-press.lcmlog" --out "$work/plot.jpg" >/dev/null 2>&1 &&
  fail "plot_session.py accepted a .jpg" || pass "plot_session.py refuses a picture it would not write as PNG"

# lcm-spy on Java 17 under Xvfb: it lists the types it found on its class path.
if command -v xvfb-run >/dev/null; then
  types=$(ls "$SOURCE"/lcmtypes/lcm/*.lcm | wc -l)
  # Its own session, so that the window, Xvfb and Java all go when the test is done with them.
  setsid timeout 30 xvfb-run -a "$SOURCE/scripts/spy.sh" --lcm "$url" --build "$BUILD" >"$work/spy.txt" 2>&1 &
  spy=$!
  for _ in $(seq 300); do grep -q "LCM types" "$work/spy.txt" 2>/dev/null && break; sleep 0.1; done
  sleep 0.5
  kill -- -"$spy" 2>/dev/null
  wait "$spy" 2>/dev/null
  grep -q "Found $types LCM types" "$work/spy.txt" && pass "spy.sh: lcm-spy started and found all $types types" ||
    fail "spy.sh: $(head -5 "$work/spy.txt")"
else
  echo "skip: no xvfb-run for lcm-spy"
fi
"$SOURCE/scripts/spy.sh" --build "$work/nowhere" >/dev/null 2>"$work/spy.err" && fail "spy.sh without a build" ||
  { grep -q "build the project first" "$work/spy.err" && pass "spy.sh says to build first" || fail "spy.sh error: $(cat "$work/spy.err")"; }

echo "$failures failures"
((failures == 0))
