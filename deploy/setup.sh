#!/usr/bin/env bash
# Installs pathfarm's build dependencies from Debian's packages (idempotent,
# non-interactive) and builds a Release tree in build/.
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(
  build-essential cmake ninja-build pkg-config git python3 procps
  iproute2 openssl sqlite3
  libembree-dev libopenexr-dev libimath-dev libtbb-dev
  libgrpc++-dev protobuf-compiler-grpc libprotobuf-dev protobuf-compiler
  libsqlite3-dev libssl-dev libspdlog-dev libfmt-dev libgtest-dev libgmock-dev
  libcli11-dev nlohmann-json3-dev libtinyobjloader-dev libstb-dev libtinygltf-dev
  clang libclang-rt-14-dev libcpp-httplib-dev prometheus-cpp-dev
  chromium nodejs
)
# Blender, for the add-on in clients/blender, its test and its screenshots (Xvfb; docs/blender.md):
# wanted by deploy/test.sh (PATHFARM_BLENDER=1), not by the demo.
BLENDER_PACKAGES=(blender python3-numpy xvfb xauth)

installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive

missing=()
for package in "${PACKAGES[@]}"; do installed "$package" || missing+=("$package"); done
# Debian's nodejs comes without npm; a Node.js installed another way may bring its own.
command -v npm > /dev/null || missing+=(npm)
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# Blender installs while pathfarm compiles: its minute of downloading and unpacking would
# otherwise add to every CI run.
blender_missing=()
if [ "${PATHFARM_BLENDER:-0}" = 1 ]; then
  for package in "${BLENDER_PACKAGES[@]}"; do installed "$package" || blender_missing+=("$package"); done
fi
blender_install="" blender_log=""
if ((${#blender_missing[@]})); then
  echo "setup: installing ${blender_missing[*]} beside the build"
  blender_log=$(mktemp)
  ($SUDO apt-get update -qq && $SUDO apt-get install -y -qq --no-install-recommends "${blender_missing[@]}") \
    > "$blender_log" 2>&1 &
  blender_install=$!
fi

BUILD_DIR=${PATHFARM_BUILD_DIR:-build}
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build "$BUILD_DIR" --parallel "$(nproc)"

if [ -n "$blender_install" ]; then
  if ! wait "$blender_install"; then
    cat "$blender_log" >&2
    echo "setup: installing ${blender_missing[*]} failed (above)" >&2
    exit 1
  fi
  rm -f "$blender_log"
  # Configured again, so that CMake finds Blender and registers the add-on's test.
  cmake -S . -B "$BUILD_DIR" > /dev/null
fi

# The browser test's driver, playwright-core, as pinned in its package-lock.json; it runs
# the system's Chromium and downloads no browser.
(cd tests/browser && npm ci --no-audit --no-fund --loglevel=error)
