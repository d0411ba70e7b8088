#pragma once
// What the client does with a shot file after reading it and before submitting it, but
// for auto's choice of pipeline (pipeline_probe.h): the keyframe probe where the file
// leaves the interval to it, and a check that the farm can plan the result.
#include <filesystem>

#include "client/shot_file.h"

namespace pathfarm::farm {

// The spec of `file` as `pipeline`, ready to submit. A dui shot whose keyframe probe
// chooses k = 1 comes back as d. Throws SceneError naming the file for a shot the farm
// cannot plan (a shot too large for a scheduler's default limits is left to the
// scheduler, which refuses it before planning or plans it within its own limits).
ShotSpec preparedShot(const ShotFile& file, Pipeline pipeline);
// As the pipeline the file names.
ShotSpec preparedShot(const ShotFile& file);
// preparedShot(ShotFile::load(file)).
ShotSpec loadShotFile(const std::filesystem::path& file);

}  // namespace pathfarm::farm
