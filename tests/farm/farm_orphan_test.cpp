// A worker started with --parent ends when that process ends, even by SIGKILL: the
// workers of a killed `pathfarm local` do not outlive it (they used to poll a dead
// scheduler for hours, then to wait a minute to deliver their tasks to it).
#include "farm/farm_fixture.h"

namespace pathfarm::farmtest {
namespace {

// Whether `pid` still runs: its /proc entry is there and it is no zombie waiting for a
// parent to reap it.
bool running(pid_t pid) {
  const std::string stat = readFile("/proc/" + std::to_string(pid) + "/stat");
  const size_t end = stat.rfind(')');
  return end != std::string::npos && end + 2 < stat.size() && stat[end + 2] != 'Z';
}

TEST_F(FarmTest, AWorkerStopsWhenTheProcessThatStartedItIsKilled) {
  // A shell starts a worker (its scheduler never answers), names itself as the worker's
  // parent, writes the worker's pid and waits.
  const fs::path pidFile = dir() / "worker.pid";
  farm::ChildProcess shell({"/bin/sh", "-c",
                            "\"$0\" worker --scheduler 127.0.0.1:1 --cache \"$1\" --parent $$ >\"$2\" 2>&1 & "
                            "echo $! >\"$3\"; wait",
                            pathfarmBinary().string(), (dir() / "cache").string(), (dir() / "worker.log").string(),
                            pidFile.string()});
  pid_t worker = 0;
  ASSERT_TRUE(waitUntil([&] { return (worker = std::atoi(readFile(pidFile).c_str())) > 0; }, 10s));
  ASSERT_TRUE(waitUntil([&] { return contains(readFile(dir() / "worker.log"), "cannot reach the scheduler"); }, 10s))
      << readFile(dir() / "worker.log");
  ASSERT_TRUE(running(worker));
  shell.signal(SIGKILL);
  EXPECT_TRUE(waitUntil([&] { return !running(worker); }, 15s)) << readFile(dir() / "worker.log");
  if (running(worker)) kill(worker, SIGKILL);

  // A worker whose named parent is not its parent (that process ended before the worker
  // could follow it) stops at once.
  farm::ChildProcess stray({pathfarmBinary().string(), "worker", "--scheduler", "127.0.0.1:1", "--cache",
                            (dir() / "cache").string(), "--parent", "999999"},
                           (dir() / "stray.log").string());
  EXPECT_EQ(stray.wait(10s), 1);
  EXPECT_TRUE(contains(readFile(dir() / "stray.log"), "the process that started this worker (999999) has ended"));
}

TEST_F(FarmTest, TheWorkersOfAKilledLocalFarmEndAtOnceMidTask) {
  RenderSpec spec;
  spec.name = "long";
  spec.width = 256;
  spec.height = 256;
  spec.spp = 4096;  // minutes of tiles: the workers are rendering when the farm is killed
  spec.tile = 128;
  farm::ChildProcess local({pathfarmBinary().string(), "local", writeShotFile(spec).string(), "--workers", "2",
                            "--threads", "1", "--out", (dir() / "out").string()},
                           (dir() / "local.log").string());
  const fs::path logs = dir() / "out" / "farm" / "logs";
  const auto rendering = [&](int i) {
    return contains(readFile(logs / ("local-" + std::to_string(i) + ".log")), "TASK_RENDER_TILE");
  };
  ASSERT_TRUE(waitUntil([&] { return rendering(0) && rendering(1); }, 30s)) << readFile(dir() / "local.log");
  std::vector<pid_t> workers;  // the farm's children: its two workers
  std::istringstream children(
      readFile("/proc/" + std::to_string(local.pid()) + "/task/" + std::to_string(local.pid()) + "/children"));
  for (pid_t child = 0; children >> child;) workers.push_back(child);
  ASSERT_EQ(workers.size(), 2u);
  local.signal(SIGKILL);
  const auto start = Clock::now();
  EXPECT_TRUE(waitUntil([&] { return std::none_of(workers.begin(), workers.end(), running); }, 10s));
  EXPECT_LT(Clock::now() - start, 5s) << "the workers finished their tiles first";
  for (const pid_t worker : workers)
    if (running(worker)) kill(worker, SIGKILL);
}

}  // namespace
}  // namespace pathfarm::farmtest
