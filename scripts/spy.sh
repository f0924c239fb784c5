#!/usr/bin/env bash
# lcm-spy with glovesculpt's message types, on Java 17.
#
#   scripts/spy.sh [--lcm URL] [--build DIR]
#
# Debian's /usr/bin/lcm-spy passes -Xincgc, an option Java 9 removed, so it does not start on
# Debian 12's Java 17; and it knows none of our types. This starts the same class (lcm.spy.Spy)
# with the jar the build makes from lcmtypes/lcm/*.lcm (build/lcmtypes/sculpt_lcm_types.jar) on
# the class path, beside Debian's lcm.jar and jchart2d.jar (liblcm-java, libjchart2d-java; the
# set-up script installs them). lcm-spy then decodes every SCULPT_* channel.
set -euo pipefail

url="udpm://239.255.76.67:7667?ttl=0"
build="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/build"
usage() { sed -n '4p' "${BASH_SOURCE[0]}" | sed 's/^# *//'; }
while (($#)); do
  case "$1" in
    --lcm) url="${2:?--lcm needs a URL}"; shift 2 ;;
    --lcm=*) url="${1#--lcm=}"; shift ;;
    --build) build="${2:?--build needs a folder}"; shift 2 ;;
    -h | --help) usage; exit 0 ;;
    *) echo "spy.sh: error: unknown argument '$1' ($(usage))" >&2; exit 2 ;;
  esac
done

types="$build/lcmtypes/sculpt_lcm_types.jar"
[[ -f "$types" ]] || { echo "spy.sh: error: $types not found: build the project first" >&2; exit 1; }
for jar in /usr/share/java/lcm.jar /usr/share/java/jchart2d.jar; do
  [[ -f "$jar" ]] || { echo "spy.sh: error: $jar not found: install liblcm-java and libjchart2d-java (scripts/setup.sh)" >&2; exit 1; }
done
exec java -Djava.net.preferIPv4Stack=true -Xmx256m \
  -cp "/usr/share/java/lcm.jar:/usr/share/java/jchart2d.jar:$types" lcm.spy.Spy --lcm-url="$url"
