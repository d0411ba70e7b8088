#pragma once
// Running `pipeline: "auto"`'s probe on a farm (the arithmetic is in pipeline_choice.h).
// The shot file is read as each candidate pipeline, each candidate's probe is
// submitted as a small shot of its own, so the farm's workers render and filter it like
// any shot, and the frames come back to this machine to be measured against the plain pt
// probe. The choice is made here, once, and the spec submitted names the winner with its
// reason and predictions: every worker sees the same decision.
#include <filesystem>
#include <functional>

#include "pathfarm/shot.pb.h"
#include "client/farm_client.h"
#include "client/shot_file.h"

namespace pathfarm::farm {

// `autoSpec` is `file`'s spec for a shot whose pipeline is auto, with its scene inputs
// uploaded if they were (their digests carry over to every probe). The probes' frames go
// to probeFolder/<pipeline>/. `progress` sees each probe shot's summaries while it runs.
// With a `submitKey`, each probe is submitted under that key and its pipeline, so
// submitting the same shot again with the same key reuses the probes the farm has.
// Returns the spec to submit. Throws SceneError when the file does not read as a
// candidate, FarmError when the farm refuses a probe, std::runtime_error when plain pt's
// probe fails (a candidate whose probe fails is left out, and the reason says so).
ShotSpec choosePipeline(FarmClient& client, const ShotFile& file, const ShotSpec& autoSpec,
                        const std::filesystem::path& probeFolder,
                        const std::function<void(const ShotSummary&)>& progress, const std::string& submitKey = "");

}  // namespace pathfarm::farm
