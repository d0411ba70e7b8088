#!/usr/bin/env bash
# `pathfarm denoise` and `pathfarm upsample` as a user runs them: decomposed frames in,
# filtered frames out with a lower error, and bad input refused with exit status 2.
source "$(dirname "$0")/cli_test_support.sh"
scene="$source_dir/scenes/cornell/scene.json"
quiet() { "$@" > "$work/log" 2>&1 || fail "$* failed: $(cat "$work/log")"; }

quiet "$pathfarm" render "$scene" --frames 4:6 --res 48x48 --spp 4 --decompose default --out "$work/noisy"
quiet "$pathfarm" render "$scene" --frames 5:5 --res 48x48 --spp 256 --out "$work/reference"
quiet "$pathfarm" denoise "$work/noisy/frame_0005.exr" --prev "$work/noisy/frame_0004.exr" \
  --next "$work/noisy/frame_0006.exr" --out "$work/denoised.exr"
relmse() { "$pathfarm" compare "$1" "$2" --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["relmse"])'; }
before=$(relmse "$work/noisy/frame_0005.exr" "$work/reference/frame_0005.exr")
after=$(relmse "$work/denoised.exr" "$work/reference/frame_0005.exr")
python3 -c "import sys; sys.exit(0 if $after < 0.8 * $before else 1)" || fail "denoising did not lower relMSE ($before -> $after)"

# The upsampling protocol: a quarter of the samples at target resolution, 2x2 down, up again.
quiet "$pathfarm" render "$scene" --frames 5:5 --res 24x24 --spp 4 --decompose default --out "$work/low"
quiet "$pathfarm" upsample "$work/low/frame_0005.exr" --guide "$work/noisy/frame_0005.exr" --out "$work/up.exr"
"$pathfarm" compare "$work/up.exr" "$work/up.exr" --layer rerender > /dev/null 2>&1 \
  || fail "the upsampled frame has no rerender layer"

# Bad input: a frame without components, sizes that do not fit, a missing file.
quiet "$pathfarm" render "$scene" --frames 5:5 --res 48x48 --spp 1 --out "$work/plain"
for args in "denoise $work/plain/frame_0005.exr --out $work/x.exr" \
            "upsample $work/low/frame_0005.exr --guide $work/low/frame_0005.exr --out $work/x.exr" \
            "denoise $work/missing.exr --out $work/x.exr"; do
  # shellcheck disable=SC2086
  expect_refused $args
done
[ -e "$work/x.exr" ] && fail "a refused command wrote its output"

finish "filter CLI"
