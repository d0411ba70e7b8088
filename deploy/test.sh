#!/usr/bin/env bash
# Installs dependencies, builds, and runs every test (what CI runs).
set -euo pipefail
cd "$(dirname "$0")/.."
# With Blender, for the add-on's test (tests/blender); PATHFARM_BLENDER=0 leaves it out.
PATHFARM_BLENDER=${PATHFARM_BLENDER:-1} ./deploy/setup.sh
BUILD_DIR=${PATHFARM_BUILD_DIR:-build}
# The benchmark programs are compiled, not run, so that the figures in docs/ keep a
# program that builds.
cmake --build "$BUILD_DIR" --target benchmarks --parallel "$(nproc)"
ctest --test-dir "$BUILD_DIR" --output-on-failure --parallel "$(nproc)" --timeout 600
