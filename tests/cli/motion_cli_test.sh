#!/usr/bin/env bash
# `pathfarm flow`, `interpolate` and `motionblur` as a user runs them: outputs with the
# promised layers, and bad input refused with exit status 2.
source "$(dirname "$0")/cli_test_support.sh"
scene="$source_dir/scenes/cornell/scene.json"
quiet() { "$@" > "$work/log" 2>&1 || fail "$* failed: $(cat "$work/log")"; }
has_layer() { "$pathfarm" compare "$1" "$1" --layer "$2" > /dev/null 2>&1 || fail "$1 has no layer $2"; }

quiet "$pathfarm" render "$scene" --frames 0:2 --res 32x32 --spp 2 --decompose default --out "$work/seq"
quiet "$pathfarm" flow "$work/seq/frame_0000.exr" "$work/seq/frame_0001.exr" --out "$work/flow.exr"
has_layer "$work/flow.exr" flow
has_layer "$work/flow.exr" occlusion
quiet "$pathfarm" interpolate "$work/seq/frame_0000.exr" "$work/seq/frame_0002.exr" --at 0.5 \
  --guides "$work/seq/frame_0001.exr" --out "$work/mid.exr"
has_layer "$work/mid.exr" rerender
quiet "$pathfarm" motionblur "$work/seq/frame_0001.exr" --exposure 0.5 --out "$work/blur.exr"
has_layer "$work/blur.exr" ""

quiet "$pathfarm" render "$scene" --frames 0:0 --res 16x16 --spp 1 --out "$work/plain"
for args in "flow $work/plain/frame_0000.exr $work/seq/frame_0001.exr --out $work/x.exr" \
            "interpolate $work/seq/frame_0000.exr $work/seq/frame_0002.exr --at 1.5 --out $work/x.exr" \
            "interpolate $work/seq/frame_0000.exr $work/plain/frame_0000.exr --at 0.5 --out $work/x.exr" \
            "motionblur $work/missing.exr --out $work/x.exr"; do
  # shellcheck disable=SC2086
  expect_refused $args
done
[ -e "$work/x.exr" ] && fail "a refused command wrote its output"
finish "motion CLI"
