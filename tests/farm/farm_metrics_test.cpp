// The scheduler's /metrics (Prometheus text format) after a shot: every figure is checked
// against what the test knows independently (the shot's tiles and frames, the one
// worker, the chunks it moved), and the histogram's buckets are cumulative up to +Inf.
#include <httplib.h>

#include "farm/farm_fixture.h"

namespace pathfarm::farmtest {
namespace {

// "name{labels} value" lines by "name{labels}"; comments and blank lines skipped.
std::map<std::string, double> samplesOf(const std::string& text) {
  std::map<std::string, double> samples;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] == '#') continue;
    const size_t space = line.rfind(' ');
    samples[line.substr(0, space)] = std::stod(line.substr(space + 1));
  }
  return samples;
}

TEST_F(FarmTest, MetricsCountWhatTheShotDid) {
  const fs::path httpPortFile = dir() / "http-port";
  SchedulerConfig config;
  config.extraArguments = {"--http", "127.0.0.1:0", "--http-port-file", httpPortFile.string()};
  startScheduler(config);
  const int httpPort = std::stoi(readFile(httpPortFile));
  httplib::Client http("127.0.0.1", httpPort);
  http.set_read_timeout(10, 0);

  RenderSpec spec;
  spec.frameEnd = 1;
  spec.tile = 32;  // 2 x 2 tiles a frame at 64 x 48
  const CommandResult submitted = runPathfarm({"submit", writeShotFile(spec).string(), "--scheduler", address()});
  ASSERT_EQ(submitted.status, 0) << submitted.output;
  const int64_t id = shotIdFrom(submitted);
  startWorker("w1");
  ASSERT_EQ(waitForShot(id, 60s).state(), farm::SHOT_DONE);
  // A second shot no worker may take (it requires a tag nobody offers) waits at 0 % done.
  RenderSpec waiting = spec;
  waiting.name = "waiting";
  farm::ShotSpec untaken = shotSpec(waiting);
  untaken.add_required_tags("nobody-has-this");
  const int64_t waitingId = client().submit(untaken);

  const auto response = http.Get("/metrics");
  ASSERT_TRUE(response) << "no answer from /metrics";
  ASSERT_EQ(response->status, 200);
  EXPECT_NE(response->get_header_value("Content-Type").find("text/plain; version=0.0.4"), std::string::npos);
  const std::string& body = response->body;
  EXPECT_NE(body.find("# TYPE pathfarm_task_duration_seconds histogram"), std::string::npos) << body;
  const auto samples = samplesOf(body);
  const auto value = [&](const std::string& key) {
    const auto it = samples.find(key);
    EXPECT_NE(it, samples.end()) << key << " missing in:\n" << body;
    return it == samples.end() ? -1.0 : it->second;
  };
  const double tiles = static_cast<double>(spec.frames() * spec.tilesPerFrame());
  EXPECT_EQ(value(R"(pathfarm_tasks{kind="render_tile",state="done"})"), tiles);
  EXPECT_EQ(value(R"(pathfarm_tasks{kind="assemble_frame",state="done"})"), spec.frames());
  EXPECT_EQ(value(R"(pathfarm_shots{state="done"})"), 1);
  EXPECT_EQ(value(R"(pathfarm_shots{state="queued"})"), 1);
  EXPECT_EQ(value("pathfarm_shot_progress{shot=\"" + std::to_string(waitingId) + "\",name=\"waiting\"}"), 0);
  EXPECT_EQ(samples.count("pathfarm_shot_progress{shot=\"" + std::to_string(id) + "\",name=\"" + spec.name + "\"}"),
            0u) << "a done shot's progress is not a gauge any more";
  EXPECT_EQ(value(R"(pathfarm_workers{state="idle"})") + value(R"(pathfarm_workers{state="busy"})"), 1);
  EXPECT_EQ(value(R"(pathfarm_attempts_ended_total{cause="worker_fault"})"), 0);
  EXPECT_EQ(value(R"(pathfarm_task_duration_seconds_count{kind="render_tile"})"), tiles);
  EXPECT_EQ(value(R"(pathfarm_task_duration_seconds_bucket{kind="render_tile",le="+Inf"})"), tiles);
  double previous = 0;
  for (const char* le : {"0.1", "0.5", "1", "2", "5", "10", "30", "60", "300", "1800", "7200", "+Inf"}) {
    const double cumulative =
        value(std::string(R"(pathfarm_task_duration_seconds_bucket{kind="render_tile",le=")") + le + "\"}");
    EXPECT_GE(cumulative, previous) << "le " << le;
    previous = cumulative;
  }
  EXPECT_GT(value(R"(pathfarm_task_duration_seconds_sum{kind="render_tile"})"), 0);
  // Every tile and frame went into the store; the assemblies read the tiles back out.
  const FarmDatabase db = database();
  EXPECT_GE(value(R"(pathfarm_chunk_bytes_total{direction="in"})"),
            static_cast<double>(db.integer("SELECT SUM(size) FROM chunks")));
  EXPECT_GT(value(R"(pathfarm_chunk_bytes_total{direction="out"})"), 0);
  EXPECT_EQ(http.Get("/nothing-here")->status, 404);
}

}  // namespace
}  // namespace pathfarm::farmtest
