#!/usr/bin/env bash
# The moving-camera suite: every suite scene rendered by each pipeline on the local farm,
# against a high-spp reference, with plain pt at the same spp measured by the same shot
# (its baseline). Prints a markdown table (docs/performance.md, "Moving-camera suite") and
# copies each shot's contact sheet to FIGURES/suite_<scene>_<pipeline>.png. For `auto`, the
# last columns give the probe's predictions for the shot and its cost, and the probe's
# scores of every candidate go to standard error, as do the causes of the interpolated
# frames' and the upsampled keyframes' re-render.
#
#   bench/suite_benchmark.sh [--build DIR] [--scenes "dolly courtyard walkthrough cornell showroom"]
#                            [--pipelines "dui"] [--spp 64] [--reference-spp 1024]
#                            [--frames 0:23] [--res 320x180] [--figures docs/figures]
set -euo pipefail
cd "$(dirname "$0")/.."
build=build scenes="dolly courtyard walkthrough cornell showroom" pipelines=dui spp=64 reference=1024
frames=0:23 res=320x180 figures=docs/figures
while (($#)); do
  case "$1" in
    --build) build=$2 ;;
    --scenes) scenes=$2 ;;
    --pipelines) pipelines=$2 ;;
    --spp) spp=$2 ;;
    --reference-spp) reference=$2 ;;
    --frames) frames=$2 ;;
    --res) res=$2 ;;
    --figures) figures=$2 ;;
    *) echo "suite_benchmark: unknown option $1" >&2; exit 2 ;;
  esac
  shift 2
done
pathfarm="$build/bin/pathfarm"
[ -x "$pathfarm" ] || { echo "suite_benchmark: no $pathfarm (build first)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$figures"

echo "| scene | pipeline | k | probe's predicted re-render | core-s/frame | pt core-s/frame | relative cost | cost at equal error | relMSE | pt relMSE | worst tile | pt worst tile | error in worst 1 % | pt | temporal | pt temporal | re-render, interpolated | auto: predicted core-s/frame | auto: predicted relMSE | auto: probe's share of the shot |"
echo "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
for scene in $scenes; do
  for pipeline in $pipelines; do
    out="$work/$scene-$pipeline"
    cat > "$work/shot.json" <<JSON
{"name": "$scene-$pipeline", "scene": "$PWD/scenes/$scene/scene.json",
 "frames": {"start": ${frames%:*}, "end": ${frames#*:}}, "resolution": [${res%x*}, ${res#*x}],
 "spp": $spp, "pipeline": "$pipeline", "reference_spp": $reference, "output": "$out"}
JSON
    "$pathfarm" local "$work/shot.json" --workers 2 > "$work/log" 2>&1 || { cat "$work/log" >&2; exit 1; }
    [ -f "$out/contact_sheet.png" ] && cp "$out/contact_sheet.png" "$figures/suite_${scene}_${pipeline}.png"
    python3 - "$out/report.json" "$scene" "$pipeline" <<'PY'
import json, re, sys
r = json.load(open(sys.argv[1]))
# The probe's prediction for the interval it chose, from the report's reason.
chosen = re.search(r"k = %s: ([0-9.]+%%)" % r.get("keyframe_interval", 0), r.get("keyframe_reason", ""))
errors = {e["stage"]: e for e in r["errors"]}
final, base = errors.get("final", {}), errors.get("baseline", {})
f = lambda v, p="%.4f": p % v if isinstance(v, (int, float)) and v >= 0 else "-"
probe = r.get("probe_core_seconds", 0)
print("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
    sys.argv[2], r["pipeline"] if r["pipeline"] == sys.argv[3] else "%s (for %s)" % (r["pipeline"], sys.argv[3]),
    r.get("keyframe_interval", "-"), chosen.group(1) if chosen else "-", f(r["core_seconds_per_frame"], "%.2f"),
    f(r["baseline_core_seconds_per_frame"], "%.2f"), f(r["relative_cost"], "%.3f"), f(r.get("cost_at_equal_error", -1), "%.3f"),
    f(final.get("relmse")), f(base.get("relmse")), f(final.get("worst_tile_relmse")), f(base.get("worst_tile_relmse")),
    f(100 * final.get("worst_percent_share", -0.01), "%.0f%%"), f(100 * base.get("worst_percent_share", -0.01), "%.0f%%"),
    f(r["temporal_error"]), f(r["baseline_temporal_error"]), f(100 * r["interpolation_rerender_rate"], "%.1f%%"),
    f(r.get("predicted_core_seconds_per_frame", 0) or -1, "%.2f"), f(r.get("predicted_relmse", 0) or -1),
    f(100 * probe / r["core_seconds"] if probe and r["core_seconds"] else -1, "%.1f%%")))
# auto's probe table, from the report's reason.
if probe: print("  " + r["pipeline_reason"], file=sys.stderr)
# Why interpolated frames' and upsampled keyframes' pixels were re-rendered (a pixel may
# have several causes).
for field, which in (("interpolation_rerender_causes", "re-render causes"),
                     ("upsample_rerender_causes", "keyframe re-render causes")):
    causes = r.get(field, {})
    if causes:
        print("  %s %s %s: " % (sys.argv[2], r["pipeline"], which) +
              ", ".join("%s %.1f%%" % (c, 100 * v) for c, v in sorted(causes.items(), key=lambda i: -i[1])),
              file=sys.stderr)
PY
  done
done
