#pragma once
// What `pathfarm local` and `pathfarm submit` are given: a shot file, or a scene file (a
// glTF file or a JSON scene) rendered as a shot of its own, named after the file, with
// the scene's frames and render settings. Shot keys given on the command line are set
// over the file's (or the scene's) before the shot is read, and checked as a file's are.
#include <filesystem>

#include <nlohmann/json.hpp>

#include "client/shot_file.h"

namespace pathfarm::farm {

// True for .gltf and .glb files, and for a JSON file that reads as a scene (it has a
// camera, shapes or an include, and no "scene" key) rather than as a shot.
bool isSceneFile(const std::filesystem::path& file);

// `keys` is a JSON object of shot keys. Throws SceneError naming the file on bad input.
ShotFile loadShotSource(const std::filesystem::path& file, const nlohmann::json& keys);

}  // namespace pathfarm::farm
