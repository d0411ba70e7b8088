#pragma once
// Loads a scene file (docs/scene-format.md). Any problem throws SceneError with a
// message naming the file and the key path; nothing is half-loaded.
#include <filesystem>
#include <string_view>

#include "renderer/scene/scene.h"
#include "renderer/scene/scene_error.h"

namespace pathfarm {

Scene loadScene(const std::filesystem::path& file);
// Parses scene text as if it had been read from `file` (relative paths resolve against
// its folder, and messages name it).
Scene parseScene(std::string_view text, const std::filesystem::path& file);

}  // namespace pathfarm
