#!/usr/bin/env bash
# Builds pathfarm's libFuzzer targets (fuzz/*_fuzzer.cpp) with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer, and runs each from its committed seed corpus (fuzz/corpus/NAME):
#   gltf_loader  .gltf/.glb files                      renderer/scene/gltf
#   scene_json   scene JSON files                      renderer/scene/scene_loader.h parseScene
#   shot_json    shot files                            client/shot_preparation.h preparedShot
#   mesh_readers OBJ and PLY files ("ply" magic: PLY)  renderer/scene/mesh_io.h parseObj, parsePly
#   exr_chunk    EXR chunks as workers fetch them      image/exr_io.h decodeExr, scanExrFile, readExrRows
#   rpc_handlers sequences of RPC calls and requests   scheduler/*_service.cpp over gRPC in-process
# CI (tests/CMakeLists.txt, label fuzz) runs each briefly with --quick; a long run is e.g.
#   bench/fuzz.sh --target all --runs 1000000
# A finding (crash-*, leak-*, timeout-*, oom-*) fails the run, naming the target; it is
# kept in WORK/findings/NAME/, and `WORK/MODE/NAME_fuzzer FILE` runs it again.
#
# Usage: bench/fuzz.sh [--target NAME|all] [--runs N] [--seconds S] [--fork N] [--seed N] [--work DIR]
#                      [--quick] [--build DIR] [--build-only]
#   --fork N      N fuzzing processes at once (libFuzzer -fork=N), e.g. one per core
#   --seed N      libFuzzer's random seed (default: a new one each run). CI passes one, so
#                 that its brief runs try the same inputs every time and a finding there
#                 comes from the change under test; long runs explore with new seeds
#   --quick       -O0 -g1 instead of -O1 -g (half the compile time), objects in WORK/quick
#                 (never mixed with WORK/full's), and new inputs are not kept between runs
#   --build DIR   the CMake build whose generated protobuf code shot_json uses (build)
#   --build-only  compile and link, run nothing
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
all_targets=(gltf_loader scene_json shot_json mesh_readers exr_chunk rpc_handlers)
target=all
runs=-1
seconds=0
fork=1
seed=0
work=build-fuzz
build=build
quick=0
build_only=0
usage="usage: $0 [--target NAME|all] [--runs N] [--seconds S] [--fork N] [--seed N] [--work DIR] [--quick] [--build DIR] [--build-only]"
while (($#)); do
  case "$1" in
    --target) target=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --fork) fork=$2; shift 2 ;;
    --seed) seed=$2; shift 2 ;;
    --seconds) seconds=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    --quick) quick=1; shift ;;
    --build-only) build_only=1; shift ;;
    *) echo "$usage" >&2; exit 2 ;;
  esac
done
if ((runs < 0 && seconds == 0)); then runs=20000; fi
if [[ $target == all ]]; then
  targets=("${all_targets[@]}")
elif [[ " ${all_targets[*]} " == *" $target "* ]]; then
  targets=("$target")
else
  echo "fuzz: unknown target '$target' (${all_targets[*]} or all)" >&2; exit 2
fi
mkdir -p "$work"
work=$(cd "$work" && pwd)
build=$(cd "$build" && pwd)
generated=$build/proto/generated

# Sources shared by several targets are compiled once and linked into each.
tinygltf=(fuzz/tinygltf_implementation.cpp)
math=(renderer/math/quaternion.cpp renderer/math/transform.cpp)
gltf=(renderer/scene/gltf/gltf_document.cpp renderer/scene/gltf/gltf_animation.cpp
      renderer/scene/gltf/gltf_materials.cpp renderer/scene/gltf/gltf_mesh.cpp renderer/scene/gltf/gltf_scene.cpp
      renderer/scene/gltf/gltf_lights.cpp renderer/scene/gltf/gltf_deformation.cpp renderer/scene/mesh_deformation.cpp
      renderer/math/key_track.cpp renderer/math/animation.cpp renderer/scene/texture.cpp renderer/scene/json_node.cpp
      renderer/scene/alpha_coverage.cpp renderer/scene/scene_inputs.cpp "${math[@]}" "${tinygltf[@]}")
meshes=(renderer/scene/mesh_io.cpp renderer/scene/obj_reader.cpp renderer/scene/ply_reader.cpp
        renderer/scene/scene_inputs.cpp fuzz/tinyobj_implementation.cpp)
