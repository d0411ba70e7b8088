// The DUI pipeline on a multi-process farm (issue: the shot planner and the DUI pipeline):
// a small Cornell animation filtered end to end (its frames composited in windows of 16
// rows), judged against renders made apart from the farm, and the same shot with a worker
// killed midway and its inputs streamed, which must not change a byte.
#include <map>

#include "farm/farm_fixture.h"
#include "image/exr_io.h"
#include "postproc/metrics/image_metrics.h"

namespace pathfarm::farmtest {
namespace {

constexpr int kSpp = 32;  // keyframes get a quarter: 8 spp at full resolution

fs::path writeDuiShot(const fs::path& folder) {
  const fs::path file = folder / "dui.shot.json";
  writeFile(file, "{\"name\": \"dui\", \"scene\": \"" + cornellScene().string() +
                      "\", \"frames\": {\"start\": 0, \"end\": 4}, \"resolution\": [64, 64], \"spp\": " +
                      std::to_string(kSpp) +
                      ", \"max_depth\": 6, \"pipeline\": \"dui\", \"keyframe_interval\": 4, \"tile\": 32,"
                      " \"evaluation_frames\": [2], \"baseline_core_seconds\": 1, \"filter_window_rows\": 16}\n");
  return file;
}

// Mean relMSE of the beauty of frames 0..4 in `folder` against those in `reference`.
double meanRelMse(const fs::path& folder, const fs::path& reference) {
  double sum = 0;
  for (int64_t frame = 0; frame <= 4; ++frame) {
    const std::string name = farm::frameFileName(frame);
    sum += compareImages(readExr(folder / name), readExr(reference / name), {"R", "G", "B"}).relMse;
  }
  return sum / 5;
}

TEST_F(FarmTest, DuiShotIsFilteredEndToEndAndAKilledWorkerChangesNoByte) {
  const auto renderPt = [&](int spp, const std::string& folder) {
    const fs::path out = dir() / folder;
    const CommandResult rendered = runPathfarm({"render", cornellScene().string(), "--frames", "0:4", "--res", "64x64",
                                                "--spp", std::to_string(spp), "--max-depth", "6", "--out", out.string()},
                                               {}, 120s);
    if (rendered.status != 0) throw std::runtime_error("`pathfarm render` failed:\n" + rendered.output);
    return out;
  };
  const fs::path shot = writeDuiShot(dir());
  const fs::path undisturbed = dir() / "undisturbed";
  const CommandResult local =
      runPathfarm({"local", shot.string(), "--workers", "2", "--threads", "1", "--out", undisturbed.string()}, {}, 300s);
  ASSERT_EQ(local.status, 0) << local.output;
  for (int64_t frame = 0; frame <= 4; ++frame)
    ASSERT_TRUE(fs::exists(undisturbed / farm::frameFileName(frame))) << "frame " << frame << " is missing";
  EXPECT_TRUE(fs::exists(undisturbed / "report.md"));
  EXPECT_TRUE(contains(readFile(undisturbed / "report.json"), "\"pipeline\": \"dui\""));

  // Better than plain path tracing at the keyframes' budget, against a 512-spp reference.
  const fs::path reference = renderPt(512, "reference");
  const double dui = meanRelMse(undisturbed, reference);
  const double keyframeBudget = meanRelMse(renderPt(kSpp / 4, "pt-keyframe-budget"), reference);
  EXPECT_LT(dui, keyframeBudget) << "dui relMSE " << dui << ", pt at " << kSpp / 4 << " spp " << keyframeBudget;

  // The same shot on a farm whose first worker is killed while it holds a task, and whose
  // leases name at most two inputs: a task with more reads them in parts (LeaseInputs).
  SchedulerConfig config;
  config.leaseSeconds = 1.5;
  config.extraArguments = {"--lease-inputs", "2"};
  startScheduler(config);
  const CommandResult submitted = runPathfarm({"submit", shot.string(), "--scheduler", address()});
  ASSERT_EQ(submitted.status, 0) << submitted.output;
  const int64_t id = shotIdFrom(submitted);
  const FarmDatabase db = database();
  // A worker killed just after completing a task, before its next lease, holds nothing:
  // then another is started and killed, until one dies holding a lease.
  bool diedHoldingALease = false;
  for (int tries = 0; tries < 3 && !diedHoldingALease; ++tries) {
    const std::string name = "victim" + std::to_string(tries);
    const std::string running = "SELECT COUNT(*) FROM attempts a JOIN workers w ON w.id = a.worker_id "
                                "WHERE w.name = '" + name + "' AND a.state = 0";
    farm::ChildProcess& victim = startWorker(name);
    ASSERT_TRUE(waitUntil(
        [&] { return db.integer(running) > 0 && db.integer("SELECT COUNT(*) FROM tasks WHERE state = 3") > 3; },
        30s))
        << name << " never held a task midway through the shot";
    victim.signal(SIGKILL);
    ASSERT_EQ(victim.wait(5s), 128 + SIGKILL);
    diedHoldingALease = db.integer(running) > 0;  // its lease outlives it by 1.5 s
  }
  ASSERT_TRUE(diedHoldingALease) << "no victim died holding a lease";
  ASSERT_LT(db.integer("SELECT COUNT(*) FROM tasks WHERE state = 3"), db.integer("SELECT COUNT(*) FROM tasks"))
      << "the shot ended before the worker was killed";
  startWorker("survivor");
  const farm::ShotSummary summary = waitForShot(id, 120s);
  ASSERT_EQ(summary.state(), farm::SHOT_DONE) << describe(summary);
  EXPECT_GT(db.integer("SELECT COUNT(*) FROM attempts WHERE state = 3"), 0) << "no lease expired: nothing was lost";
  EXPECT_GT(db.integer("SELECT COUNT(*) FROM (SELECT task_id FROM task_deps GROUP BY task_id HAVING COUNT(*) > 2)"), 0)
      << "no task had more inputs than a lease names";
  EXPECT_GT(db.integer("SELECT COUNT(*) FROM tasks WHERE created_by IS NOT NULL"), 0) << "no follow-up tile was asked for";
  EXPECT_EQ(db.integer("SELECT COUNT(*) FROM tasks WHERE kind = " + std::to_string(farm::TASK_COMPOSITE)), 5 * (4 + 1))
      << "each frame's four windows and their join";
  const fs::path disturbed = fetchFrames(id, "disturbed");
  for (int64_t frame = 0; frame <= 4; ++frame) {
    const std::string name = farm::frameFileName(frame);
    EXPECT_EQ(readFile(disturbed / name), readFile(undisturbed / name)) << name << " differs after the kill";
  }
}

// The tgpt pipeline on the farm (gradient renders of 16-pixel tiles joined per frame,
// Poisson windows, blends) gives the frames that `pathfarm render --integrator tgpt` (whole
// frames) and `pathfarm poisson` give on one machine.
TEST_F(FarmTest, TgptShotOnTheFarmEqualsRenderThenPoisson) {
  const fs::path shot = dir() / "tgpt.shot.json";
  writeFile(shot, "{\"name\": \"tgpt\", \"scene\": \"" + cornellScene().string() +
                      "\", \"frames\": {\"start\": 0, \"end\": 6}, \"resolution\": [48, 32], \"spp\": 4,"
                      " \"max_depth\": 5, \"pipeline\": \"tgpt\", \"poisson_window\": 4, \"poisson_overlap\": 2,"
                      " \"poisson_norm\": \"l1\", \"tile\": 16, \"baseline_core_seconds\": 1}\n");
  const fs::path farmFrames = dir() / "farm-frames";
  const CommandResult local =
      runPathfarm({"local", shot.string(), "--workers", "2", "--threads", "1", "--out", farmFrames.string()}, {}, 300s);
  ASSERT_EQ(local.status, 0) << local.output;

  const fs::path gradients = dir() / "gradients", reconstructed = dir() / "reconstructed";
  const CommandResult rendered =
      runPathfarm({"render", cornellScene().string(), "--integrator", "tgpt", "--frames", "0:6", "--res", "48x32",
                   "--spp", "4", "--max-depth", "5", "--out", gradients.string()},
                  {}, 120s);
  ASSERT_EQ(rendered.status, 0) << rendered.output;
  const CommandResult solved = runPathfarm({"poisson", gradients.string(), "--window", "4", "--overlap", "2", "--norm",
                                            "l1", "--out", reconstructed.string()},
                                           {}, 120s);
  ASSERT_EQ(solved.status, 0) << solved.output;
  for (int64_t frame = 0; frame <= 6; ++frame) {
    const std::string name = farm::frameFileName(frame);
    const FrameImage fromFarm = readExr(farmFrames / name), fromCli = readExr(reconstructed / name);
    for (const char* channel : {"R", "G", "B"})
      EXPECT_EQ(fromFarm.channel(channel), fromCli.channel(channel)) << name << " channel " << channel;
  }
}

// A Metropolis shot on the farm (a seed pool, chain blocks spread over three tasks on two
// workers, a merge per frame) gives the frames `pathfarm render` gives with every block in
// one process: the split does not change a bit.
class MetropolisFarmTest : public FarmTest {
 protected:
  void expectFarmEqualsOneProcess(const std::string& pipeline);
};

void MetropolisFarmTest::expectFarmEqualsOneProcess(const std::string& pipeline) {
  const fs::path shot = dir() / (pipeline + ".shot.json");
  writeFile(shot, "{\"name\": \"" + pipeline + "\", \"scene\": \"" + cornellScene().string() +
                      "\", \"frames\": {\"start\": 2, \"end\": 5}, \"resolution\": [40, 32], \"spp\": 4,"
                      " \"max_depth\": 4, \"pipeline\": \"" + pipeline + "\", \"mlt_window\": 3,"
                      " \"mutations_per_pixel\": 8, \"mlt_chains\": 10, \"chains_per_block\": 2, \"chain_tasks\": 3,"
                      " \"bootstrap_samples\": 2000, \"temporal_delta\": 0.75, \"baseline_core_seconds\": 1}\n");
  const fs::path farmFrames = dir() / (pipeline + "-farm");
  const CommandResult local =
      runPathfarm({"local", shot.string(), "--workers", "2", "--threads", "1", "--out", farmFrames.string()}, {}, 300s);
  ASSERT_EQ(local.status, 0) << local.output;
  const fs::path oneProcess = dir() / (pipeline + "-render");
  const CommandResult rendered = runPathfarm(
      {"render", cornellScene().string(), "--integrator", pipeline, "--frames", "2:5", "--window", "3", "--res", "40x32",
       "--max-depth", "4", "--mutations-per-pixel", "8", "--chains", "10", "--chains-per-block", "2", "--bootstrap",
       "2000", "--delta", "0.75", "--out", oneProcess.string()},
      {}, 120s);
  ASSERT_EQ(rendered.status, 0) << rendered.output;
  for (int64_t frame = 2; frame <= 5; ++frame) {
    const std::string name = farm::frameFileName(frame);
    const FrameImage fromFarm = readExr(farmFrames / name), fromCli = readExr(oneProcess / name);
    double sum = 0;
    for (const char* channel : {"R", "G", "B"}) {
      EXPECT_EQ(fromFarm.channel(channel), fromCli.channel(channel)) << name << " channel " << channel;
      for (const float v : fromFarm.channel(channel)) sum += v;
    }
    EXPECT_GT(sum, 0) << name << " is black";
  }
}

TEST_F(MetropolisFarmTest, PssmltShotEqualsOneProcessWhateverTheSplit) { expectFarmEqualsOneProcess("pssmlt"); }
TEST_F(MetropolisFarmTest, TmltShotEqualsOneProcessWhateverTheSplit) { expectFarmEqualsOneProcess("tmlt"); }

}  // namespace
}  // namespace pathfarm::farmtest
