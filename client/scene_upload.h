#pragma once
// `pathfarm submit` without shared storage: the scene and every file loading it reads
// (meshes, glTF buffers and images, textures, environment maps) go into the scheduler's
// content-addressed store, and the spec names them relative to their common folder, so
// workers fetch them by digest. Files the store has already are not sent again. The
// scene's own references must be relative paths (an absolute one names a file on the
// worker's disk, which only works with shared storage).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "pathfarm/shot.pb.h"
#include "client/farm_client.h"

namespace pathfarm::farm {

struct UploadSummary {
  int64_t files = 0, filesSent = 0;
  uint64_t bytes = 0, bytesSent = 0;
};

// A file to upload, whole; throws SceneError when it cannot be read or is larger than a
// chunk may be.
std::string readUploadFile(const std::filesystem::path& file);

// Fills `spec.inputs` with the scene's files, named relative to their common folder, and
// rewrites `spec.scene` the same way; sends nothing. Returns each input's file on this
// machine, in the order of `spec.inputs`. Throws SceneError when the scene cannot be
// loaded or a file read.
std::vector<std::filesystem::path> describeSceneInputs(ShotSpec& spec);
// describeSceneInputs, then sends the files the scheduler lacks. Throws FarmError when
// the scheduler refuses a file.
UploadSummary uploadSceneInputs(FarmClient& client, ShotSpec& spec);

}  // namespace pathfarm::farm
