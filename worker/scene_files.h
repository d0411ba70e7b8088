#pragma once
// A shot's scene on this worker's disk. With shared storage it is the path the shot
// names; with uploaded files (ShotSpec.inputs) they are fetched by digest and rebuilt in
// a folder of their own under `scenesRoot`, named by the digest of the whole file list, so
// shots with the same files share it and a half-written folder is never used.
#include <filesystem>

#include "worker/task_runner.h"

namespace pathfarm::farm {

// Throws std::invalid_argument for an unsafe file list, whatever `fetch` throws for a
// file it cannot get, and std::runtime_error when the folder cannot be written.
std::filesystem::path localSceneFile(const ShotSpec& spec, const std::filesystem::path& scenesRoot,
                                     const TaskRunner::ChunkFetcher& fetch);

}  // namespace pathfarm::farm
