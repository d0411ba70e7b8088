#!/usr/bin/env bash
# Farm efficiency: wall time of a 64-tile shot on `pathfarm local --workers 2` (one
# render thread each) against `pathfarm render --threads 2` of the same frame.
#
#   bench/farm_efficiency.sh [BUILD_DIR] [REPEATS] [SPP]
#
# SPP (default 256) sets the work per tile: about 1 s per tile on one core at 256.
# Prints each run's wall times and the median efficiency = render time / farm time
# (1.0: the farm costs nothing; the target is at least 0.95).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
repeats=${2:-3}
spp=${3:-256}
pathfarm="$build/bin/pathfarm"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# One frame of the Cornell box at 512x512 in 64-pixel tiles: 64 tiles.
cat > "$work/shot.json" <<JSON
{"name": "efficiency", "scene": "$PWD/scenes/cornell/scene.json", "frames": {"start": 6, "end": 6},
 "resolution": [512, 512], "spp": $spp, "max_depth": 8, "tile": 64, "output": "$work/farm"}
JSON

seconds() {
  local start end
  start=$(date +%s.%N)
  "$@" > "$work/log" 2>&1 || { cat "$work/log"; exit 1; }
  end=$(date +%s.%N)
  awk -v a="$start" -v b="$end" 'BEGIN { print b - a }'
}

ratios=()
for i in $(seq "$repeats"); do
  rm -rf "$work/farm" "$work/render"
  render=$(seconds "$pathfarm" render scenes/cornell/scene.json --frames 6:6 --res 512x512 --spp "$spp" --max-depth 8 \
           --threads 2 --out "$work/render")
  farm=$(seconds "$pathfarm" local "$work/shot.json" --workers 2 --threads 1)
  cmp -s "$work/render/frame_0006.exr" "$work/farm/frame_0006.exr" || { echo "farm and render frames differ"; exit 1; }
  ratio=$(awk -v r="$render" -v f="$farm" 'BEGIN { print r / f }')
  ratios+=("$ratio")
  printf "run %d: render --threads 2 %.2f s, local --workers 2 %.2f s, efficiency %.3f\n" "$i" "$render" "$farm" "$ratio"
done
median=$(printf "%s\n" "${ratios[@]}" | sort -g | sed -n "$(( (repeats + 1) / 2 ))p")
printf "median efficiency over %d runs: %.3f\n" "$repeats" "$median"
