#!/usr/bin/env bash
# The moving-camera suite: every suite scene rendered by each pipeline on the local farm,
# against a high-spp reference, with plain pt at the same spp measured by the same shot
# (its baseline). Prints a markdown table (docs/performance.md, "Moving-camera suite") and
# copies each shot's contact sheet to FIGURES/suite_<scene>_<pipeline>.png. For `auto`, the
# last columns give the probe's predictions for the shot and its cost, and the probe's
# scores of every candidate go to standard error, as do the causes of the interpolated
# frames' and the upsampled keyframes' re-render. Error figures come with their 95 %
# intervals (report.proto's Interval); with --repeat N every shot runs N times (the same
# bits each time) and the costs are the median of the runs with their range.
#
#   bench/suite_benchmark.sh [--build DIR] [--scenes "dolly courtyard walkthrough cornell showroom creature"]
#                            [--pipelines "dui"] [--spp 64] [--reference-spp 1024]
#                            [--frames 0:23] [--res 320x180] [--figures docs/figures] [--repeat 1]
#                            [--setting small|production] [--reference-cache DIR]
#                            [--evaluation-frames "3,4,11,12,19,20"] [--baseline-repeats 1]
#                            [--keyframe-interval K]
# --setting production is 640x360 at 256 spp against a 4096-spp reference (production renders
# take hundreds of samples, where a frame's fixed costs weigh less); small, the default, is
# 320x180 at 64 spp against 1024. Options after it change its values. References are kept
# in the reference cache (default ~/.cache/pathfarm/references; client/reference_cache.h),
# so a second run of a scene at the same size renders none. --evaluation-frames names the
# frames measured against the reference (the shot's default: the middle frame and the
# next); more frames narrow the intervals, each costing a reference frame. Give them in
# consecutive pairs, so that the temporal error has frame pairs to compare.
# --baseline-repeats N renders plain pt N times per evaluation frame from disjoint samples
# (ShotSpec.baseline_repeats): pt's error at the shot's spp averaged over N renders, which
# narrows the cost at equal error where pt's fireflies dominate its interval.
# --keyframe-interval K gives di and dui shots every K-th frame as a keyframe instead of
# the probe's choice (the shot key keyframe_interval; other pipelines ignore it).
set -euo pipefail
cd "$(dirname "$0")/.."
build=build scenes="dolly courtyard walkthrough cornell showroom creature" pipelines=dui spp=64 reference=1024
frames=0:23 res=320x180 figures=docs/figures repeat=1 evaluation="" baseline_repeats=1 interval=""
cache="${XDG_CACHE_HOME:-$HOME/.cache}/pathfarm/references"
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
    --repeat) repeat=$2 ;;
    --reference-cache) cache=$2 ;;
    --evaluation-frames) evaluation=$2 ;;
    --baseline-repeats) baseline_repeats=$2 ;;
    --keyframe-interval) interval=$2 ;;
    --setting)
      case "$2" in
        small) res=320x180 spp=64 reference=1024 ;;
        production) res=640x360 spp=256 reference=4096 ;;
        *) echo "suite_benchmark: --setting is small or production, not $2" >&2; exit 2 ;;
      esac ;;
    *) echo "suite_benchmark: unknown option $1" >&2; exit 2 ;;
  esac
  shift 2
