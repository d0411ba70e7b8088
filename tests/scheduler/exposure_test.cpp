// What a scheduler may listen on: loopback freely; beyond it a token always, and TLS or
// the user's --insecure; the same rules for the HTTP side.
#include <gtest/gtest.h>

#include "scheduler/scheduler_server.h"

namespace pathfarm::farm {
namespace {

std::string problemOf(const SchedulerOptions& options) {
  try {
    checkExposure(options);
    return "";
  } catch (const std::runtime_error& e) {
    return e.what();
  }
}

TEST(Exposure, BeyondLoopbackATokenAndTlsOrTheUsersWord) {
  SchedulerOptions o;
  o.listen = "127.0.0.1:7700";
  EXPECT_EQ(problemOf(o), "");
  o.listen = "0.0.0.0:7700";
  EXPECT_NE(problemOf(o).find("give an access token"), std::string::npos) << problemOf(o);
  o.token = "secret";
  EXPECT_NE(problemOf(o).find("--tls-cert"), std::string::npos) << problemOf(o);
  o.insecure = true;
  EXPECT_EQ(problemOf(o), "");
  o.insecure = false;
  o.tls.certFile = "server.pem";
  o.tls.keyFile = "server.key";
  EXPECT_EQ(problemOf(o), "") << "TLS and a token need no --insecure";
  o.http = "[::]:9100";
  EXPECT_EQ(problemOf(o), "");
  o.tls = {};
  EXPECT_NE(problemOf(o).find("--listen"), std::string::npos);
  o.listen = "127.0.0.1:7700";
  EXPECT_NE(problemOf(o).find("--http [::]:9100"), std::string::npos) << problemOf(o);
}

}  // namespace
}  // namespace pathfarm::farm
