#!/usr/bin/env bash
# auto's probe alone (docs/pipeline-choice.md): for each scene, a 24-frame `pipeline: "auto"`
# shot on the local farm, stopped once the probe has chosen. Prints each candidate's
# estimate with its standard error, the choice with every score, and what the probe shots
# cost in core-seconds (from the farm's database), to set against a shot's cost. A minute
# or two a scene at the production setting; the whole shot would take ten.
#
#   bench/auto_probe.sh [--build DIR] [--scenes "dolly courtyard"] [--setting small|production]
#                       [--work DIR]   (each scene's farm folder and probe frames kept there)
set -euo pipefail
cd "$(dirname "$0")/.."
build=build scenes="dolly courtyard" res=640x360 spp=256 work=
while (($#)); do
  case "$1" in
    --build) build=$2 ;;
    --scenes) scenes=$2 ;;
    --setting)
      case "$2" in
        small) res=320x180 spp=64 ;;
        production) res=640x360 spp=256 ;;
        *) echo "auto_probe: --setting is small or production, not $2" >&2; exit 2 ;;
      esac ;;
    --work) work=$2 ;;
    *) echo "usage: bench/auto_probe.sh [--build DIR] [--scenes LIST] [--setting small|production] [--work DIR]" >&2
       exit 2 ;;
  esac
  shift 2
done
pathfarm=$build/bin/pathfarm
[ -x "$pathfarm" ] || { echo "auto_probe: no $pathfarm (build first)" >&2; exit 2; }
if [[ -z $work ]]; then
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
for scene in $scenes; do
  out="$work/$scene-$res-$spp"
  rm -rf "$out" && mkdir -p "$out"
  cat > "$out/shot.json" <<JSON
{"name": "$scene-auto", "scene": "$PWD/scenes/$scene/scene.json", "frames": {"start": 0, "end": 23},
 "resolution": [${res%x*}, ${res#*x}], "spp": $spp, "pipeline": "auto", "output": "$out/out"}
JSON
  # Its own process group, so that stopping it stops its scheduler and workers too.
  setsid "$pathfarm" local "$out/shot.json" --workers 2 --keep-farm > "$out/log" 2>&1 &
  farm=$!
  for ((second = 0; second < 1800; ++second)); do
    grep -q 'auto chose\|error' "$out/log" && break
    kill -0 "$farm" 2> /dev/null || break
    sleep 1
  done
  kill -- -"$farm" 2> /dev/null || true
  wait "$farm" 2> /dev/null || true
  echo "== $scene, $res, $spp spp"
  grep -q 'auto chose' "$out/log" || { echo "auto_probe: no choice within 30 minutes; $out/log:" >&2; tail "$out/log" >&2; exit 1; }
  grep 'pipeline auto:.*probe at\|auto chose' "$out/log" | sed 's/^.*info //'
  sqlite3 "$out/out/farm/farm.db" \
    "select 'probe shots: ' || round(sum(t.core_seconds), 1) || ' core-seconds' from tasks t join shots s on s.id = t.shot_id
     where s.name like '%.probe.%'"
done
