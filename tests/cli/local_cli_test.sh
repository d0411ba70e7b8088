#!/usr/bin/env bash
# `pathfarm local` and `pathfarm preview` as a user runs them: a tiny shot on two local
# workers gives the same EXR bytes as `pathfarm render`, previews appear next to the
# frames, and a bad shot is refused with exit status 2 before any farm starts.
source "$(dirname "$0")/cli_test_support.sh"

cat > "$work/shot.json" <<JSON
{"name": "tiny", "scene": "$source_dir/scenes/cornell/scene.json", "frames": {"start": 1, "end": 2},
 "resolution": [40, 30], "spp": 2, "max_depth": 6, "tile": 16, "output": "farm_out", "pipeline": "pt"}
JSON
"$pathfarm" local "$work/shot.json" --workers 2 --threads 1 > "$work/log" 2>&1 || fail "local failed: $(cat "$work/log")"
"$pathfarm" render "$source_dir/scenes/cornell/scene.json" --frames 1:2 --res 40x30 --spp 2 --max-depth 6 \
  --out "$work/render" > "$work/render.log" 2>&1 || fail "render failed"
for f in frame_0001.exr frame_0002.exr; do
  cmp -s "$work/farm_out/$f" "$work/render/$f" || fail "$f from the farm differs from pathfarm render"
done
# Its workers' command lines name their cache under the output folder.
pgrep -f "$work/farm_out/farm/cache" > /dev/null && fail "workers left running"
# A finished shot keeps its frames, its report and the logs; the intermediate data goes.
[ -d "$work/farm_out/farm/logs" ] || fail "the farm's logs were removed"
for gone in chunks cache farm.db; do [ -e "$work/farm_out/farm/$gone" ] && fail "farm/$gone was kept"; done
grep -q "removed .* MB of intermediate" "$work/log" || fail "no word of the removed data: $(cat "$work/log")"

# The embedded scheduler takes the scheduler's size options: frames assembled from inputs
# streamed two at a time are the same bytes, and a shot over the task limit is refused.
"$pathfarm" local "$work/shot.json" --workers 2 --threads 1 --lease-inputs 2 --out "$work/streamed" > "$work/log" 2>&1 ||
  fail "local with --lease-inputs 2 failed: $(cat "$work/log")"
cmp -s "$work/streamed/frame_0002.exr" "$work/render/frame_0002.exr" || fail "frame assembled from streamed inputs differs"
"$pathfarm" local "$work/shot.json" --workers 1 --max-tasks-per-shot 5 --out "$work/limited" > "$work/log" 2>&1 &&
  fail "a shot of 14 tasks ran under --max-tasks-per-shot 5"
grep -q "more than this scheduler takes (5, --max-tasks-per-shot)" "$work/log" || fail "task limit message: $(cat "$work/log")"

# A decomposed shot: every component's buffers come back from the tiles unchanged.
cat > "$work/decomposed.json" <<JSON
{"name": "split", "scene": "$source_dir/scenes/cornell/scene.json", "frames": {"start": 2, "end": 2},
 "resolution": [40, 30], "spp": 2, "max_depth": 6, "tile": 16, "output": "split_out", "decompose": "default",
 "pipeline": "pt"}
JSON
"$pathfarm" local "$work/decomposed.json" --workers 2 --threads 1 --keep-farm > "$work/log" 2>&1 || fail "decomposed local failed: $(cat "$work/log")"
[ -d "$work/split_out/farm/chunks" ] || fail "--keep-farm did not keep the chunks"
"$pathfarm" render "$source_dir/scenes/cornell/scene.json" --frames 2:2 --res 40x30 --spp 2 --max-depth 6 \
  --decompose default --out "$work/split_render" > "$work/render.log" 2>&1 || fail "decomposed render failed"
cmp -s "$work/split_out/frame_0002.exr" "$work/split_render/frame_0002.exr" || fail "decomposed farm frame differs"

"$pathfarm" preview "$work/farm_out" > "$work/log" 2>&1 || fail "preview failed: $(cat "$work/log")"
[ -s "$work/farm_out/frame_0001.png" ] || fail "no preview written"

echo '{"scene": "missing.json"}' > "$work/bad.json"
expect_refused local "$work/bad.json" --out "$work/bad_out"
grep -q "missing.json: cannot open the scene file" "$work/log" || fail "bad shot message: $(cat "$work/log")"
[ -e "$work/bad_out" ] && fail "a bad shot started a farm"

finish "local CLI"
