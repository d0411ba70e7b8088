#!/usr/bin/env bash
# Installs dependencies, builds, and renders the demo animation: the animated Cornell box.
set -euo pipefail
cd "$(dirname "$0")/.."
./deploy/setup.sh
BUILD_DIR=${PATHFARM_BUILD_DIR:-build}
OUT=${PATHFARM_DEMO_OUT:-demo-output/cornell}
"$BUILD_DIR/bin/pathfarm" render scenes/cornell/scene.json --frames 0:23 --spp 64 --res 256x256 --out "$OUT" --png
echo
echo "EXR frames (beauty in R,G,B; per-pixel variance in variance.R/G/B): $OUT/frame_0000.exr .. frame_0023.exr"
echo "PNG previews:                                                      $OUT/frame_0000.png .. frame_0023.png"