exr=(image/exr_io.cpp image/exr_core_rows.cpp image/frame_image.cpp image/atomic_file.cpp)
scene=("${gltf[@]}" "${meshes[@]}" "${exr[@]}"
       renderer/scene/scene_loader.cpp renderer/scene/environment_parser.cpp renderer/scene/light_parser.cpp
       renderer/scene/material_parser.cpp renderer/scene/transform_parser.cpp renderer/scene/mesh.cpp
       renderer/lights/environment_light.cpp renderer/sampling/piecewise_constant.cpp)
shot=("${scene[@]}" client/shot_file.cpp client/shot_preparation.cpp client/reference_choice.cpp contract/pipeline.cpp
      scheduler/planner.cpp scheduler/quoted_text.cpp
      postproc/poisson/window_blend.cpp
      renderer/decomposition/decomposition.cpp renderer/decomposition/lpe_automaton.cpp
      "$generated/pathfarm/shot.pb.cc" "$generated/pathfarm/chunk.pb.cc")
# The RPC handlers and what they call into are instrumented; the renderer, the filters and
# the generated protocol code they reach are linked from the CMake build's libraries (and
# the glTF and OBJ readers with the renderer: its files are compiled in groups, so the
# loaders come along with the scene code the handlers reach).
rpc=(fuzz/rpc_handlers_fuzzer.cpp fuzz/rpc_fuzz_calls.cpp
     scheduler/worker_service.cpp scheduler/client_service.cpp scheduler/client_service_inputs.cpp
     scheduler/service_chunks.cpp scheduler/worker_sessions.cpp scheduler/farm_state.cpp
     scheduler/farm_state_follow_ups.cpp scheduler/farm_state_queries.cpp scheduler/farm_state_requeue.cpp
     scheduler/farm_state_retention.cpp scheduler/farm_state_sessions.cpp scheduler/farm_state_submit.cpp scheduler/schema.cpp scheduler/sqlite_db.cpp
     contract/pipeline.cpp scheduler/planner.cpp scheduler/quoted_text.cpp scheduler/farm_names.cpp scheduler/output_check.cpp
     scheduler/shot_report.cpp scheduler/shot_verdict.cpp proto/wire/chunk_store.cpp proto/wire/chunk_transfer.cpp proto/wire/connection.cpp proto/wire/input_files.cpp
     proto/wire/sha256.cpp proto/wire/tls.cpp)
sources_of() {
  case "$1" in
    gltf_loader) echo fuzz/gltf_loader_fuzzer.cpp "${gltf[@]}" ;;
    scene_json) echo fuzz/scene_json_fuzzer.cpp "${scene[@]}" ;;
    shot_json) echo fuzz/shot_json_fuzzer.cpp "${shot[@]}" ;;
    mesh_readers) echo fuzz/mesh_readers_fuzzer.cpp "${meshes[@]}" ;;
    exr_chunk) echo fuzz/exr_chunk_fuzzer.cpp "${exr[@]}" ;;
    rpc_handlers) echo "${rpc[@]}" ;;
  esac
}
exr_libs="$(pkg-config --libs OpenEXR)"
stb_libs="$(pkg-config --libs stb)"
libs_of() {
  case "$1" in
    gltf_loader) echo "$stb_libs -lspdlog -lfmt -lpthread" ;;
    scene_json) echo "$stb_libs $exr_libs -lspdlog -lfmt -lpthread" ;;
    shot_json) echo "$stb_libs $exr_libs -lprotobuf -lspdlog -lfmt -lpthread" ;;
    mesh_readers) echo "-lspdlog -lfmt -lpthread" ;;
    exr_chunk) echo "$exr_libs -lspdlog -lfmt -lpthread" ;;
    rpc_handlers) echo "$build/postproc/libpathfarm_postproc.a $build/renderer/libpathfarm_renderer.a" \
                       "$build/image/libpathfarm_image.a $build/proto/libpathfarm_proto.a" \
                       "$(pkg-config --libs grpc++ protobuf sqlite3 openssl) $exr_libs $stb_libs" \
                       "-lembree3 -ltbb -ltinygltf -ltinyobjloader -lspdlog -lfmt -lpthread" ;;
  esac
}
max_len_of() {
  case "$1" in
    gltf_loader|exr_chunk) echo 65536 ;;
    *) echo 16384 ;;
  esac
}

if ((quick)); then mode=quick; optimize="-O0 -g1"; else mode=full; optimize="-O1 -g"; fi
out=$work/$mode
mkdir -p "$out"
# What shot_json and rpc_handlers take from the CMake build.
needs_build() { [[ $1 == shot_json && ! -f $generated/pathfarm/shot.pb.cc ]] ||
                [[ $1 == rpc_handlers && ! -f $build/renderer/libpathfarm_renderer.a ]]; }
