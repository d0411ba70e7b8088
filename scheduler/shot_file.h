#pragma once
// Shot files (docs/shot-format.md): what to render and how, read into a ShotSpec with
// every default filled in from the scene and every path made absolute. The scene is
// loaded too, so a bad shot or scene is reported before anything is queued.
#include <filesystem>
#include <string_view>

#include "pathfarm/shot.pb.h"

namespace pathfarm::farm {

// Throws SceneError (renderer/scene/json_node.h) naming the file and key on bad input.
// A shot whose pipeline is "auto" (the default) comes back with only the keys every
// pipeline shares resolved; choosePipeline (scheduler/pipeline_probe.h) reads it again as
// each candidate.
ShotSpec loadShotFile(const std::filesystem::path& file);
// The same on the file's text already in memory: `file` names it in messages, and the
// scene and output paths resolve against its folder. A non-empty `pipeline` replaces the
// file's.
ShotSpec parseShotFile(std::string_view text, const std::filesystem::path& file, std::string_view pipeline = {});
// The file's text, or SceneError.
std::string readShotFileText(const std::filesystem::path& file);

}  // namespace pathfarm::farm
