#!/usr/bin/env bash
# Renders the references the demo's shots measure against (16384 spp of their evaluation
# frames) into scenes/<shot>/references/, each named by the digest of everything its
# pixels depend on (client/reference_cache.h), for committing: a fresh clone's demo then
# renders no reference. Run it after changing a demo scene or shot, or kRendererVersion;
# the unit test ReferenceCache.TheDemosShippedReferencesAreTheOnesItsShotsAskFor fails
# until then. Takes about 50 minutes on 2 cores (Cornell 26, showroom 24).
#
#   bench/demo_references.sh [--build DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build=build
[ "${1:-}" = --build ] && build=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for shot in cornell showroom; do
  rm -rf "scenes/$shot/references"  # keys no shot asks for any more
  "$build/bin/pathfarm" local "scenes/$shot/shot.json" --workers 2 --out "$work/$shot"
  ls -l "scenes/$shot/references"
done
