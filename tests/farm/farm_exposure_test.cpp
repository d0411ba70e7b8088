// What a scheduler refuses before it serves anyone: a second scheduler on a database that
// one already serves, an address beyond loopback without a token or without --insecure
// (the channel is not encrypted), and an empty PATHFARM_TOKEN, which must not switch
// access control off in silence. No test here binds anything but loopback: the refusals
// come before the address is bound.
#include "farm/farm_fixture.h"

namespace pathfarm::farmtest {
namespace {

TEST_F(FarmTest, ASecondSchedulerOnTheSameDatabaseIsRefused) {
  startScheduler();
  const CommandResult second =
      runPathfarm({"scheduler", "--listen", "127.0.0.1:0", "--db", databaseFile().string(), "--store",
                   (dir() / "other-store").string()});
  EXPECT_EQ(second.status, 1) << second.output;
  EXPECT_TRUE(contains(second.output, "is in use by another scheduler (pid ")) << second.output;
  // The first one serves on, and once it is gone (even killed) the database is free again.
  EXPECT_NO_THROW(client().shots());
  killScheduler();
  EXPECT_NO_THROW(startScheduler());
  EXPECT_NO_THROW(client().shots());
}

TEST_F(FarmTest, ListeningBeyondLoopbackNeedsATokenAndInsecure) {
  const fs::path tokenFile = dir() / "token";
  writeFile(tokenFile, "exposure-test-token\n");
  const std::vector<std::string> base = {"scheduler", "--db", (dir() / "exposed.db").string(), "--store",
                                         (dir() / "exposed-store").string()};
  const auto run = [&](std::vector<std::string> extra) {
    std::vector<std::string> arguments = base;
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    return runPathfarm(arguments);
  };
  const CommandResult open = run({"--listen", "0.0.0.0:0"});
  EXPECT_EQ(open.status, 1) << open.output;
  EXPECT_TRUE(contains(open.output, "reaches beyond this machine: give an access token")) << open.output;
  const CommandResult clear = run({"--listen", "[::]:0", "--token-file", tokenFile.string()});
  EXPECT_EQ(clear.status, 1) << clear.output;
  EXPECT_TRUE(contains(clear.output, "pass --insecure")) << clear.output;
  // The dashboard's API asks for the same token, sent in clear without TLS.
  const CommandResult openHttp = run({"--listen", "127.0.0.1:0", "--http", "0.0.0.0:0"});
  EXPECT_EQ(openHttp.status, 1) << openHttp.output;
  EXPECT_TRUE(contains(openHttp.output, "--http 0.0.0.0:0 reaches beyond this machine: give an access token"))
      << openHttp.output;
  const CommandResult clearHttp =
      run({"--listen", "127.0.0.1:0", "--http", "0.0.0.0:0", "--token-file", tokenFile.string()});
  EXPECT_EQ(clearHttp.status, 1) << clearHttp.output;
  EXPECT_TRUE(contains(clearHttp.output, "--http 0.0.0.0:0 reaches beyond this machine unencrypted")) << clearHttp.output;
  EXPECT_TRUE(contains(clearHttp.output, "pass --insecure")) << clearHttp.output;
  EXPECT_FALSE(fs::exists(dir() / "exposed.db")) << "refused before the database was opened";
}

TEST_F(FarmTest, AnEmptyTokenVariableIsAnErrorNotAnOpenFarm) {
  const CommandResult scheduler =
      runPathfarm({"scheduler", "--listen", "127.0.0.1:0", "--db", (dir() / "empty.db").string()}, {"PATHFARM_TOKEN="});
  EXPECT_EQ(scheduler.status, 1) << scheduler.output;
  EXPECT_TRUE(contains(scheduler.output, "PATHFARM_TOKEN is set but empty")) << scheduler.output;
  const CommandResult status = runPathfarm({"status", "--scheduler", "127.0.0.1:9"}, {"PATHFARM_TOKEN="});
  EXPECT_NE(status.status, 0) << status.output;
  EXPECT_TRUE(contains(status.output, "PATHFARM_TOKEN is set but empty")) << status.output;
}

}  // namespace
}  // namespace pathfarm::farmtest
