#!/usr/bin/env bash
# The farm under load (issue 19): one shot of --tasks no-op tasks through a real scheduler
# process and --workers worker processes on 127.0.0.1, with a probe timing heartbeats the
# whole time (build/bin/farm_heartbeat_probe). Prints the submit's time, tasks per second
# from submit to done, the heartbeat latencies while the shot is submitted and while it
# runs, and the scheduler's peak memory and database size.
#
#   bench/farm_load.sh [--build DIR] [--workers 64] [--tasks 100000] [--limit 1800]
set -euo pipefail
cd "$(dirname "$0")/.."
build=build workers=64 tasks=100000 limit=1800
while (($#)); do
  case "$1" in
    --build) build=$2 ;;
    --workers) workers=$2 ;;
    --tasks) tasks=$2 ;;
    --limit) limit=$2 ;;
    *) echo "farm_load: unknown option $1" >&2; exit 2 ;;
  esac
  shift 2
done
case $build in /*) ;; *) build=$PWD/$build ;; esac
pathfarm="$build/bin/pathfarm" probe="$build/bin/farm_heartbeat_probe"
cmake --build "$build" --target pathfarm farm_heartbeat_probe > /dev/null || { echo "farm_load: cannot build in $build" >&2; exit 2; }
for program in "$pathfarm" "$probe"; do [ -x "$program" ] || { echo "farm_load: no $program (build first)" >&2; exit 2; }; done
work=$(mktemp -d "${TMPDIR:-/tmp}/pathfarm-load-XXXXXX")
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill -9 "$pid" 2> /dev/null || true; done
  wait 2> /dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

"$pathfarm" scheduler --listen 127.0.0.1:0 --port-file "$work/port" --db "$work/farm.db" --store "$work/store" \
  > "$work/scheduler.log" 2>&1 &
scheduler_pid=$!
pids+=("$scheduler_pid")
for _ in $(seq 100); do [ -s "$work/port" ] && break; sleep 0.1; done
[ -s "$work/port" ] || { echo "farm_load: the scheduler wrote no port" >&2; tail "$work/scheduler.log" >&2; exit 1; }
address="127.0.0.1:$(cat "$work/port")"
for i in $(seq "$workers"); do
  "$pathfarm" worker --scheduler "$address" --threads 1 --name "load-$i" --cache "$work/cache-$i" \
    > "$work/worker-$i.log" 2>&1 &
  pids+=($!)
done
sleep 3  # every worker registered and long-polling

# A probe per phase; closing its stdin ends it.
start_probe() {  # $1: phase name
  exec {probe_in}> >("$probe" --scheduler "$address" --seconds "$limit" > "$work/probe-$1.txt" 2>&1)
  pids+=($!)
}
stop_probe() { exec {probe_in}>&-; }

cat > "$work/load.json" <<JSON
{"name": "load", "pipeline": "noop", "noop_tasks": $tasks}
JSON
start_probe submit
submit_start=$(date +%s.%N)
id=$("$pathfarm" submit "$work/load.json" --shared-paths --scheduler "$address" | grep -E '^[0-9]+$')
submit_end=$(date +%s.%N)
stop_probe
start_probe run
state=""
while :; do
  state=$("$pathfarm" status "$id" --scheduler "$address" | head -1 | grep -oE 'SHOT_[A-Z]+' | head -1)
  [[ $state == SHOT_DONE || $state == SHOT_FAILED || $state == SHOT_CANCELLED ]] && break
  (($(date +%s) - ${submit_start%.*} > limit)) && { echo "farm_load: not done in $limit s" >&2; exit 1; }
  sleep 0.5
done
done_at=$(date +%s.%N)
stop_probe
sleep 0.5  # the probes print
[[ $state == SHOT_DONE ]] || { echo "farm_load: the shot ended $state" >&2; exit 1; }

peak=$(awk '/VmHWM/ {print $2}' "/proc/$scheduler_pid/status")
database=$(du -ck "$work"/farm.db* | tail -1 | cut -f1)
awk -v t="$tasks" -v w="$workers" -v s0="$submit_start" -v s1="$submit_end" -v d="$done_at" -v peak="$peak" \
  -v db="$database" 'BEGIN {
  printf "%d no-op tasks, %d worker processes, 127.0.0.1\n", t, w
  printf "submit: %.1f s\n", s1 - s0
  printf "submit to done: %.1f s, %.0f tasks/s\n", d - s0, t / (d - s0)
  printf "scheduler peak memory: %.0f MiB; database %.0f MiB\n", peak / 1024, db / 1024 }'
echo "heartbeats while submitting: $(cat "$work/probe-submit.txt")"
echo "heartbeats while running:    $(cat "$work/probe-run.txt")"
