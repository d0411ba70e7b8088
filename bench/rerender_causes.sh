#!/usr/bin/env bash
# Whether re-rendering helps, per cause: for each check that flags an in-between frame's
# pixels (the interpolate task's rerender_causes.Y, worker/interpolation_tasks.cpp), the
# relMSE against the reference of the interpolation's own value there and of the final,
# re-rendered frame, over the pixels the check flagged alone and over all it flagged,
# summed over the shot's interpolated evaluation frames. Prints a markdown table
# (docs/performance.md, "Which flagged pixels a re-render improves").
#
# The shot must have been rendered keeping its farm and intermediate chunks, with its
# frames under their default names:
#   build/bin/pathfarm local SHOT --keep-farm --keep-intermediates
#   bench/rerender_causes.sh [--build DIR] OUTPUT_FOLDER
set -euo pipefail
build="$(cd "$(dirname "$0")/.." && pwd)/build"
if [ "${1:-}" = --build ]; then build=$(cd "$2" && pwd); shift 2; fi
out=$(cd "${1:?usage: bench/rerender_causes.sh [--build DIR] OUTPUT_FOLDER}" && pwd)
pathfarm="$build/bin/pathfarm"
db="$out/farm/farm.db"
[ -f "$db" ] || { echo "$out/farm/farm.db: none (render the shot with --keep-farm --keep-intermediates)" >&2; exit 2; }
chunk() { echo "$out/farm/chunks/objects/${1:0:2}/${1:2}"; }
params() { sqlite3 "$db" "SELECT hex(params) FROM tasks WHERE id = $1" | xxd -r -p | protoc --decode_raw; }
field() { grep -m1 "^$1:" | cut -d' ' -f2; }  # a top-level field of TaskParams

# The evaluation task's inputs: each evaluated frame's interpolation and reference render.
declare -A interpolated reference
evaluation=$(sqlite3 "$db" "SELECT id FROM tasks WHERE kind = 10")  # TASK_EVALUATE
for input in $(sqlite3 "$db" "SELECT depends_on FROM task_deps WHERE task_id = $evaluation"); do
  kind=$(sqlite3 "$db" "SELECT kind FROM tasks WHERE id = $input")
  sha=$(sqlite3 "$db" "SELECT output_sha FROM tasks WHERE id = $input")
  decoded=$(params "$input")
  frame=$(field 1 <<< "$decoded")
  [ "$kind" = 8 ] && interpolated[$frame]=$sha  # TASK_INTERPOLATE
  [ "$kind" = 2 ] && [ "$(field 3 <<< "$decoded")" = 6 ] && reference[$frame]=$sha  # ROLE_REFERENCE
done
[ ${#interpolated[@]} -gt 0 ] || { echo "no interpolated frame among the evaluation frames" >&2; exit 2; }

# relMSE over the masked pixels of every evaluated frame, weighed by the values compared,
# and the pixels: "ERROR PIXELS".
masked() {  # final|interpolated MASK
  local sum=0 values=0 frame image measured
  for frame in "${!interpolated[@]}"; do
    image=$(chunk "${interpolated[$frame]}")
    [ "$1" = final ] && image="$out/$(printf 'frame_%04d.exr' "$frame")"
    measured=$("$pathfarm" compare "$image" "$(chunk "${reference[$frame]}")" --json \
      --mask "$(chunk "${interpolated[$frame]}"):rerender_causes.Y$2" | python3 -c \
      'import json,sys; d=json.load(sys.stdin); print(d["relmse"] * d["compared"], d["compared"])')
    sum=$(python3 -c "print($sum + ${measured% *})")
    values=$((values + ${measured#* }))
  done
  python3 -c "print('%.4g %d' % ($sum / max($values, 1), $values / 3))"
}

echo "frames ${!interpolated[*]} of $out"
echo "| cause | pixels alone | alone: interpolated → re-rendered | pixels in all | all: interpolated → re-rendered |"
echo "| --- | ---: | --- | ---: | --- |"
bit=1
for cause in holes silhouettes untracked illumination mismatch light_edges light_mismatch moving_caustics; do
  read -r aloneInterpolated alonePixels <<< "$(masked interpolated "=$bit")"
  read -r aloneFinal _ <<< "$(masked final "=$bit")"
  read -r allInterpolated allPixels <<< "$(masked interpolated "&$bit")"
  read -r allFinal _ <<< "$(masked final "&$bit")"
  echo "| $cause | $alonePixels | $aloneInterpolated → $aloneFinal | $allPixels | $allInterpolated → $allFinal |"
  bit=$((bit * 2))
done
