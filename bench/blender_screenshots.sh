#!/usr/bin/env bash
# The add-on's screenshot for docs/blender.md (docs/figures/blender/blender_panel.png):
# Blender in a virtual X display renders the test scene's 12 frames on a local farm and
# shows the panel and the frames. Needs PATHFARM_BLENDER=1 ./deploy/setup.sh.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${PATHFARM_BUILD_DIR:-build}
work=$(mktemp -d "${TMPDIR:-/tmp}/pathfarm_screens.XXXXXX")
trap 'rm -rf "$work"' EXIT
export BLENDER_USER_CONFIG="$work/config" BLENDER_USER_SCRIPTS="$work/scripts"
# Opening a file skips the splash screen.
blender -b --factory-startup --python-expr "import bpy; bpy.ops.wm.save_as_mainfile(filepath='$work/start.blend')" \
  > "$work/log" 2>&1
xvfb-run -a -s "-screen 0 1600x900x24" blender "$work/start.blend" --python bench/blender_screenshots.py -- \
  "$PWD/$BUILD_DIR/bin/pathfarm" "$PWD" "$work" > "$work/log" 2>&1 || { tail -20 "$work/log"; exit 1; }
cp "$work/blender_panel.png" docs/figures/blender/
echo "docs/figures/blender/blender_panel.png"
