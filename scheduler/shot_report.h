#pragma once
// A shot's speed-against-error report (Zimmer et al. 2015, Table 1) from its tasks' figures:
// core-seconds per stage and per output frame, re-render rates, the cost of a plain pt
// render of the same spp (measured on the baseline frames or given), the resolution gain,
// relative cost = core-seconds per frame / the baseline's, overhead = relative cost x gain,
// and the evaluation task's errors. Tasks not yet done count nothing.
#include <filesystem>
#include <string>
#include <vector>

#include "pathfarm/report.pb.h"
#include "scheduler/farm_state.h"

namespace pathfarm::farm {

ShotReport buildReport(const ShotSummary& summary, const ShotSpec& spec, const std::vector<TaskRecord>& tasks);

// For a shot whose pipeline `auto` chose: the probe's predictions against what the shot
// measured, and the probe's cost against the shot's, in a sentence (empty otherwise).
std::string predictionSummary(const ShotReport& report);

std::string reportJson(const ShotReport& report);
std::string reportMarkdown(const ShotReport& report);
// report.json and report.md in `folder` (created), each written atomically.
void writeReportFiles(const ShotReport& report, const std::filesystem::path& folder);

}  // namespace pathfarm::farm
