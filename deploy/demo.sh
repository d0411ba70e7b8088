#!/usr/bin/env bash
# Installs dependencies, builds, and renders the demo animation (the animated Cornell
# box, scenes/cornell/shot.json) with the DUI pipeline on an embedded local farm: a
# scheduler and two worker processes on this machine. Prints the shot's report.
set -euo pipefail
cd "$(dirname "$0")/.."
./deploy/setup.sh
BUILD_DIR=${PATHFARM_BUILD_DIR:-build}
OUT=${PATHFARM_DEMO_OUT:-demo-output/cornell}
"$BUILD_DIR/bin/pathfarm" local scenes/cornell/shot.json --workers 2 --out "$OUT"
"$BUILD_DIR/bin/pathfarm" preview "$OUT"
echo
cat "$OUT/report.md"
echo
echo "EXR frames (beauty in R,G,B; every component's color):             $OUT/frame_0000.exr .. frame_0023.exr"
echo "PNG previews:                                                      $OUT/frame_0000.png .. frame_0023.png"
echo "Speed against error (above):                                       $OUT/report.md, report.json"
echo "Contact sheet (final, pt, reference, error maps):                  $OUT/contact_sheet.png"
echo "The farm's logs (chunks and caches are removed; --keep-farm keeps them): $OUT/farm/logs/"
