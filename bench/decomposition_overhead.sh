#!/usr/bin/env bash
# The decomposed render's cost against plain path tracing on the suite's scenes: issue 41's
# first target, `--decompose auto` at most 1.2x pt at 64 spp and 1.1x at 256 spp. Each row
# is render_throughput's: one frame rendered plain and decomposed at the same spp,
# alternating run by run on every core, medians of the repeats (no EXR is written; the
# farm's tiles add their encoding, docs/performance.md).
#
#   bench/decomposition_overhead.sh [--build DIR] [--scenes "dolly courtyard ..."] [--repeat 3] [--frame 11]
#                                   [--settings "320x180@64 320x180@256 640x360@256"]
set -euo pipefail
cd "$(dirname "$0")/.."
build=build scenes="dolly courtyard walkthrough cornell showroom creature" repeat=3 frame=11
settings="320x180@64 320x180@256 640x360@256"
while (($#)); do
  case "$1" in
    --build) build=$2 ;;
    --scenes) scenes=$2 ;;
    --repeat) repeat=$2 ;;
    --frame) frame=$2 ;;
    --settings) settings=$2 ;;
    *) echo "usage: bench/decomposition_overhead.sh [--build DIR] [--scenes LIST] [--repeat N] [--frame N] [--settings LIST]" >&2
       exit 2 ;;
  esac
  shift 2
done
cmake --build "$build" --target render_throughput > /dev/null
echo "| scene | resolution | spp | plain s | decomposed s | decomposed / plain | pairs' lowest to highest | components |"
echo "| --- | --- | ---: | ---: | ---: | ---: | --- | --- |"
for scene in $scenes; do
  for setting in $settings; do
    res=${setting%@*} spp=${setting#*@}
    line=$("$build/bin/render_throughput" --scene "scenes/$scene/scene.json" --res "$res" --spp "$spp" --frame "$frame" \
             --repeat "$repeat" --decompose auto 2> /dev/null | grep '^decomposition ')
    # "decomposition NAMES: 5.181 s against 4.361 s plain, overhead 18.8 % (pairs: 1.15 to 1.21)"
    python3 - "$scene" "$res" "$spp" "$line" << 'PY'
import re, sys
scene, res, spp, line = sys.argv[1:]
m = re.match(r"decomposition (.*): ([\d.]+) s against ([\d.]+) s plain.*pairs: ([\d.]+) to ([\d.]+)", line)
names = ", ".join(part.split("=")[0] for part in m.group(1).split(","))
split, plain = float(m.group(2)), float(m.group(3))
print(f"| {scene} | {res} | {spp} | {plain:.3f} | {split:.3f} | {split / plain:.3f} | {m.group(4)} to {m.group(5)} | {names} |")
PY
  done
done
