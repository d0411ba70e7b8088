#!/usr/bin/env bash
# What each kind of task of a shot cost and wrote: runs `pathfarm local SHOT --workers N`
# (with the arguments after `--`), keeping every intermediate chunk, and prints one
# markdown row per kind of task from the farm's database: the tasks, their core-seconds
# and the megabytes of their output chunks; then the shot's wall time. For A/B runs of
# two builds, run it for each in turn, more than once: on this 2-core machine the
# core-seconds of the same shot move by about 5 % between runs.
#
#   bench/task_kinds.sh [--build DIR] [--workers 2] [--label TEXT] SHOT [-- LOCAL-ARGS...]
#   e.g. bench/task_kinds.sh scenes/dolly/shot.json -- --res 640x360 --spp 256 --frames 8:10 --pipeline d \
#          --set 'evaluation_frames=[]'
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/local_shot_args.sh
parse_local_shot_args "bench/task_kinds.sh [--build DIR] [--workers N] [--label TEXT] SHOT [-- ARGS...]" "$@"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
start=$SECONDS
"$build/bin/pathfarm" local "$shot" --workers "$workers" --out "$work/frames" --keep-farm --keep-intermediates "${local_args[@]}" \
  > "$work/local.log" 2>&1 || { tail "$work/local.log" >&2; exit 1; }
[ -z "$label" ] || echo "$label"
echo "| task kind | tasks | core-seconds | output MB |"
echo "| --- | ---: | ---: | ---: |"
# Task kinds by number: proto/pathfarm/shot.proto's TaskKind.
sqlite3 -separator ' | ' "$work/frames/farm/farm.db" \
  "SELECT '| ' || t.kind, COUNT(*), printf('%.2f', SUM(t.core_seconds)), printf('%.1f', COALESCE(SUM(c.size), 0) / 1e6) || ' |'
   FROM tasks t LEFT JOIN chunks c ON c.sha256 = t.output_sha GROUP BY t.kind ORDER BY t.kind"
echo
echo "wall time: $((SECONDS - start)) s"
