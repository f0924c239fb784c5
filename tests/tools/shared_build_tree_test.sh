#!/usr/bin/env bash
# The README's two commands share one build tree: scripts/main.sh must configure build/ with
# exactly the options scripts/test.sh's Release pass gives it, or running one after the other
# recompiles the whole project (a changed flag changes every compile command).
# Usage: SOURCE=… shared_build_tree_test.sh   (ctest sets it).
set -uo pipefail
: "${SOURCE:?}"

# The one line of a script that configures build/ (not build-minimal/, build-tidy/, ...).
configure_line() {
  local lines
  lines="$(grep -E '^cmake -S \. -B build ' "$1")"
  if [[ "$(printf '%s\n' "$lines" | grep -c .)" != 1 ]]; then
    echo "FAIL: $1 should configure build/ on exactly one line, found:" >&2
    printf '%s\n' "$lines" >&2
    return 1
  fi
  # Options in any order are the same configuration; output redirection is not an option.
  printf '%s\n' "$lines" | sed 's/>.*$//' | tr -s ' ' '\n' | grep . | sort
}

main_options="$(configure_line "$SOURCE/scripts/main.sh")" || exit 1
test_options="$(configure_line "$SOURCE/scripts/test.sh")" || exit 1
if [[ "$main_options" != "$test_options" ]]; then
  echo "FAIL: scripts/main.sh and scripts/test.sh configure build/ differently:"
  diff <(printf '%s\n' "$main_options") <(printf '%s\n' "$test_options")
  exit 1
fi
echo "ok: both configure build/ alike: $(grep -E "^cmake -S \. -B build " "$SOURCE/scripts/main.sh")"
