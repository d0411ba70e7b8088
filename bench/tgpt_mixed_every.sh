#!/usr/bin/env bash
# tgpt's mixed differences on one sample in N (`--mixed-every N`, docs/gradient-domain.md):
# what the render saves against what the reconstruction loses, per scene and setting.
# Each setting renders frames 0..9 with tgpt once per N (one window of `pathfarm poisson
# --norm l1`, as a tgpt shot does), plain pt at the same spp, and a pt reference with a seed
# of its own. The base paths and temporal offsets are the same bits for every N, so the
# errors compare pair by pair, frame by frame. The time is frame 3's on one thread, the
# median of --repeat renders with the N's taking turns (timed on every core, this 2-core
# machine's runs moved by 20 %).
#
#   bench/tgpt_mixed_every.sh [--build DIR] [--scenes "dolly courtyard"] [--every "1 4"]
#                             [--settings "320x180@64 160x90@256"] [--reference-spp 32] (times the spp)
#                             [--repeat 3] [--work DIR]   (kept; the renders and times it holds are reused)
#
# Columns: frame 3's render seconds; relMSE of the reconstruction
# against the reference, mean over the frames, then less the reference's own noise (what
# pt's relMSE against it puts there: c / reference spp, with c from pt's c / spp + c /
# reference spp); the worst 16x16 tile's relMSE, mean over the frames; cost at equal error
# against N = 1 (time ratio x ratio of the errors less the reference's noise), with a 90 %
# interval from resampling the frames.
set -euo pipefail
cd "$(dirname "$0")/.."
build=build scenes="dolly courtyard" every="1 4" settings="320x180@64 160x90@256" refFactor=32 repeat=3 work=
while (($#)); do
  case "$1" in
    --build) build=$2 ;;
    --scenes) scenes=$2 ;;
    --every) every=$2 ;;
    --settings) settings=$2 ;;
    --reference-spp) refFactor=$2 ;;
    --repeat) repeat=$2 ;;
    --work) work=$2 ;;
    *) echo "usage: bench/tgpt_mixed_every.sh [--build DIR] [--scenes LIST] [--every \"1 4\"] [--settings LIST]" \
            "[--reference-spp FACTOR] [--repeat N] [--work DIR]" >&2
       exit 2 ;;
  esac
  shift 2
done
pathfarm=$build/bin/pathfarm
if [[ -z $work ]]; then
  work=$(mktemp -d "${TMPDIR:-/tmp}/pathfarm_mixed.XXXXXX")
  trap 'rm -rf "$work"' EXIT
fi

# Seconds of one render of frame 3 on one thread, from its log ("... 1.30 s, ... M samples/s").
frameSeconds() {
  "$pathfarm" render "$@" --frames 3:3 --threads 1 --out "$work/timing" 2>&1 | grep -o '[0-9.]* s, [0-9.]* M samples/s' |
    cut -d' ' -f1
}

echo "| scene | resolution | spp | N | frame 3, one thread, s | relMSE | less the reference's noise | worst tile | flicker | time / N=1 | cost at equal error / N=1 (90 % interval) |"
echo "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |"
for scene in $scenes; do
  for setting in $settings; do
    res=${setting%@*} spp=${setting#*@}
    dir=$work/$scene.$setting
    common=(--frames 0:9 --res "$res")
    [[ -d $dir/reference ]] || "$pathfarm" render "scenes/$scene/scene.json" "${common[@]}" \
      --spp $((spp * refFactor)) --seed 9091 --out "$dir/reference" > /dev/null 2>&1
    [[ -d $dir/pt ]] || "$pathfarm" render "scenes/$scene/scene.json" "${common[@]}" --spp "$spp" --out "$dir/pt" \
      > /dev/null 2>&1
    "$pathfarm" compare-seq --json "$dir/pt" "$dir/reference" > "$dir/pt.json"
    for n in $every; do
      [[ -d $dir/rec_$n ]] && continue
      "$pathfarm" render "scenes/$scene/scene.json" "${common[@]}" --spp "$spp" --integrator tgpt --mixed-every "$n" \
        --out "$dir/tgpt_$n" > /dev/null 2>&1
      "$pathfarm" poisson "$dir/tgpt_$n" --window 10 --overlap 0 --norm l1 --out "$dir/rec_$n" > /dev/null 2>&1
    done
    for n in $every; do "$pathfarm" compare-seq --json "$dir/rec_$n" "$dir/reference" > "$dir/rec_$n.json"; done
    if [[ ! -s $dir/seconds ]]; then
      for ((r = 0; r < repeat; ++r)); do
        for n in $every; do
          echo "$n $(frameSeconds "scenes/$scene/scene.json" --res "$res" --spp "$spp" --integrator tgpt \
                       --mixed-every "$n")" >> "$dir/seconds"
        done
      done
    fi
    python3 - "$scene" "$res" "$spp" "$refFactor" "$dir" << 'PY'
import json, random, sys
scene, res, spp, factor, folder = sys.argv[1:]
spp, factor = int(spp), int(factor)
def frames(name, key="relmse"):
    return [f[key] for f in json.load(open(f"{folder}/{name}.json"))["frames"]]
def mean(values):
    return sum(values) / len(values)
# The ratio of the mean errors less the reference's noise, over frames drawn with replacement.
def resampledRatios(errors, first, noise):
    draw = random.Random(1)
    ratios = []
    for _ in range(2000):
        picks = [draw.randrange(len(errors)) for _ in errors]
        ratios.append((mean([errors[i] for i in picks]) - noise) / (mean([first[i] for i in picks]) - noise))
    ratios.sort()
    return ratios[len(ratios) // 20], ratios[len(ratios) * 19 // 20]
# pt's relMSE against the reference is c/spp + c/(factor spp): the reference's share is 1/(factor + 1).
referenceNoise = mean(frames("pt")) / (factor + 1)
times = {}
for line in open(f"{folder}/seconds"):
    n, seconds = line.split()
    times.setdefault(n, []).append(float(seconds))
median = {n: sorted(t)[len(t) // 2] for n, t in times.items()}
everyN = list(times)
first, firstSeconds = frames(f"rec_{everyN[0]}"), median[everyN[0]]
for n in everyN:
    errors, seconds = frames(f"rec_{n}"), median[n]
    ratio = (mean(errors) - referenceNoise) / (mean(first) - referenceNoise)
    low, high = resampledRatios(errors, first, referenceNoise)
    timeRatio = seconds / firstSeconds
    flicker = json.load(open(f"{folder}/rec_{n}.json"))["temporal_relmse"]
    print(f"| {scene} | {res} | {spp} | {n} | {seconds:.2f} | {mean(errors):.6f} | {mean(errors) - referenceNoise:.6f} "
          f"| {mean(frames(f'rec_{n}', 'worst_tile_relmse')):.4f} | {flicker:.4f} | {timeRatio:.3f} "
          f"| {timeRatio * ratio:.3f} ({timeRatio * low:.2f} to {timeRatio * high:.2f}) |")
pt = frames("pt")
print(f"| {scene} | {res} | {spp} | pt | | {mean(pt):.6f} | {mean(pt) - referenceNoise:.6f} "
      f"| {mean(frames('pt', 'worst_tile_relmse')):.4f} | | | |")
PY
  done
done