for name in "${targets[@]}"; do
  if needs_build "$name"; then
    echo "fuzz: $name needs the libraries and generated code of $build: build pathfarm first (cmake --build $build)" >&2
    exit 2
  fi
done

# Concurrent runs (ctest -j) take turns to build: one compiles, the others then find
# nothing to do.
exec 9>"$out/build.lock"
flock 9
# The objects and links, as a ninja file: both cores compile, and an object is compiled
# again when its source or any header it includes is newer (a stale object compiled
# against an older class layout would make the fuzzer report crashes that are not in the
# code) or when its flags change.
{
  echo "cxxflags = -std=c++20 $optimize -fno-omit-frame-pointer -fsanitize=fuzzer-no-link,address,undefined" \
       "-fno-sanitize-recover=undefined -I$root -I$generated $(pkg-config --cflags stb OpenEXR spdlog fmt)" \
       "-DPATHFARM_FUZZ_ASSETS='\"$root/fuzz/assets\"'"
  echo "rule pch"
  echo "  command = clang++ \$cxxflags -fpch-instantiate-templates -x c++-header -MD -MF \$out.d \$in -o \$out"
  echo "  depfile = \$out.d"
  echo "  deps = gcc"
  echo "  description = fuzz: precompiling \$in"
  echo "rule cxx"
  echo "  command = clang++ \$cxxflags -include-pch objects/fuzz_pch.h.pch -MD -MF \$out.d -c \$in -o \$out"
  echo "  depfile = \$out.d"
  echo "  deps = gcc"
  echo "  description = fuzz: compiling \$in"
  echo "build objects/fuzz_pch.h.pch: pch $root/fuzz/fuzz_pch.h"
  echo "rule link"
  echo "  command = clang++ -fsanitize=fuzzer,address,undefined \$in -o \$out \$libs"
  echo "  description = fuzz: linking \$out"
  declare -A seen=()
  for name in "${all_targets[@]}"; do
    needs_build "$name" && continue
    objects=()
    declare -A linked=()
    for source in $(sources_of "$name"); do
      [[ $source == /* ]] || source=$root/$source
      relative=${source#"$root"/}
      relative=${relative#/}
      object=objects/${relative//\//_}.o
      [[ -n ${linked[$object]:-} ]] && continue
      linked[$object]=1
      if [[ -z ${seen[$object]:-} ]]; then
        echo "build $object: cxx $source | objects/fuzz_pch.h.pch"
        seen[$object]=1
      fi
      objects+=("$object")
    done
    unset linked
    echo "build ${name}_fuzzer: link ${objects[*]}"
    echo "  libs = $(libs_of "$name")"
  done
} >"$out/build.ninja"
binaries=()
for name in "${targets[@]}"; do binaries+=("${name}_fuzzer"); done
ninja -C "$out" -j "$(nproc)" "${binaries[@]}"
exec 9>&-
((build_only)) && exit 0

options=(-rss_limit_mb=2048 -timeout=10 -print_final_stats=1)
((runs >= 0)) && options+=(-runs="$runs")
((seconds > 0)) && options+=(-max_total_time="$seconds")
((fork > 1)) && options+=(-fork="$fork")
((seed > 0)) && options+=(-seed="$seed")
failed=()
for name in "${targets[@]}"; do
  # New inputs the fuzzer finds go to the work folder's corpus; the committed seeds stay as they are.
  corpus=$out/corpus/$name
  ((quick)) && rm -rf "$corpus"
  findings=$work/findings/$name
  mkdir -p "$corpus" "$findings"
  before=$(ls -A "$findings")
  echo "fuzz: $name: running ${options[*]} -max_len=$(max_len_of "$name")"
  status=0
  "$out/${name}_fuzzer" "${options[@]}" -max_len="$(max_len_of "$name")" -artifact_prefix="$findings/" \
    "$corpus" "fuzz/corpus/$name" || status=$?
  new=$(comm -13 <(echo "$before") <(ls -A "$findings") | sed "s|^|$findings/|")
  slow=$(echo "$new" | grep '/slow-unit-' || true)
  new=$(echo "$new" | grep -E '/(crash|leak|timeout|oom)-' || true)
  [[ -n $slow ]] && echo "fuzz: $name: inputs slower than 10 s (not failing the run): $slow" >&2
  if ((status != 0)) || [[ -n $new ]]; then
    echo "fuzz: FINDING in $name (exit status $status): ${new:-no artifact written}" >&2
    failed+=("$name")
  fi
done
if ((${#failed[@]})); then
  echo "fuzz: findings in ${failed[*]}; run one again with $out/NAME_fuzzer FILE" >&2
  exit 1
fi
echo "fuzz: no findings in ${targets[*]}"
