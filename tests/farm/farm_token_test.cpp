// A scheduler started with --token-file serves only callers carrying that token: the
// CLI and workers without it (or with another) are refused; with it, everything works.
#include "farm/farm_fixture.h"

namespace pathfarm::farmtest {
namespace {

TEST_F(FarmTest, TokenIsRequiredOfEveryClientAndWorker) {
  const std::string token = "farm-test-token-5f1c9e";
  const fs::path tokenFile = dir() / "token";
  writeFile(tokenFile, token + "\n");  // the trailing newline is not part of the token
  const fs::path wrongTokenFile = dir() / "wrong-token";
  writeFile(wrongTokenFile, "not-the-token\n");

  SchedulerConfig config;
  config.tokenFile = tokenFile;
  const std::string scheduler = startScheduler(config);

  RenderSpec spec;
  spec.name = "guarded";
  spec.frameStart = spec.frameEnd = 1;
  spec.width = 32;
  spec.height = 32;
  spec.tile = 16;
  spec.spp = 2;
  const std::string shotFile = writeShotFile(spec).string();

  // Without the token, or with another one: refused, exit status 1, and said why.
  const auto expectRefused = [](const CommandResult& result, const std::string& what) {
    EXPECT_EQ(result.status, 1) << what << ":\n" << result.output;
    EXPECT_TRUE(contains(result.output, "refused") && contains(result.output, "token")) << what << ":\n"
                                                                                         << result.output;
  };
  expectRefused(runPathfarm({"status", "--scheduler", scheduler}), "status without a token");
  expectRefused(runPathfarm({"submit", shotFile, "--scheduler", scheduler}), "submit without a token");
  expectRefused(runPathfarm({"workers", "--scheduler", scheduler}), "workers without a token");
  expectRefused(runPathfarm({"status", "--scheduler", scheduler}, {"PATHFARM_TOKEN=not-the-token"}),
                "status with a wrong PATHFARM_TOKEN");
  expectRefused(runPathfarm({"submit", shotFile, "--scheduler", scheduler, "--token-file", wrongTokenFile.string()}),
                "submit with a wrong --token-file");
  try {
    client().shots();
    ADD_FAILURE() << "FarmClient without the token was served";
  } catch (const farm::FarmError& e) {
    EXPECT_EQ(e.code(), grpc::StatusCode::UNAUTHENTICATED) << e.what();
  }

  // A worker without the token is refused at registration and exits with failure.
  farm::ChildProcess& rogue = startWorker("rogue");
  const auto rogueStatus = rogue.wait(15s);
  ASSERT_TRUE(rogueStatus.has_value()) << "a worker without the token kept running:\n" << workerLog("rogue");
  EXPECT_EQ(*rogueStatus, 1) << workerLog("rogue");
  EXPECT_TRUE(contains(workerLog("rogue"), "refused")) << workerLog("rogue");
  farm::ChildProcess& impostor = startWorker("impostor", {"--token-file", wrongTokenFile.string()});
  const auto impostorStatus = impostor.wait(15s);
  ASSERT_TRUE(impostorStatus.has_value()) << "a worker with a wrong token kept running:\n" << workerLog("impostor");
  EXPECT_EQ(*impostorStatus, 1) << workerLog("impostor");

  // With the token (from the environment or a file) the same calls work.
  const std::vector<std::string> tokenEnvironment = {"PATHFARM_TOKEN=" + token};
  const CommandResult emptyStatus = runPathfarm({"status", "--scheduler", scheduler}, tokenEnvironment);
  EXPECT_EQ(emptyStatus.status, 0) << emptyStatus.output;
  const CommandResult submitted =
      runPathfarm({"submit", shotFile, "--scheduler", scheduler, "--token-file", tokenFile.string()});
  ASSERT_EQ(submitted.status, 0) << submitted.output;
  const int64_t id = shotIdFrom(submitted);
  startWorker("trusted", {}, tokenEnvironment);
  startWorker("trusted-by-file", {"--token-file", tokenFile.string()});

  const farm::ShotSummary summary = waitForShot(id, 30s, token);
  ASSERT_EQ(summary.state(), farm::SHOT_DONE) << describe(summary);

  // The refused submissions queued nothing; the refused workers never registered.
  const auto shots = client(token).shots();
  ASSERT_EQ(shots.size(), 1u);
  EXPECT_EQ(shots[0].id(), id);
  const CommandResult status = runPathfarm({"status", std::to_string(id), "--scheduler", scheduler}, tokenEnvironment);
  EXPECT_EQ(status.status, 0) << status.output;
  EXPECT_TRUE(contains(status.output, "SHOT_DONE")) << status.output;
  const CommandResult workers =
      runPathfarm({"workers", "--scheduler", scheduler, "--token-file", tokenFile.string()});
  EXPECT_EQ(workers.status, 0) << workers.output;
  EXPECT_TRUE(contains(workers.output, " trusted: ")) << workers.output;
  EXPECT_TRUE(contains(workers.output, " trusted-by-file: ")) << workers.output;
  EXPECT_FALSE(contains(workers.output, "rogue")) << workers.output;
  EXPECT_FALSE(contains(workers.output, "impostor")) << workers.output;
  EXPECT_EQ(database().integer("SELECT COUNT(*) FROM workers"), 2);

  const fs::path fetched = fetchFrames(id, "fetched", {}, tokenEnvironment);
  expectSameFrames(fetched, renderLocally(spec), spec);
}

TEST_F(FarmTest, WorkersAndClientsWithTokensOfTheirOwnCannotActAsEachOther) {
  const fs::path clientToken = dir() / "client-token", workerToken = dir() / "worker-token";
  writeFile(clientToken, "client-token-81d2\n");
  writeFile(workerToken, "worker-token-3a7e\n");
  SchedulerConfig config;
  config.tokenFile = clientToken;
  config.extraArguments = {"--worker-token-file", workerToken.string()};
  const std::string scheduler = startScheduler(config);

  // The client's credential does not make a worker, nor the worker's a client.
  const std::optional<int> posing = startWorker("posing", {"--token-file", clientToken.string()}).wait(15s);
  ASSERT_TRUE(posing.has_value()) << "a worker with the client token kept running";
  EXPECT_NE(*posing, 0);
  const CommandResult fetchAsWorker =
      runPathfarm({"status", "--scheduler", scheduler, "--token-file", workerToken.string()});
  EXPECT_EQ(fetchAsWorker.status, 1) << fetchAsWorker.output;
  EXPECT_TRUE(contains(fetchAsWorker.output, "refused")) << fetchAsWorker.output;

  // Each with its own, the shot renders.
  startWorker("w1", {"--token-file", workerToken.string()});
  RenderSpec spec;
  const CommandResult submitted =
      runPathfarm({"submit", writeShotFile(spec).string(), "--scheduler", scheduler, "--token-file", clientToken.string()});
  ASSERT_EQ(submitted.status, 0) << submitted.output;
  EXPECT_EQ(waitForShot(shotIdFrom(submitted), 60s, "client-token-81d2").state(), farm::SHOT_DONE);
}

}  // namespace
}  // namespace pathfarm::farmtest
