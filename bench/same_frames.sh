#!/usr/bin/env bash
# Whether two builds of pathfarm render the same bits: every suite scene through every
# pipeline on a local farm (auto included, its probe and choice too), and every integrator
# of `pathfarm render`, with each binary; then each frame of one is compared byte for byte
# with the other's. For changes that must not change output (refactors): run it with the
# binary from before the change saved aside.
#
#   bench/same_frames.sh --before OLD/pathfarm --after build/bin/pathfarm
#                        [--scenes "dolly courtyard walkthrough cornell showroom"]
#                        [--pipelines "pt d du di dui tgpt tmlt auto"] [--res 96x54] [--spp 8]
#                        [--frames 0:5]
# Prints a line per shot (frames identical of frames written) and exits 1 on any difference.
set -euo pipefail
cd "$(dirname "$0")/.."
before="" after=build/bin/pathfarm scenes="dolly courtyard walkthrough cornell showroom"
pipelines="pt d du di dui tgpt tmlt auto" res=96x54 spp=8 frames=0:5
while (($#)); do
  case "$1" in
    --before) before=$2 ;;
    --after) after=$2 ;;
    --scenes) scenes=$2 ;;
    --pipelines) pipelines=$2 ;;
    --res) res=$2 ;;
    --spp) spp=$2 ;;
    --frames) frames=$2 ;;
    *) echo "same_frames: unknown option $1" >&2; exit 2 ;;
  esac
  shift 2
done
for binary in "$before" "$after"; do
  [ -x "$binary" ] || { echo "same_frames: no executable '$binary' (--before and --after name two pathfarm binaries)" >&2; exit 2; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# $1: label, $2: folder of the "before" frames, $3: folder of the "after" frames.
compare_folders() {
  local total=0 same=0 frame
  for frame in "$2"/*.exr; do
    [ -e "$frame" ] || continue
    total=$((total + 1))
    cmp -s "$frame" "$3/$(basename "$frame")" && same=$((same + 1))
  done
  local after_total
  after_total=$(find "$3" -maxdepth 1 -name '*.exr' | wc -l)
  echo "$1: $same of $total frames identical"
  [ "$total" -gt 0 ] && [ "$same" -eq "$total" ] && [ "$after_total" -eq "$total" ]
}

status=0
for scene in $scenes; do
  for pipeline in $pipelines; do
    for side in before after; do
      binary=$before
      [ "$side" = after ] && binary=$after
      out="$work/$side/$scene-$pipeline"
      cat > "$work/shot.json" <<JSON
{"name": "$scene-$pipeline", "scene": "$PWD/scenes/$scene/scene.json",
 "frames": {"start": ${frames%:*}, "end": ${frames#*:}}, "resolution": [${res%x*}, ${res#*x}],
 "spp": $spp, "pipeline": "$pipeline", "output": "$out", "mlt_window": 3}
JSON
      "$binary" local "$work/shot.json" --workers 2 > "$work/log" 2>&1 || { cat "$work/log" >&2; exit 1; }
    done
    compare_folders "$scene $pipeline" "$work/before/$scene-$pipeline" "$work/after/$scene-$pipeline" || status=1
  done
done

# `pathfarm render`: every integrator on the first suite scene, and pt's decomposition.
scene=${scenes%% *}
for integrator in pt "pt --decompose auto" bdpt gpt tgpt "pssmlt --mutations-per-pixel 4" \
                  "mlt --mutations-per-pixel 4" "tmlt --mutations-per-pixel 4"; do
  label=${integrator%% *}
  [[ "$integrator" == *decompose* ]] && label="pt-decomposed"
  for side in before after; do
    binary=$before
    [ "$side" = after ] && binary=$after
    args=(--integrator $integrator)
    [[ "$integrator" == pssmlt* || "$integrator" == mlt* || "$integrator" == tmlt* ]] || args+=(--spp "$spp")
    "$binary" render "scenes/$scene/scene.json" --frames 0:1 --res "$res" --threads 2 "${args[@]}" \
      --out "$work/$side/render-$label" > "$work/log" 2>&1 || { cat "$work/log" >&2; exit 1; }
  done
  compare_folders "render $label" "$work/before/render-$label" "$work/after/render-$label" || status=1
done
exit $status
