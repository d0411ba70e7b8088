#!/usr/bin/env bash
# Installs dependencies, builds, and renders the two demo animations with the DUI
# pipeline on an embedded local farm (a scheduler and two worker processes on this
# machine): the animated Cornell box (scenes/cornell/shot.json) and the showroom, a glTF
# 2.0 scene with a moving camera, a textured floor, metals and glass
# (scenes/showroom/shot.json). Prints each shot's report.
set -euo pipefail
cd "$(dirname "$0")/.."
./deploy/setup.sh
BUILD_DIR=${PATHFARM_BUILD_DIR:-build}
OUT=${PATHFARM_DEMO_OUT:-demo-output}
for shot in cornell showroom; do
  "$BUILD_DIR/bin/pathfarm" local "scenes/$shot/shot.json" --workers 2 --out "$OUT/$shot"
  "$BUILD_DIR/bin/pathfarm" preview "$OUT/$shot"
  echo
  cat "$OUT/$shot/report.md"
  echo
done
for shot in cornell showroom; do
  echo "$shot:"
  echo "  EXR frames (beauty in R,G,B; every component's color):   $OUT/$shot/frame_0000.exr .. frame_0023.exr"
  echo "  PNG previews:                                            $OUT/$shot/frame_0000.png .. frame_0023.png"
  echo "  Speed against error (above):                             $OUT/$shot/report.md, report.json"
  echo "  Contact sheet (final, pt, reference, error maps):        $OUT/$shot/contact_sheet.png"
  echo "  The farm's logs (chunks and caches are removed):         $OUT/$shot/farm/logs/"
done
