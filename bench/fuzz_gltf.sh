#!/usr/bin/env bash
# Builds the glTF loader's libFuzzer target (fuzz/gltf_loader_fuzzer.cpp) with clang,
# AddressSanitizer and UndefinedBehaviorSanitizer, and runs it from the seed corpus
# (fuzz/corpus/gltf). CI runs it briefly (--runs 2000); a long run is e.g.
#   bench/fuzz_gltf.sh --seconds 3600
# Findings (crash-*, leak-*, timeout-*) are written to the work folder and fail the run.
#
# Usage: bench/fuzz_gltf.sh [--runs N] [--seconds S] [--work DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
runs=-1
seconds=0
work=build-fuzz
while (($#)); do
  case "$1" in
    --runs) runs=$2; shift 2 ;;
    --seconds) seconds=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    *) echo "usage: $0 [--runs N] [--seconds S] [--work DIR]" >&2; exit 2 ;;
  esac
done
if ((runs < 0 && seconds == 0)); then runs=20000; fi

mkdir -p "$work/objects" "$work/corpus"
sources=(
  fuzz/gltf_loader_fuzzer.cpp fuzz/tinygltf_implementation.cpp
  renderer/scene/gltf/gltf_document.cpp renderer/scene/gltf/gltf_animation.cpp
  renderer/scene/gltf/gltf_materials.cpp renderer/scene/gltf/gltf_mesh.cpp renderer/scene/gltf/gltf_scene.cpp
  renderer/scene/gltf/gltf_lights.cpp
  renderer/scene/animation.cpp renderer/scene/texture.cpp renderer/scene/json_node.cpp renderer/scene/alpha_coverage.cpp
  renderer/scene/scene_inputs.cpp
  renderer/math/quaternion.cpp renderer/math/transform.cpp
)
flags=(-std=c++20 -O1 -g -fno-omit-frame-pointer -fsanitize=fuzzer-no-link,address,undefined
       -fno-sanitize-recover=undefined -I. $(pkg-config --cflags stb))
# Any header change rebuilds every object: a stale object compiled against an older
# class layout would make the fuzzer report crashes that are not in the code.
newest_header=$(find renderer fuzz -name '*.h' -printf '%T@ %p\n' | sort -n | tail -1 | cut -d' ' -f2)
objects=()
for source in "${sources[@]}"; do
  object="$work/objects/$(echo "$source" | tr / _).o"
  if [[ ! -f "$object" || "$source" -nt "$object" || "$newest_header" -nt "$object" ]]; then
    echo "fuzz: compiling $source"
    clang++ "${flags[@]}" -c "$source" -o "$object"
  fi
  objects+=("$object")
done
clang++ -fsanitize=fuzzer,address,undefined "${objects[@]}" -o "$work/gltf_loader_fuzzer" \
  $(pkg-config --libs stb) -lspdlog -lfmt -lpthread

# New inputs the fuzzer finds go to the work folder's corpus; the committed seeds stay as they are.
options=(-max_len=65536 -rss_limit_mb=2048 -timeout=10 -artifact_prefix="$work/")
((runs >= 0)) && options+=(-runs="$runs")
((seconds > 0)) && options+=(-max_total_time="$seconds")
echo "fuzz: running ${options[*]}"
"$work/gltf_loader_fuzzer" "${options[@]}" "$work/corpus" fuzz/corpus/gltf
