#!/usr/bin/env bash
# The Blender add-on's test (addon_test.py) in Debian's Blender, headless, with its own
# user folders so that installing the add-on leaves the user's Blender untouched.
set -euo pipefail
pathfarm=$1 source_dir=$2
work=$(mktemp -d "${TMPDIR:-/tmp}/pathfarm_blender.XXXXXX")
trap '[ -n "${PATHFARM_KEEP:-}" ] || rm -rf "$work"' EXIT
export BLENDER_USER_CONFIG="$work/config" BLENDER_USER_SCRIPTS="$work/scripts"
blender -b --factory-startup --python-exit-code 1 \
  --python "$source_dir/tests/blender/addon_test.py" -- "$pathfarm" "$source_dir" "$work/run" 2>&1 |
  grep -v -E "^(Fra:|Read |Info: |Blender quit|$)"
