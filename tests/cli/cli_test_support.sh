# Sourced by the command-line tests, called as `TEST.sh PATHFARM_BINARY SOURCE_DIR`: a
# scratch folder removed on exit, failures counted, and the closing line and status.
set -u
pathfarm=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
finish() {
  if [ "$failures" -eq 0 ]; then echo "$1: all checks passed"; fi
  exit "$failures"
}
# Runs pathfarm with the given arguments and fails unless it refuses them as bad input
# (exit status 2); the output is kept in $work/log.
expect_refused() {
  "$pathfarm" "$@" > "$work/log" 2>&1
  local status=$?
  [ "$status" -eq 2 ] || fail "$*: exit status $status, expected 2 ($(cat "$work/log"))"
}