done
pathfarm="$build/bin/pathfarm"
[ -x "$pathfarm" ] || { echo "suite_benchmark: no $pathfarm (build first)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$figures"

echo "| scene | pipeline | k | probe's predicted re-render | core-s/frame | pt core-s/frame | relative cost | cost at equal error (95 %) | relMSE | pt relMSE | against the truth (95 %) | pt against the truth (95 %) | worst tile | pt worst tile | error in worst 1 % | pt | temporal against the truth (95 %) | pt temporal against the truth (95 %) | re-render, interpolated | auto: predicted core-s/frame | auto: predicted relMSE | auto: probe's share of the shot |"
echo "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
for scene in $scenes; do
  for pipeline in $pipelines; do
    out="$work/$scene-$pipeline"
    extra=""
    [ -n "$evaluation" ] && extra=", \"evaluation_frames\": [$evaluation]"
    [ -n "$interval" ] && extra="$extra, \"keyframe_interval\": $interval"
    cat > "$work/shot.json" <<JSON
{"name": "$scene-$pipeline", "scene": "$PWD/scenes/$scene/scene.json",
 "frames": {"start": ${frames%:*}, "end": ${frames#*:}}, "resolution": [${res%x*}, ${res#*x}],
 "spp": $spp, "pipeline": "$pipeline", "reference_spp": $reference, "baseline_repeats": $baseline_repeats,
 "output": "$out"$extra}
JSON
    reports=()
    for ((run = 1; run <= repeat; run++)); do
      rm -rf "$out"
      "$pathfarm" local "$work/shot.json" --workers 2 --reference-cache "$cache" > "$work/log" 2>&1 || { cat "$work/log" >&2; exit 1; }
      cp "$out/report.json" "$work/report-$run.json"
      reports+=("$work/report-$run.json")
    done
    [ -f "$out/contact_sheet.png" ] && cp "$out/contact_sheet.png" "$figures/suite_${scene}_${pipeline}.png"
    python3 - "$scene" "$pipeline" "${reports[@]}" <<'PY'
import json, re, statistics, sys
runs = [json.load(open(f)) for f in sys.argv[3:]]
r = runs[-1]
# Costs vary from run to run (this machine is shared); the median with the runs' range.
def cost(key, pattern="%.2f"):
    values = [run[key] for run in runs]
    if not all(isinstance(v, (int, float)) and v >= 0 for v in values): return "-"
    text = pattern % statistics.median(values)
    return text if len(values) == 1 else "%s (%s to %s)" % (text, pattern % min(values), pattern % max(values))
def interval(i, pattern="%.4f", scale=1.0):
    if not i: return "-"
    end = lambda v: "inf" if v in ("Infinity", float("inf")) else ("-inf" if v in ("-Infinity", float("-inf")) else pattern % (scale * v))
    return "%s (%s to %s)" % (pattern % (scale * i["estimate"]), end(i["low"]), end(i["high"]))
def equal_error():
    i = r.get("cost_at_equal_error_interval")
    if not i or r.get("cost_at_equal_error", -1) < 0: return "-"
    # The error ratio is the same in every run; the relative cost is the runs' median.
    scale = statistics.median(run["relative_cost"] for run in runs) / r["relative_cost"]
    return interval(i, "%.3f", scale)
# The probe's prediction for the interval it chose, from the report's reason.
chosen = re.search(r"k = %s: ([0-9.]+%%)" % r.get("keyframe_interval", 0), r.get("keyframe_reason", ""))
errors = {e["stage"]: e for e in r["errors"]}
final, base = errors.get("final", {}), errors.get("baseline", {})
f = lambda v, p="%.4f": p % v if isinstance(v, (int, float)) and v >= 0 else "-"
probe = r.get("probe_core_seconds", 0)
print("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
    sys.argv[1], r["pipeline"] if r["pipeline"] == sys.argv[2] else "%s (for %s)" % (r["pipeline"], sys.argv[2]),
    r.get("keyframe_interval", "-"), chosen.group(1) if chosen else "-", cost("core_seconds_per_frame"),
    cost("baseline_core_seconds_per_frame"), cost("relative_cost", "%.3f"), equal_error(),
    f(final.get("relmse")), f(base.get("relmse")), interval(final.get("truth_error")), interval(base.get("truth_error")),
    f(final.get("worst_tile_relmse")), f(base.get("worst_tile_relmse")),
    f(100 * final.get("worst_percent_share", -0.01), "%.0f%%"), f(100 * base.get("worst_percent_share", -0.01), "%.0f%%"),
    interval(r.get("temporal_truth_error")), interval(r.get("baseline_temporal_truth_error")),
    f(100 * r["interpolation_rerender_rate"], "%.1f%%"),
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
        print("  %s %s %s: " % (sys.argv[1], r["pipeline"], which) +
              ", ".join("%s %.1f%%" % (c, 100 * v) for c, v in sorted(causes.items(), key=lambda i: -i[1])),
              file=sys.stderr)
PY
  done
done
