#!/usr/bin/env bash
# `pathfarm compare` and `compare-seq` as a user runs them: a noisier render has the
# larger error, JSON is well-formed, and bad input is refused with exit status 2.
source "$(dirname "$0")/cli_test_support.sh"
scene="$source_dir/scenes/cornell/scene.json"

for spp in 1 8 64; do
  "$pathfarm" render "$scene" --frames 2:3 --res 32x32 --spp $spp --out "$work/spp$spp" > /dev/null 2>&1 || fail "render $spp spp"
done
relmse() { "$pathfarm" compare "$1" "$2" --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["relmse"])'; }
low=$(relmse "$work/spp1/frame_0002.exr" "$work/spp64/frame_0002.exr") || fail "compare --json"
high=$(relmse "$work/spp8/frame_0002.exr" "$work/spp64/frame_0002.exr") || fail "compare --json"
python3 -c "import sys; sys.exit(0 if $low > $high > 0 else 1)" || fail "1 spp ($low) should be worse than 8 spp ($high)"

"$pathfarm" compare "$work/spp8/frame_0002.exr" "$work/spp64/frame_0002.exr" --crop 0,0,16,16 > "$work/out" 2>&1 || fail "compare --crop"
grep -q "relMSE" "$work/out" || fail "compare prints no relMSE: $(cat "$work/out")"
"$pathfarm" compare-seq "$work/spp8" "$work/spp64" > "$work/out" 2>&1 || fail "compare-seq: $(cat "$work/out")"
grep -q "temporal relMSE (flicker)" "$work/out" || fail "compare-seq prints no temporal error: $(cat "$work/out")"
"$pathfarm" compare-seq "$work/spp8" "$work/spp64" --json | python3 -c 'import json,sys; d=json.load(sys.stdin); assert len(d["frames"]) == 2' \
  || fail "compare-seq --json"

# A mask splits the frame: the error of the pixels inside and of those outside, weighed by
# how many values each compared, is the whole frame's.
json() { "$pathfarm" compare "$work/spp8/frame_0002.exr" "$work/spp64/frame_0002.exr" --json "$@"; }
json > "$work/whole.json" && json --mask "$work/spp64/frame_0002.exr:R" > "$work/inside.json" &&
  json --mask "$work/spp64/frame_0002.exr:R" --outside-mask > "$work/outside.json" || fail "compare --mask"
python3 - "$work" << 'PY' || fail "the masked errors do not add up to the whole frame's"
import json, sys
whole, inside, outside = (json.load(open(f"{sys.argv[1]}/{n}.json")) for n in ("whole", "inside", "outside"))
assert inside["compared"] > 0 and outside["compared"] > 0, (inside, outside)
assert inside["compared"] + outside["compared"] == whole["compared"]
total = inside["relmse"] * inside["compared"] + outside["relmse"] * outside["compared"]
assert abs(total - whole["relmse"] * whole["compared"]) <= 1e-9 * max(1.0, total), (total, whole)
PY

# A channel of whole numbers read as bits (a decomposed render's object ids here): the
# pixels with bit 0 set are those of the odd ids, and no bit set is the id 0 alone.
"$pathfarm" render "$scene" --frames 2 --res 32x32 --spp 4 --decompose default --out "$work/ids" > /dev/null 2>&1 ||
  fail "render with object ids"
ids="$work/ids/frame_0002.exr"
compared() { "$pathfarm" compare "$ids" "$work/spp64/frame_0002.exr" --json --mask "$ids:diffuse_direct.objectid.Y$1" |
  python3 -c 'import json,sys; print(json.load(sys.stdin)["compared"])'; }
odd=$(compared "&1") || fail "compare --mask CHANNEL&BITS"
sum=0
for id in 1 3 5 7 9 11 13 15; do sum=$((sum + $(compared "=$id"))) || fail "compare --mask CHANNEL=VALUE"; done
[ "$odd" -gt 0 ] && [ "$odd" -eq "$sum" ] || fail "&1 compared $odd values, the odd ids $sum"
[ $(($(compared "=0") + $(compared "&65535"))) -eq $((3 * 32 * 32)) ] || fail "=0 and &65535 do not split the frame"

for args in "$work/missing.exr $work/spp64/frame_0002.exr" \
            "$ids $work/spp64/frame_0002.exr --mask $ids:diffuse_direct.objectid.Y&x" \
            "$work/spp8/frame_0002.exr $work/spp64/frame_0002.exr --mask $work/spp64/frame_0002.exr:nothing.Y" \
            "$work/spp8/frame_0002.exr $work/spp64/frame_0002.exr --outside-mask" \
            "$work/spp8/frame_0002.exr $work/spp64/frame_0002.exr --layer reflection.color" \
            "$work/spp8/frame_0002.exr $work/spp64/frame_0002.exr --crop 0,0,99,99"; do
  # shellcheck disable=SC2086
  expect_refused compare $args
done

finish "metrics CLI"
