#pragma once
// Shows a watched shot's progress: a bar with tasks done/total, workers busy, elapsed
// and remaining time on a terminal; a log line now and then otherwise.
#include <filesystem>

#include "pathfarm/shot.pb.h"
#include "client/farm_client.h"
#include "client/shot_file.h"

namespace pathfarm {

class ShotProgress {
 public:
  ~ShotProgress();
  void update(const farm::ShotSummary& summary);

 private:
  bool terminal_ = false, drawn_ = false, checked_ = false;
  double lastLogged_ = -1e9;
};

// One line for listings: "12 cornell RUNNING 40/96 tasks ...".
std::string describeShot(const farm::ShotSummary& summary);

// `spec` (of `file`) with the pipeline its probe chose when it is auto (each probe shot's
// progress shown, its frames written under probeFolder), else `spec` itself.
farm::ShotSpec withChosenPipeline(farm::FarmClient& client, const farm::ShotFile& file, farm::ShotSpec spec,
                                  const std::filesystem::path& probeFolder, const std::string& submitKey = "");

}  // namespace pathfarm
