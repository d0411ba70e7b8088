#!/usr/bin/env bash
# glTF scenes as a user brings them: `pathfarm render` and `pathfarm local` of a .glb, a broken file refused
# with exit status 2 naming the file and the JSON pointer, and the showroom (a JSON scene
# including a .glb, with punctual lights added) finished by every pipeline on a local farm
# with finite frames.
source "$(dirname "$0")/cli_test_support.sh"
showroom="$source_dir/scenes/showroom"

"$pathfarm" render "$showroom/showroom.glb" --frames 5:5 --res 32x18 --spp 2 --out "$work/glb" > "$work/log" 2>&1 ||
  fail "render of showroom.glb failed: $(cat "$work/log")"
[ -s "$work/glb/frame_0005.exr" ] || fail "no frame from showroom.glb"

python3 - "$showroom/showroom.glb" "$work/broken.glb" <<'PY'
import json, struct, sys
data = open(sys.argv[1], "rb").read()
length = struct.unpack_from("<I", data, 12)[0]
gltf = json.loads(data[20:20 + length])
gltf["accessors"][0]["count"] += 1000   # the first accessor now overruns its buffer view
text = json.dumps(gltf).encode()
text += b" " * (-len(text) % 4)
rest = data[20 + length:]
body = struct.pack("<I4s", len(text), b"JSON") + text + rest
open(sys.argv[2], "wb").write(struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body)
PY
# The .glb handed to `pathfarm local` as it is, with shot keys as options: a pt shot of
# it renders the bytes `pathfarm render` wrote above, under the name --frame-names gives,
# and --on-done runs when it is done.
cp "$showroom/showroom.glb" "$work/showroom.glb"
"$pathfarm" local "$work/showroom.glb" --frames 5 --res 32x18 --spp 2 --pipeline pt --workers 1 \
  --frame-names '{shot}/{frame:03d}.exr' \
  --on-done 'echo "$PATHFARM_SHOT_NAME $PATHFARM_SHOT_STATE $PATHFARM_SHOT_OUTPUT" > "$PATHFARM_SHOT_OUTPUT/hook"' \
  > "$work/log" 2>&1 || fail "local of showroom.glb failed: $(tail -5 "$work/log")"
cmp -s "$work/output/showroom/showroom/005.exr" "$work/glb/frame_0005.exr" ||
  fail "local of showroom.glb differs from its render: $(tail -5 "$work/log")"
[ "$(cat "$work/output/showroom/hook" 2>/dev/null)" = "showroom SHOT_DONE $work/output/showroom" ] ||
  fail "--on-done: $(cat "$work/output/showroom/hook" 2>&1)"
expect_refused local "$work/showroom.glb" --res 32 --workers 1
grep -q -- '--res "32": expected WIDTHxHEIGHT' "$work/log" || fail "--res 32 message: $(cat "$work/log")"

expect_refused render "$work/broken.glb" --out "$work/broken"
grep -q "broken.glb: /meshes/0/primitives/0/attributes/POSITION: .* overrun" "$work/log" ||
  fail "broken.glb message: $(cat "$work/log")"

# The showroom as its scene.json sets it up, with a spot, a point and a moving
# directional light added: every pipeline meets punctual lights beside area lights and
# the sky map.
cat > "$work/lit_showroom.json" <<JSON
{"include": {"file": "$showroom/showroom.glb", "camera": "dolly", "shutter": [0, 0.5]},
 "environment": {"map": "$source_dir/scenes/sky/sky.hdr", "rotation": 60},
 "lights": [
   {"type": "spot", "position": [-1, 2.5, 1], "direction": [0.4, -1, -0.3], "intensity": 20,
    "inner_cone": 15, "outer_cone": 30},
   {"type": "point", "position": [1, 1.2, -1], "intensity": [4, 3, 2]},
   {"type": "directional", "intensity": 1.5, "transform": {"rotate": {"axis": [1, 0, 0], "angle": -60}},
    "animation": {"rotate": [{"frame": 0, "axis": [1, 0, 0], "angle": -60},
                             {"frame": 3, "axis": [1, 0.3, 0], "angle": -50}]}}]}
JSON
for pipeline in pt d du di dui tgpt pssmlt mlt tmlt; do
  cat > "$work/$pipeline.json" <<JSON
{"name": "showroom-$pipeline", "scene": "$work/lit_showroom.json", "frames": {"start": 0, "end": 3},
 "resolution": [32, 18], "spp": 2, "max_depth": 4, "tile": 16, "pipeline": "$pipeline", "output": "out_$pipeline"}
JSON
  "$pathfarm" local "$work/$pipeline.json" --workers 2 --threads 1 > "$work/log" 2>&1 ||
    { fail "$pipeline on the showroom failed: $(tail -5 "$work/log")"; continue; }
  for frame in 0 1 2 3; do
    exr="$work/out_$pipeline/frame_000$frame.exr"
    [ -s "$exr" ] || { fail "$pipeline: no frame $frame"; continue; }
    # compare counts the pixels that are NaN or infinite.
    "$pathfarm" compare "$exr" "$exr" --json > "$work/compare" 2>&1 || fail "$pipeline: compare failed"
    grep -q '"nonfinite": 0,' "$work/compare" || fail "$pipeline frame $frame not finite: $(cat "$work/compare")"
  done
done

finish "glTF CLI"
