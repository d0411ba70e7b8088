#!/usr/bin/env bash
# Runs tests/browser/dashboard_test.mjs: the dashboard in Debian's headless Chromium.
# Usage: run_dashboard_test.sh PATHFARM SOURCE_DIR SCREENSHOT.png
# Exits 77 (skipped) when this machine has no Chromium; deploy/setup.sh installs it and
# the test's node modules (npm ci), so CI runs it. The whole run is bounded by `timeout`.
set -euo pipefail
pathfarm=$1
source_dir=$2
screenshot=$3
here=$(cd "$(dirname "$0")" && pwd)
chromium=${PATHFARM_CHROMIUM:-/usr/bin/chromium}

if [ ! -x "$chromium" ]; then
  echo "SKIPPED: no Chromium at $chromium (apt-get install chromium, or deploy/setup.sh)"
  exit 77
fi
if [ ! -d "$here/node_modules/playwright-core" ]; then
  echo "FAILED: $here/node_modules lacks playwright-core: run deploy/setup.sh (or npm ci in tests/browser)" >&2
  exit 1
fi

work=$(mktemp -d "${TMPDIR:-/tmp}/pathfarm-browser-test-XXXXXX")
trap 'rm -rf "$work"' EXIT
mkdir -p "$(dirname "$screenshot")"
timeout --kill-after=10 120 node "$here/dashboard_test.mjs" --pathfarm "$pathfarm" --source "$source_dir" \
  --work "$work" --screenshot "$screenshot" --chromium "$chromium"
