#!/usr/bin/env bash
# Peak resident memory of a shot on the local farm (issue 43, "Production resolution"):
# runs `pathfarm local SHOT --workers N` with the arguments given after `--`, samples the
# resident set of `pathfarm local` and of each worker process every second (ps), and
# prints one markdown row: wall time, the peaks (the largest worker's and `pathfarm
# local`'s), all in GiB, and the size of the farm's chunk store at the end (every intermediate chunk
# still kept and the frames; kept with --keep-farm for the count, then removed with the run's
# folder) and its largest size while the shot ran (sampled every 5 s); then the largest peak
# of each kind of task and the tasks' wall seconds summed per kind, from the workers' logs.
#
#   bench/local_memory.sh [--build DIR] [--workers 2] [--label TEXT] SHOT [-- LOCAL-ARGS...]
#   e.g. bench/local_memory.sh scenes/walkthrough/shot.json -- --res 1920x1080 --spp 16 --frames 0:4 --pipeline dui
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/local_shot_args.sh
parse_local_shot_args "bench/local_memory.sh [--build DIR] [--workers N] [--label TEXT] SHOT [-- ARGS...]" "$@"
work=$(mktemp -d)
trap 'kill "$pid" 2> /dev/null || true; rm -rf "$work"' EXIT

start=$SECONDS
"$build/bin/pathfarm" local "$shot" --workers "$workers" --out "$work/frames" --keep-farm "${local_args[@]}" > "$work/local.log" 2>&1 &
pid=$!
declare -A peak  # pid -> peak resident KiB
store_peak=0 tick=0
while kill -0 "$pid" 2> /dev/null; do
  for p in $pid $(pgrep -P "$pid" || true); do
    rss=$(ps -o rss= -p "$p" 2> /dev/null | tr -d ' ' || true)
    [ -n "$rss" ] && ((rss > ${peak[$p]:-0})) && peak[$p]=$rss
  done
  if ((tick++ % 5 == 0)) && [ -d "$work/frames/farm/chunks" ]; then
    size=$(du -sk "$work/frames/farm/chunks" 2> /dev/null | cut -f1 || true)
    [ -n "$size" ] && ((size > store_peak)) && store_peak=$size
  fi
  sleep 1
done
status=0
wait "$pid" || status=$?
seconds=$((SECONDS - start))
if ((status != 0)); then
  echo "local_memory: the shot failed:" >&2
  tail -20 "$work/local.log" >&2
  exit 1
fi
worker=0
for p in "${!peak[@]}"; do [ "$p" != "$pid" ] && ((peak[$p] > worker)) && worker=${peak[$p]}; done
gib() { awk -v k="$1" 'BEGIN { printf "%.2f", k / 1048576 }'; }
store=$(du -sk "$work/frames/farm/chunks" | cut -f1)
((store > store_peak)) && store_peak=$store
echo "| ${label:-$shot $*} | $seconds | $(gib "$worker") | $(gib "${peak[$pid]:-0}") | $(gib "$store") | $(gib "$store_peak") |"
# Each task's own peak, as its worker logged it ("peak resident X GiB": one-slot workers),
# the largest per kind of task; and the tasks' wall seconds summed per kind.
cat "$work"/frames/farm/logs/local-*.log | python3 -c '
import re, sys
kinds, peaks, seconds = {}, {}, {}
for line in sys.stdin:
    started = re.search(r"task (\d+) \((TASK_\w+)\)", line)
    if started: kinds[started.group(1)] = started.group(2)[5:].lower()
    ran = re.search(r"task (\d+): ran ([\d.]+) s.*peak resident ([\d.]+) GiB", line)
    if ran:
        kind = kinds.get(ran.group(1), "?")
        peaks[kind] = max(peaks.get(kind, 0.0), float(ran.group(3)))
        seconds[kind] = seconds.get(kind, 0.0) + float(ran.group(2))
print("largest peak per task kind (GiB): " + ", ".join(f"{k} {v:.2f}" for k, v in sorted(peaks.items())))
print("wall seconds per task kind, summed: " + ", ".join(f"{k} {v:.0f}" for k, v in sorted(seconds.items())))
'
