#!/usr/bin/env bash
# The chaos run (issue 19): a shot rendered on a farm whose workers are SIGKILLed every few
# seconds (and started again) and whose scheduler is SIGKILLed and restarted on its database
# a few times; every frame must come out byte-identical to an undisturbed `pathfarm local`
# run of the same shot. One line per pipeline: kills survived, time, frames identical.
#
#   bench/chaos.sh [--build DIR] [--pipelines "dui tgpt tmlt"] [--frames 0:5] [--res 96x64]
#                  [--spp 16] [--workers 3] [--kill-every 2] [--scheduler-kills 2] [--limit 600]
#                  [--soak-minutes 0]
# With --soak-minutes M the pipelines run again, round after round, until M minutes passed.
#
# CI runs a small one (ctest chaos.small); a long soak is e.g.
#   bench/chaos.sh --frames 0:23 --res 192x192 --spp 64 --workers 6 --scheduler-kills 6
# Everything listens on 127.0.0.1 only; every wait is bounded by --limit seconds.
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/frames_identical.sh
build=build pipelines="dui tgpt tmlt" frames=0:5 res=96x64 spp=16 workers=3 every=2 schedulerKills=2 limit=600
soakMinutes=0
while (($#)); do
  case "$1" in
    --build) build=$2 ;;
    --pipelines) pipelines=$2 ;;
    --frames) frames=$2 ;;
    --res) res=$2 ;;
    --spp) spp=$2 ;;
    --workers) workers=$2 ;;
    --kill-every) every=$2 ;;
    --scheduler-kills) schedulerKills=$2 ;;
    --limit) limit=$2 ;;
    --soak-minutes) soakMinutes=$2 ;;
    *) echo "chaos: unknown option $1" >&2; exit 2 ;;
  esac
  shift 2
done
case $build in /*) ;; *) build=$PWD/$build ;; esac
pathfarm="$build/bin/pathfarm"
[ -x "$pathfarm" ] || { echo "chaos: no $pathfarm (build first)" >&2; exit 2; }
work=$(mktemp -d "${TMPDIR:-/tmp}/pathfarm-chaos-XXXXXX")
scheduler_pid="" worker_pids=()
cleanup() {
  for pid in $scheduler_pid "${worker_pids[@]}"; do kill -9 "$pid" 2> /dev/null || true; done
  wait 2> /dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

start_scheduler() {  # $1: the address to listen on (127.0.0.1:0 the first time)
  rm -f "$work/port"
  "$pathfarm" scheduler --listen "$1" --port-file "$work/port" --db "$work/farm.db" --store "$work/store" \
    --lease-seconds 3 --retry-backoff 0.2 >> "$work/scheduler.log" 2>&1 &
  scheduler_pid=$!
  for _ in $(seq 100); do [ -s "$work/port" ] && return 0; sleep 0.1; done
  echo "chaos: the scheduler wrote no port; its log:" >&2; tail -20 "$work/scheduler.log" >&2; exit 1
}
start_worker() {  # $1: slot index
  # The scheduler keeps its port across restarts: read from $port, not from the port file,
  # which a restart removes (the background command could read it at that moment).
  "$pathfarm" worker --scheduler "127.0.0.1:$port" --threads 1 --name "chaos-$1" \
    --cache "$work/cache-$1" >> "$work/worker-$1.log" 2>&1 &
  worker_pids[$1]=$!
}
state_of() {  # the state word of shot $1 (empty while the scheduler is away)
  [ -s "$work/port" ] || return 0
  "$pathfarm" status "$1" --scheduler "127.0.0.1:$(cat "$work/port")" 2> /dev/null | head -1 |
    grep -oE 'SHOT_[A-Z]+' | head -1 | sed 's/SHOT_//' || true
}

echo "| pipeline | frames | workers | worker kills | scheduler kills | seconds | frames identical |"
echo "| --- | ---: | ---: | ---: | ---: | ---: | --- |"
run_pipeline() {  # $1: the pipeline; sets status=1 unless every frame is identical
  local pipeline=$1
  shot="$work/$pipeline.json"
  cat > "$shot" <<JSON
{"name": "chaos-$pipeline", "scene": "$PWD/scenes/cornell/scene.json",
 "frames": {"start": ${frames%:*}, "end": ${frames#*:}}, "resolution": [${res%x*}, ${res#*x}],
 "spp": $spp, "tile": 32, "pipeline": "$pipeline", "max_attempts": 3, "output": "$work/undisturbed-$pipeline"}
JSON
  # Rendered once; later rounds compare against the same frames.
  [ -d "$work/undisturbed-$pipeline" ] || "$pathfarm" local "$shot" --workers 2 > "$work/local-$pipeline.log" 2>&1 ||
    { echo "chaos: the undisturbed run failed:" >&2; tail -20 "$work/local-$pipeline.log" >&2; exit 1; }

  rm -rf "$work/farm.db"* "$work/store" "$work"/cache-*
  start_scheduler 127.0.0.1:0
  port=$(cat "$work/port")
  for i in $(seq 0 $((workers - 1))); do start_worker "$i"; done
  id=$("$pathfarm" submit "$shot" --shared-paths --scheduler "127.0.0.1:$port" | grep -E '^[0-9]+$')
  started=$SECONDS kills=0 restarts=0 state=""
  # The scheduler is killed after every second worker kill, up to --scheduler-kills times.
  while ((SECONDS - started < limit)); do
    sleep "$every"
    state=$(state_of "$id")
    [[ ${state,,} == done || ${state,,} == failed || ${state,,} == cancelled ]] && break
    victim=$((RANDOM % workers))
    kill -9 "${worker_pids[$victim]}" 2> /dev/null || true
    wait "${worker_pids[$victim]}" 2> /dev/null || true
    start_worker "$victim"
    kills=$((kills + 1))
    if ((restarts < schedulerKills && kills % 2 == 0)); then
      kill -9 "$scheduler_pid"; wait "$scheduler_pid" 2> /dev/null || true
      start_scheduler "127.0.0.1:$port"
      restarts=$((restarts + 1))
    fi
  done
  seconds=$((SECONDS - started))
  identical="no: shot ${state:-unreachable}"
  if [[ ${state,,} == done ]]; then
    "$pathfarm" fetch "$id" --out "$work/chaos-$pipeline" --scheduler "127.0.0.1:$port" > /dev/null
    identical=$(frames_identical "$work/undisturbed-$pipeline" "$work/chaos-$pipeline") || status=1
  else
    status=1
    "$pathfarm" status "$id" --scheduler "127.0.0.1:$port" 2> /dev/null | tail -5 >&2 || true
  fi
  label=$pipeline
  ((soakMinutes > 0)) && label="$pipeline, round $round"
  echo "| $label | $frames | $workers | $kills | $restarts | $seconds | $identical |"
  for pid in $scheduler_pid "${worker_pids[@]}"; do kill -9 "$pid" 2> /dev/null || true; done
  wait 2> /dev/null || true
  scheduler_pid="" worker_pids=()
}

status=0 round=1
while :; do
  for pipeline in $pipelines; do run_pipeline "$pipeline"; done
  ((soakMinutes > 0 && SECONDS < soakMinutes * 60)) || break
  round=$((round + 1))
done
echo "chaos: $round round(s) in $((SECONDS / 60)) min $((SECONDS % 60)) s"
exit $status
