#!/usr/bin/env bash
# The glTF scale figures of docs/performance.md: a one-million-triangle mesh, one
# 100k-triangle mesh placed 1, 10 and 100 times (Embree instances: memory should stay
# flat), and the 100 placements as 100 separate meshes (copies, for comparison), each
# imported and rendered by build/bin/scene_scale.
#
#   bench/gltf_scale.sh [--build build] [--work /tmp/pathfarm_gltf_scale] [--res 320x180] [--spp 4] [--repeat 3]
set -euo pipefail
cd "$(dirname "$0")/.."
build=build work=/tmp/pathfarm_gltf_scale res=320x180 spp=4 repeat=3
while (($#)); do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --res) res=$2; shift 2 ;;
    --spp) spp=$2; shift 2 ;;
    --repeat) repeat=$2; shift 2 ;;
    *) echo "gltf_scale.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
cmake --build "$build" --target scene_scale > /dev/null || { echo "gltf_scale.sh: cannot build scene_scale in $build" >&2; exit 2; }
python3 bench/gltf_scale/make_scale_scenes.py "$work"
ls -l "$work"/*.glb
for scene in terrain rocks_1 rocks_10 rocks_100 rocks_100_copies character; do
  echo
  "$build/bin/scene_scale" --scene "$work/$scene.json" --res "$res" --spp "$spp" --repeat "$repeat"
done
