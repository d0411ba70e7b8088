#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test (what CI runs).
set -euo pipefail
cd "$(dirname "$0")/.."
./deploy/setup.sh
BUILD_DIR=${PATHFARM_BUILD_DIR:-build}
# The benchmark programs are compiled, not run, so that the figures in docs/ keep a
# program that builds. They compile while the tests run, at the lowest priority: a sixth
# of the tests' time leaves the cores idle (farm tests waiting on leases and processes),
# and that is where the compiler runs.
bench_log=$(mktemp)
trap 'rm -f "$bench_log"' EXIT
nice -n 19 cmake --build "$BUILD_DIR" --target benchmarks --parallel "$(nproc)" > "$bench_log" 2>&1 &
bench_build=$!
tests=0
ctest --test-dir "$BUILD_DIR" --output-on-failure --parallel "$(nproc)" --timeout 600 || tests=$?
if ! wait "$bench_build"; then
  cat "$bench_log"
  echo "test.sh: the benchmark programs do not build" >&2
  exit 1
fi
exit "$tests"
