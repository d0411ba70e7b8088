// TLS on a real farm, with certificates the test makes (tests/farm/make_test_certificates.sh):
// a worker and the CLI that trust the scheduler's CA render a shot to the same bytes as
// ever, the dashboard and metrics answer over HTTPS, and a plain or wrongly trusting
// client gets nothing. With a client CA, a caller without a certificate it signed is
// refused and one with it is served.
#include <httplib.h>

#include "farm/farm_fixture.h"

namespace pathfarm::farmtest {
namespace {

class TlsFarmTest : public FarmTest {
 protected:
  void SetUp() override {
    FarmTest::SetUp();
    certificates_ = dir() / "certificates";
    const std::string command = "bash " + (fs::path(PATHFARM_SOURCE_DIR) / "tests" / "farm" /
                                           "make_test_certificates.sh").string() + " " + certificates_.string();
    ASSERT_EQ(std::system(command.c_str()), 0) << "cannot make the test certificates (is openssl installed?)";
  }
  std::string file(const std::string& name) const { return (certificates_ / name).string(); }
  farm::ClientTls trusting(const std::string& ca, const std::string& cert = "", const std::string& key = "") const {
    farm::ClientTls tls;
    tls.caFile = file(ca);
    if (!cert.empty()) tls.certFile = file(cert);
    if (!key.empty()) tls.keyFile = file(key);
    return tls;
  }
  std::vector<std::string> serverArguments() const {
    return {"--tls-cert", file("server.pem"), "--tls-key", file("server.key")};
  }
  // `pathfarm ARGUMENTS... --scheduler ADDRESS` plus TLS arguments.
  CommandResult runClient(std::vector<std::string> arguments, const std::vector<std::string>& tls) {
    arguments.insert(arguments.end(), {"--scheduler", address()});
    arguments.insert(arguments.end(), tls.begin(), tls.end());
    return runPathfarm(arguments);
  }

  fs::path certificates_;
};

TEST_F(TlsFarmTest, AFarmOverTlsRendersTheSameBytesAndRefusesWhoDoesNotTrustIt) {
  const fs::path httpPortFile = dir() / "http-port";
  SchedulerConfig config;
  config.extraArguments = serverArguments();
  config.extraArguments.insert(config.extraArguments.end(),
                               {"--http", "127.0.0.1:0", "--http-port-file", httpPortFile.string()});
  startScheduler(config);
  useTls(trusting("ca.pem"));
  startWorker("w1", {"--tls-ca", file("ca.pem")});
  RenderSpec spec;
  spec.frameEnd = 1;
  const CommandResult submitted = runClient({"submit", writeShotFile(spec).string()}, {"--tls-ca", file("ca.pem")});
  ASSERT_EQ(submitted.status, 0) << submitted.output;
  const int64_t id = shotIdFrom(submitted);
  ASSERT_EQ(waitForShot(id, 60s).state(), farm::SHOT_DONE);
  expectSameFrames(fetchFrames(id, "fetched", {"--tls-ca", file("ca.pem")}), renderLocally(spec), spec);

  // Refused, each saying what to do.
  const CommandResult plain = runClient({"status"}, {});
  EXPECT_NE(plain.status, 0) << "a client without TLS was served:\n" << plain.output;
  EXPECT_TRUE(contains(plain.output, "it speaks TLS; give the CA of its certificate with --tls-ca")) << plain.output;
  const CommandResult wrongCa = runClient({"status"}, {"--tls-ca", file("other-ca.pem")});
  EXPECT_NE(wrongCa.status, 0) << "a client trusting another CA was served:\n" << wrongCa.output;
  EXPECT_TRUE(contains(wrongCa.output, "the scheduler's certificate was refused")) << wrongCa.output;
  // A worker whose certificate check fails stops with the reason instead of retrying.
  const CommandResult distrustingWorker =
      runPathfarm({"worker", "--scheduler", address(), "--tls-ca", file("other-ca.pem"), "--cache",
                   (dir() / "distrusting-cache").string()},
                  {}, 20s);
  EXPECT_GT(distrustingWorker.status, 0) << distrustingWorker.output;
  EXPECT_TRUE(contains(distrustingWorker.output, "over TLS")) << distrustingWorker.output;
  const CommandResult environment = runPathfarm({"status", "--scheduler", address()}, {"PATHFARM_TLS_CA=" + file("ca.pem")});
  EXPECT_EQ(environment.status, 0) << environment.output;

  // The HTTP side is HTTPS with the same certificate.
  const int httpPort = std::stoi(readFile(httpPortFile));
  httplib::SSLClient https("127.0.0.1", httpPort);
  https.set_ca_cert_path(file("ca.pem").c_str());
  https.enable_server_certificate_verification(true);
  const auto metrics = https.Get("/metrics");
  ASSERT_TRUE(metrics) << "no answer over HTTPS: " << httplib::to_string(metrics.error());
  EXPECT_EQ(metrics->status, 200);
  EXPECT_TRUE(contains(metrics->body, "pathfarm_shots")) << metrics->body;
  httplib::Client http("127.0.0.1", httpPort);
  const auto plainHttp = http.Get("/metrics");
  EXPECT_TRUE(!plainHttp || plainHttp->status != 200) << "plain HTTP was answered";
}

TEST_F(TlsFarmTest, WithAClientCaOnlyCallersWithItsCertificatesAreServed) {
  SchedulerConfig config;
  config.extraArguments = serverArguments();
  config.extraArguments.insert(config.extraArguments.end(), {"--tls-client-ca", file("ca.pem")});
  startScheduler(config);
  const CommandResult anonymous = runClient({"status"}, {"--tls-ca", file("ca.pem")});
  EXPECT_NE(anonymous.status, 0) << "a client without a certificate was served:\n" << anonymous.output;
  const CommandResult signedClient =
      runClient({"status"}, {"--tls-ca", file("ca.pem"), "--tls-cert", file("client.pem"), "--tls-key", file("client.key")});
  EXPECT_EQ(signedClient.status, 0) << signedClient.output;
  const CommandResult keyless = runClient({"status"}, {"--tls-ca", file("ca.pem"), "--tls-cert", file("client.pem")});
  EXPECT_EQ(keyless.status, 1) << keyless.output;
  EXPECT_TRUE(contains(keyless.output, "both a TLS certificate and its key")) << keyless.output;

  useTls(trusting("ca.pem", "client.pem", "client.key"));
  startWorker("w1", {"--tls-ca", file("ca.pem"), "--tls-cert", file("client.pem"), "--tls-key", file("client.key")});
  RenderSpec spec;
  const int64_t id = client().submit(shotSpec(spec));
  EXPECT_EQ(waitForShot(id, 60s).state(), farm::SHOT_DONE);
}

}  // namespace
}  // namespace pathfarm::farmtest
