#!/usr/bin/env bash
# `pathfarm render --integrator bdpt|pssmlt|mlt|tmlt` as a user runs them: frames with the
# Metropolis statistics out, bad input refused with exit status 2 before anything is written.
source "$(dirname "$0")/cli_test_support.sh"
scene="$source_dir/scenes/cornell/scene.json"
quiet() { "$@" > "$work/log" 2>&1 || fail "$* failed: $(cat "$work/log")"; }
header() { strings "$1" | grep -c "$2"; }

quiet "$pathfarm" render "$scene" --frames 4:4 --res 16x16 --spp 2 --max-depth 3 --integrator bdpt --out "$work/bdpt"
[ -s "$work/bdpt/frame_0004.exr" ] || fail "bdpt wrote no frame"
quiet "$pathfarm" render "$scene" --frames 4:6 --res 16x16 --max-depth 3 --integrator tmlt --window 3 \
  --mutations-per-pixel 4 --chains 4 --chains-per-block 2 --bootstrap 500 --tune-delta --out "$work/tmlt"
for f in 4 5 6; do [ -s "$work/tmlt/frame_000$f.exr" ] || fail "tmlt wrote no frame $f"; done
grep -q "acceptance.*temporal" "$work/log" || fail "tmlt logged no temporal acceptance: $(cat "$work/log")"
[ "$(header "$work/tmlt/frame_0005.exr" pathfarm.mlt.temporal_acceptance)" -ge 1 ] || fail "no temporal acceptance in the EXR"
quiet "$pathfarm" render "$scene" --frames 4:5 --res 16x16 --max-depth 3 --integrator mlt \
  --mutations-per-pixel 4 --chains 4 --bootstrap 500 --out "$work/mlt"
for f in 4 5; do [ -s "$work/mlt/frame_000$f.exr" ] || fail "mlt wrote no frame $f"; done

expect_refused render "$scene" --frames 4:4 --res 8x8 --integrator pssmlt --spp 4 --out "$work/x"
grep -q "mutations-per-pixel" "$work/log" || fail "no clear message for --spp with pssmlt: $(cat "$work/log")"
expect_refused render "$scene" --frames 4:6 --res 8x8 --integrator mlt --window 3 --out "$work/x"
grep -q "frame by frame" "$work/log" || fail "no clear message for mlt over a window: $(cat "$work/log")"
expect_refused render "$scene" --frames 4:4 --res 8x8 --integrator pt --chains 4 --out "$work/x"
# A scene whose shutter never opens: nothing to sample.
sed 's/"shutter": \[0, 0.5\]/"shutter": [0.3, 0.3]/' "$scene" > "$work/closed.json"
expect_refused render "$work/closed.json" --frames 4:4 --res 8x8 --integrator tmlt --out "$work/x"
grep -qi "shutter" "$work/log" || fail "no clear message for a closed shutter: $(cat "$work/log")"
[ -e "$work/x" ] && fail "a refused command wrote its output"
finish "metropolis CLI"
