#!/usr/bin/env bash
# pathfarm against Blender Cycles on the same glTF scene (docs/performance.md, "Against
# Blender Cycles (issue 17)"). Writes the comparison scene (make_scene.py), renders it
# with pathfarm and, twice with different seeds, with Cycles (render_cycles.py), and
# prints a markdown table of region-by-region ratios and relMSE (compare.py).
#
#   bench/cycles/compare.sh [--variants "authored metal"] [--build DIR] [--res 256x192]
#                           [--spp 4096] [--cycles-spp 2048] [--max-depth 8] [--sky 0.25,0.3,0.4] [--threads 2]
#                           [--distribution asis|GGX|MULTI_GGX] [--png FILE] [--keep DIR]
#
# Each variant is one table: "authored" is the scene as written, "metal" makes every surface
# but the lamp a glTF metal (make_scene.py).
# --cycles-spp is the total over the two Cycles renders (each gets half). --distribution
# overrides the microfacet distribution of every Principled BSDF the importer made (asis:
# the importer's choice). --png writes the side-by-side figure (pathfarm | Cycles |
# difference), one row per variant. --keep DIR keeps the scene and the frames there.
#
# Installs Debian's blender, python3-numpy and python3-openimageio with apt-get when they
# are missing: a bench-only dependency, not part of deploy/setup.sh.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
cd "$here/../.."
build=build res=256x192 spp=4096 cycles_spp=2048 depth=8 sky=0.25,0.3,0.4 threads=2
distribution=asis png="" keep="" variants="authored metal"
while (($#)); do
  case "$1" in
    --variants) variants=$2 ;;
    --build) build=$2 ;;
    --res) res=$2 ;;
    --spp) spp=$2 ;;
    --cycles-spp) cycles_spp=$2 ;;
    --max-depth) depth=$2 ;;
    --sky) sky=$2 ;;
    --threads) threads=$2 ;;
    --distribution) distribution=$2 ;;
    --png) png=$2 ;;
    --keep) keep=$2 ;;
    *) echo "compare.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift 2
done
pathfarm="$build/bin/pathfarm"
[ -x "$pathfarm" ] || { echo "compare.sh: no $pathfarm (build first)" >&2; exit 2; }
width=${res%x*} height=${res#*x}

# Debian's python3 (the one python3-openimageio installs into), whatever PATH prefers.
python=/usr/bin/python3
if ! command -v blender >/dev/null || ! "$python" -c 'import numpy, OpenImageIO' 2>/dev/null; then
  echo "compare.sh: installing Debian's blender, python3-numpy, python3-openimageio" >&2
  sudo=""
  [ "$(id -u)" = 0 ] || sudo=sudo
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
    blender python3-numpy python3-openimageio >/dev/null
fi

if [ -n "$keep" ]; then
  work=$keep
  mkdir -p "$work"
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi

compare_variant() {  # variant -> a table on stdout, $work/$variant/side_by_side.png
  local variant=$1 dir="$work/$1"
  python3 "$here/make_scene.py" --out "$dir" --variant "$variant" --sky "$sky" --max-depth "$depth" >/dev/null

  echo "pathfarm: $variant scene, $res, $spp spp, max depth $depth" >&2
  local start=$EPOCHREALTIME
  "$pathfarm" render "$dir/scene.json" --frames 0 --spp "$spp" --res "$res" --max-depth "$depth" \
    --threads "$threads" --out "$dir/pathfarm" >"$dir/pathfarm.log" 2>&1 ||
    { cat "$dir/pathfarm.log" >&2; exit 1; }
  local pf_seconds
  pf_seconds=$(awk "BEGIN {print $EPOCHREALTIME - $start}")

  local half=$((cycles_spp / 2)) cy_seconds=0 seed
  for seed in 0 1; do
    echo "Cycles: $variant scene, $res, $half spp, seed $seed" >&2
    start=$EPOCHREALTIME
    blender -b -t "$threads" --python-exit-code 1 -P "$here/render_cycles.py" -- \
      "$dir/compare.glb" "$dir/cycles_$seed.exr" "$width" "$height" "$half" \
      --sky "$sky" --max-depth "$depth" --seed "$seed" --threads "$threads" --distribution "$distribution" \
      >"$dir/cycles_$seed.log" 2>&1 || { cat "$dir/cycles_$seed.log" >&2; exit 1; }
    cy_seconds=$(awk "BEGIN {print $cy_seconds + $EPOCHREALTIME - $start}")
  done
  grep '^render_cycles: material' "$dir/cycles_0.log" >&2 || true

  echo "### $variant: pathfarm $spp spp $(printf %.1f "$pf_seconds") s wall;" \
    "Cycles 2 x $half spp $(printf %.1f "$cy_seconds") s wall, Principled distribution $distribution"
  echo
  "$python" "$here/compare.py" "$dir/pathfarm/frame_0000.exr" "$dir/cycles_0.exr" "$dir/cycles_1.exr" \
    --layout "$dir/layout.json" --json "$dir/regions.json" --png "$dir/side_by_side.png"
  echo
}

echo "Blender $(blender --version 2>/dev/null | head -1 | cut -d' ' -f2), $threads threads, $(date +%F)," \
  "load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo
figures=()
for variant in $variants; do
  compare_variant "$variant" | grep -v '^side by side'
  figures+=("$work/$variant/side_by_side.png")
done
if [ -n "$png" ]; then
  "$python" "$here/compare.py" stack "$png" "${figures[@]}"
  echo "side by side (pathfarm | Cycles | difference), one row per variant ($variants): $png"
fi
