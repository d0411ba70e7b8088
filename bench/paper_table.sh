#!/usr/bin/env bash
# Zimmer et al. 2015's Table 1, redone on a suite scene at a production size: per pipeline
# (d and dui by default) the core-minutes per frame of each stage (render, denoise,
# upsample, interpolate, and the re-render and composite the paper folds into them), the
# resolution gain (pixels x spp a frame over the samples traced), the overhead (relative
# cost x resolution gain) and the relative cost against plain pt at the same spp,
# measured by the same shot; then the cost at equal error with its 95 % interval, against
# an independent reference (docs/performance.md, "The papers' tables"). Every column comes
# from the shot's report.json.
#
#   bench/paper_table.sh [--build DIR] [--scene walkthrough] [--pipelines "d dui"]
#                        [--res 1280x720] [--spp 64] [--frames 0:8] [--reference-spp 1024]
#                        [--reference-cache DIR]
# The reference cache (default ~/.cache/pathfarm/references) keeps the references, so a
# second run renders none.
set -euo pipefail
cd "$(dirname "$0")/.."
build=build scene=walkthrough pipelines="d dui" res=1280x720 spp=64 frames=0:8 reference=1024
cache="${XDG_CACHE_HOME:-$HOME/.cache}/pathfarm/references"
while (($#)); do
  case "$1" in
    --build) build=$2 ;;
    --scene) scene=$2 ;;
    --pipelines) pipelines=$2 ;;
    --res) res=$2 ;;
    --spp) spp=$2 ;;
    --frames) frames=$2 ;;
    --reference-spp) reference=$2 ;;
    --reference-cache) cache=$2 ;;
    *) echo "paper_table: unknown option $1" >&2; exit 2 ;;
  esac
  shift 2
done
pathfarm="$build/bin/pathfarm"
[ -x "$pathfarm" ] || { echo "paper_table: no $pathfarm (build first)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

echo "| scene | pipeline | size, frames, spp | k | render | denoise | upsample | interpolate | re-render | composite | resolution gain | overhead | relative cost | cost at equal error (95 %) |"
echo "| --- | --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
for pipeline in $pipelines; do
  out="$work/$pipeline"
  cat > "$work/shot.json" <<JSON
{"name": "$scene-$pipeline", "scene": "$PWD/scenes/$scene/scene.json",
 "frames": {"start": ${frames%:*}, "end": ${frames#*:}}, "resolution": [${res%x*}, ${res#*x}],
 "spp": $spp, "pipeline": "$pipeline", "reference_spp": $reference, "output": "$out"}
JSON
  "$pathfarm" local "$work/shot.json" --workers 2 --reference-cache "$cache" > "$work/log" 2>&1 ||
    { cat "$work/log" >&2; exit 1; }
  python3 - "$scene" "$out/report.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[2]))
stages = {s["stage"]: s["core_seconds_per_frame"] / 60 for s in r["stages"]}
minutes = lambda stage: "%.3f" % stages[stage] if stage in stages else "-"
i = r.get("cost_at_equal_error_interval")
equal = "%.3f (%.3f to %.3f)" % (i["estimate"], i["low"], i["high"]) if i else "-"
print("| %s | %s | %dx%d, %d, %d | %s | %s | %s | %s | %s | %s | %s | %.2f | %.2f | %.3f | %s |" % (
    sys.argv[1], r["pipeline"], r["width"], r["height"], int(r["frames"]), r["spp"], r.get("keyframe_interval", 1),
    minutes("render"), minutes("denoise"), minutes("upsample"), minutes("interpolate"), minutes("re-render"),
    minutes("composite"), r["resolution_gain"], r["overhead"], r["relative_cost"], equal))
PY
done
echo
echo "Core-minutes per frame; plain pt at $spp spp costs the stages' total over the relative cost."
