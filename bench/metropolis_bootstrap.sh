#!/usr/bin/env bash
# How the bootstrap's size changes a Metropolis render from one scene seed to the next
# (docs/performance.md, "The bootstrap sized to the window"): for each bootstrap setting
# and each seed, one window rendered with a fixed number of mutations, and its mean
# relMSE, mean brightness (the frames' mean luminance over the reference's) and CPU
# seconds against a path-traced reference from a seed of its own. Prints a markdown table.
#
#   bench/metropolis_bootstrap.sh [--build DIR] [--scene FILE] [--frames A:B] [--res WxH]
#       [--integrator tmlt|pssmlt] [--mutations-per-pixel N] [--seeds "1 2 3 4"]
#       [--bootstrap "10000 auto"] [--reference-spp N] [--reference-dir DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build="$root/build"
scene="$root/scenes/ajar_door/scene.json"
frames=0:23 res=64x48 integrator=tmlt mutations=600 seeds="1 2 3 4" settings="10000 auto"
reference_spp=4096 reference_dir=""
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$(cd "$2" && pwd) ;;
    --scene) scene=$2 ;;
    --frames) frames=$2 ;;
    --res) res=$2 ;;
    --integrator) integrator=$2 ;;
    --mutations-per-pixel) mutations=$2 ;;
    --seeds) seeds=$2 ;;
    --bootstrap) settings=$2 ;;
    --reference-spp) reference_spp=$2 ;;
    --reference-dir) reference_dir=$2 ;;
    *) echo "unknown option $1 (see the header of $0)" >&2; exit 2 ;;
  esac
  shift 2
done
pathfarm="$build/bin/pathfarm"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
first=${frames%:*} last=${frames#*:}
reference_dir=${reference_dir:-$work/reference}

# The reference's seed is one no run below uses.
if [ ! -s "$reference_dir/$(printf 'frame_%04d.exr' "$last")" ]; then
  echo "rendering the reference: pt at $reference_spp spp" >&2
  "$pathfarm" render "$scene" --frames "$frames" --res "$res" --spp "$reference_spp" --seed 999983 \
    --out "$reference_dir" 2> "$work/log" || { cat "$work/log" >&2; exit 1; }
fi

field() { grep -o "\"$1\": [^,]*" | cut -d' ' -f2; }  # a number of compare's JSON

# "RELMSE BRIGHTNESS" of a folder's frames: means over the frames.
measure() {
  local sum=0 bright=0 count=0 frame json
  for ((frame = first; frame <= last; ++frame)); do
    json=$("$pathfarm" compare --json "$1/$(printf 'frame_%04d.exr' "$frame")" \
      "$reference_dir/$(printf 'frame_%04d.exr' "$frame")")
    sum=$(awk -v s="$sum" -v j="$(field relmse <<< "$json")" 'BEGIN { print s + j }')
    bright=$(awk -v s="$bright" -v j="$(field brightness <<< "$json")" 'BEGIN { print s + j }')
    count=$((count + 1))
  done
  awk -v s="$sum" -v b="$bright" -v n="$count" 'BEGIN { printf "%.4f %.3f", s / n, b / n }'
}

echo "| bootstrap | seed | relMSE | brightness | CPU s |"
echo "| --- | ---: | ---: | ---: | ---: |"
for setting in $settings; do
  bootstrap=()
  [ "$setting" = auto ] || bootstrap=(--bootstrap "$setting")
  for seed in $seeds; do
    out="$work/$setting-$seed"
    TIMEFORMAT='%U %S'
    { time "$pathfarm" render "$scene" --integrator "$integrator" --frames "$frames" --res "$res" \
        --mutations-per-pixel "$mutations" --seed "$seed" "${bootstrap[@]}" --out "$out" 2> "$work/log" ||
        { cat "$work/log" >&2; exit 1; }; } 2> "$work/time"
    read -r relmse brightness <<< "$(measure "$out")"
    cpu=$(awk '{ printf "%.1f", $1 + $2 }' "$work/time")
    echo "| $setting | $seed | $relmse | $brightness | $cpu |"
    rm -rf "$out"
  done
done
