#!/usr/bin/env bash
# `pathfarm render` as a user runs it: frames and previews written, bad input refused
# with exit status 2, a clear message, and no output.
source "$(dirname "$0")/cli_test_support.sh"

# A good render: two frames and their previews. The log goes to standard error: standard
# output carries only what a script reads (a shot's id from submit, listings, reports).
if ! "$pathfarm" render "$source_dir/scenes/cornell/scene.json" --frames 3:4 --spp 2 --res 24x16 \
    --out "$work/out" --png > "$work/stdout" 2> "$work/log"; then
  fail "render failed: $(cat "$work/log")"
fi
[ -s "$work/stdout" ] && fail "render logged to standard output: $(cat "$work/stdout")"
grep -q "EXR frames and PNG previews in" "$work/log" || fail "no log on standard error: $(cat "$work/log")"
for f in frame_0003.exr frame_0004.exr frame_0003.png frame_0004.png; do
  [ -s "$work/out/$f" ] || fail "missing $f"
done
[ -e "$work/out/frame_0005.exr" ] && fail "rendered past the last frame"
# One buffer, or one channel of it as grey, previewed beside the frame.
for layer in variance variance.G; do
  "$pathfarm" preview --layer "$layer" "$work/out/frame_0003.exr" > "$work/log" 2>&1 || fail "preview --layer $layer: $(cat "$work/log")"
  [ -s "$work/out/frame_0003.$layer.png" ] || fail "no $layer preview"
done
"$pathfarm" preview --layer variance.Q "$work/out/frame_0003.exr" > "$work/log" 2>&1 && fail "previewed a missing channel"
grep -q 'no layer or channel "variance.Q"' "$work/log" || fail "missing channel message: $(cat "$work/log")"
ls "$work/out" | grep -q partial && fail "left a partial file behind"

# --seed: the scene's own seed (0) gives the same bits as none; another gives other bits.
for seed in 0 7; do
  "$pathfarm" render "$source_dir/scenes/cornell/scene.json" --frames 3:3 --spp 2 --res 24x16 --seed $seed \
    --out "$work/seed$seed" 2> "$work/log" || fail "render --seed $seed: $(cat "$work/log")"
done
cmp -s "$work/seed0/frame_0003.exr" "$work/out/frame_0003.exr" || fail "--seed 0 differs from the scene's seed"
cmp -s "$work/seed7/frame_0003.exr" "$work/out/frame_0003.exr" && fail "--seed 7 rendered the scene's samples"

# A bad scene: exit 2, the key path in the message, no output folder.
cat > "$work/bad.json" <<'JSON'
{"camera": {"position": [0, 0, 1], "look_at": [0, 0, 0]},
 "materials": {"glass": {"type": "dielectric"}},
 "shapes": [{"type": "sphere", "radius": 1, "material": "glas"}]}
JSON
expect_refused render "$work/bad.json" --out "$work/bad_out"
grep -q 'bad.json: shapes\[0\].material: unknown material "glas"' "$work/log" || fail "bad scene message: $(cat "$work/log")"
[ -e "$work/bad_out" ] && fail "bad scene created its output folder"

# Bad arguments: exit 2 as well.
for args in "--frames 5:2" "--frames x" "--res 10" "--spp 0" "--decompose x=E(D"; do
  # shellcheck disable=SC2086
  expect_refused render "$source_dir/scenes/cornell/scene.json" $args --out "$work/args_out"
done
[ -e "$work/args_out" ] && fail "bad arguments created the output folder"

expect_refused render "$work/missing.json" --out "$work/x"
grep -q "missing.json: cannot open" "$work/log" || fail "missing scene message: $(cat "$work/log")"

finish "render CLI"
