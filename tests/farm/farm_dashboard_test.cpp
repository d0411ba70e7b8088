// The dashboard's API on a real scheduler: its JSON agrees with what the test knows of
// the shot (frames, tiles, the one worker), a thumbnail is the frame shrunk, the token is
// asked for when the farm has one, the actions change the shot, and a request the API
// cannot serve gets a 4xx JSON error rather than a crash.
#include <httplib.h>
#include <stb_image.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "farm/farm_fixture.h"
#include "image/exr_io.h"

namespace pathfarm::farmtest {
namespace {

using nlohmann::json;

class DashboardTest : public FarmTest {
 protected:
  // A scheduler with its HTTP side on a free loopback port; returns that port.
  void startWithHttp(const fs::path& tokenFile = {}) {
    SchedulerConfig config;
    config.tokenFile = tokenFile;
    config.extraArguments = {"--http", "127.0.0.1:0", "--http-port-file", (dir() / "http-port").string()};
    startScheduler(config);
    httpPort_ = std::stoi(readFile(dir() / "http-port"));
  }

  httplib::Client http(const std::string& token = "") const {
    httplib::Client client("127.0.0.1", httpPort_);
    client.set_read_timeout(20, 0);
    if (!token.empty()) client.set_bearer_token_auth(token.c_str());
    return client;
  }

  // GET `path`, expecting `status` and a JSON body.
  json get(const std::string& path, int status = 200, const std::string& token = "") const {
    const auto response = http(token).Get(path.c_str());
    if (!response) throw std::runtime_error("no answer to GET " + path);
    EXPECT_EQ(response->status, status) << "GET " << path << ": " << response->body;
    return json::parse(response->body);
  }

  json post(const std::string& path, const std::string& body = "{}", int status = 200) const {
    const auto response = http().Post(path.c_str(), body, "application/json");
    if (!response) throw std::runtime_error("no answer to POST " + path);
    EXPECT_EQ(response->status, status) << "POST " << path << ": " << response->body;
    return json::parse(response->body);
  }

  int64_t submit(const RenderSpec& spec) {
    const CommandResult submitted = runPathfarm({"submit", writeShotFile(spec).string(), "--scheduler", address()});
    if (submitted.status != 0) throw std::runtime_error("submit failed: " + submitted.output);
    return shotIdFrom(submitted);
  }

  static std::string shotPath(int64_t id) { return "/api/shots/" + std::to_string(id); }

 private:
  int httpPort_ = 0;
};

TEST_F(DashboardTest, TheApiShowsAFinishedShot) {
  startWithHttp();
  RenderSpec spec;
  spec.frameEnd = 2;  // 3 frames of 2 x 2 tiles
  const int64_t id = submit(spec);
  startWorker("w1");
  ASSERT_EQ(waitForShot(id, 60s).state(), farm::SHOT_DONE);

  const json shots = get("/api/shots")["shots"];
  ASSERT_EQ(shots.size(), 1u) << shots;
  const json& shot = shots[0];
  EXPECT_EQ(shot["id"], id);
  EXPECT_EQ(shot["state"], "done");
  EXPECT_EQ(shot["tasks_total"], spec.tasks());
  EXPECT_EQ(shot["tasks_done"], spec.tasks());
  EXPECT_EQ(shot["frames_total"], spec.frames());
  EXPECT_EQ(shot["frames_done"], spec.frames());
  EXPECT_EQ(shot["priority"], 0);
  EXPECT_GT(shot["elapsed_seconds"].get<double>(), 0);

  const json page = get(shotPath(id));
  EXPECT_EQ(page["summary"]["tasks_done"], spec.tasks());
  EXPECT_EQ(page["spec"]["width"], spec.width);
  EXPECT_EQ(page["spec"]["pipeline"], "pt");
  ASSERT_EQ(page["frames"].size(), static_cast<size_t>(spec.frames()));
  for (int64_t f = 0; f < spec.frames(); ++f) {
    EXPECT_EQ(page["frames"][f]["frame"], spec.frameStart + f);
    EXPECT_EQ(page["frames"][f]["sha256"].get<std::string>().size(), 64u);
  }
  EXPECT_FALSE(page["events"].empty());
  EXPECT_TRUE(page["blocklist"].empty());

  const json tasks = get(shotPath(id) + "/tasks");
  EXPECT_EQ(tasks["matching"], spec.tasks());
  ASSERT_EQ(tasks["tasks"].size(), static_cast<size_t>(spec.tasks()));
  int64_t tiles = 0;
  for (const json& task : tasks["tasks"]) {
    tiles += task["kind"] == "render_tile";
    EXPECT_EQ(task["state"], "done") << task;
    EXPECT_EQ(task["worker"], "w1") << task;
    ASSERT_FALSE(task["attempts"].empty()) << task;
    EXPECT_EQ(task["attempts"].back()["state"], "done") << task;
    EXPECT_GE(task["seconds"].get<double>(), 0) << task;
    // The worker's own log of the attempt: started, what it ran and read, what it uploaded.
    const std::string log = task["attempts"].back()["log_tail"];
    const std::string id = std::to_string(task["id"].get<int64_t>());
    EXPECT_TRUE(contains(log, "task " + id + " (")) << log;
    EXPECT_TRUE(contains(log, "task " + id + ": ran ")) << log;
    EXPECT_TRUE(contains(log, "task " + id + ": output ")) << log;
    if (task["kind"] == "render_tile") {
      EXPECT_TRUE(contains(log, "samples ")) << log;
    }
    if (task["kind"] == "assemble_frame") {
      EXPECT_TRUE(contains(log, "read 4 input chunk(s)")) << log;
    }
  }
  EXPECT_EQ(tiles, spec.frames() * spec.tilesPerFrame());
  const json done = get(shotPath(id) + "/tasks?state=done&offset=2&limit=3");
  EXPECT_EQ(done["matching"], spec.tasks());
  ASSERT_EQ(done["tasks"].size(), 3u);
  EXPECT_EQ(done["tasks"][0]["id"], tasks["tasks"][2]["id"]);
  EXPECT_EQ(get(shotPath(id) + "/tasks?state=failed")["matching"], 0);

  // The report is report.json's document: proto3's JSON, 64-bit integers as strings.
  const json report = get(shotPath(id) + "/report");
  EXPECT_EQ(report["tasks_done"], std::to_string(spec.tasks()));
  EXPECT_EQ(report["frames"], std::to_string(spec.frames()));
  EXPECT_FALSE(report["stages"].empty());

  const json workers = get("/api/workers");
  ASSERT_EQ(workers["workers"].size(), 1u) << workers;
  EXPECT_EQ(workers["workers"][0]["name"], "w1");
  EXPECT_EQ(workers["workers"][0]["state"], "idle");
  EXPECT_EQ(workers["workers"][0]["busy"], 0);
  EXPECT_TRUE(workers["workers"][0]["tasks"].empty());
  EXPECT_LT(workers["workers"][0]["seconds_since_seen"].get<double>(), 30);
  EXPECT_TRUE(workers["blocklist"].empty());
}

TEST_F(DashboardTest, AThumbnailIsTheFrameShrunk) {
  startWithHttp();
  RenderSpec spec;
  spec.width = 320;  // shrunk by 2 to fit 160 pixels: 160 x 80
  spec.height = 160;
  spec.spp = 2;
  spec.tile = 160;
  const int64_t id = submit(spec);
  startWorker("w1");
  ASSERT_EQ(waitForShot(id, 60s).state(), farm::SHOT_DONE);

  const auto response = http().Get((shotPath(id) + "/frames/0/thumbnail.png").c_str());
  ASSERT_TRUE(response);
  ASSERT_EQ(response->status, 200) << response->body;
  EXPECT_EQ(response->get_header_value("Content-Type"), "image/png");
  int width = 0, height = 0, channels = 0;
  unsigned char* pixels =
      stbi_load_from_memory(reinterpret_cast<const unsigned char*>(response->body.data()),
                            static_cast<int>(response->body.size()), &width, &height, &channels, 3);
  ASSERT_NE(pixels, nullptr) << "not a PNG";
  const std::vector<unsigned char> thumbnail(pixels, pixels + width * height * 3);
  stbi_image_free(pixels);
  ASSERT_EQ(width, 160);
  ASSERT_EQ(height, 80);

  // Each thumbnail pixel: the sRGB encoding of the mean of its 2 x 2 block of the frame.
  const FrameImage frame = readExr(fetchFrames(id, "fetched") / farm::frameFileName(0));
  const auto srgb = [](double v) {
    v = std::clamp(v, 0.0, 1.0);
    return 255.0 * (v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055);
  };
  double worst = 0, darkest = 255, brightest = 0;
  const char* names[3] = {"R", "G", "B"};
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < 3; ++c) {
        const std::vector<float>& plane = frame.channel(names[c]);
        double mean = 0;
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) mean += plane[static_cast<size_t>(2 * y + dy) * frame.width() + 2 * x + dx];
        const double got = thumbnail[(static_cast<size_t>(y) * width + x) * 3 + c];
        worst = std::max(worst, std::abs(got - srgb(mean / 4)));
        darkest = std::min(darkest, got);
        brightest = std::max(brightest, got);
      }
    }
  }
  EXPECT_LE(worst, 1.0) << "8-bit levels between the thumbnail and the shrunk frame";
  EXPECT_GT(brightest - darkest, 50) << "the thumbnail shows a picture, not a flat colour";
  EXPECT_EQ(get(shotPath(id) + "/frames/7/thumbnail.png", 404)["error"], "shot " + std::to_string(id) + " has no frame 7 yet");
}

TEST_F(DashboardTest, WithATokenTheApiAsksForIt) {
  const fs::path tokenFile = dir() / "token";
  writeFile(tokenFile, "dashboard-test-token\n");
  startWithHttp(tokenFile);
  EXPECT_EQ(get("/api/shots", 401)["error"], "this farm requires its access token (Authorization: Bearer TOKEN)");
  get("/api/shots", 401, "dashboard-test-tokeN");
  get("/api/workers", 401, "dashboard-test-token-and-more");
  EXPECT_TRUE(get("/api/shots", 200, "dashboard-test-token")["shots"].empty());
  EXPECT_EQ(http().Post("/api/shots/1/pause", "{}", "application/json")->status, 401);
  // The page holds no data: it loads without the token and asks for it. /metrics is
  // scraped without credentials, as before the dashboard.
  EXPECT_EQ(http().Get("/metrics")->status, 200);
  const auto page = http().Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_TRUE(contains(page->body, "<script src=\"app.js\"")) << page->body;
  EXPECT_EQ(http().Get("/app.js")->status, 200);
  EXPECT_EQ(http().Get("/style.css")->status, 200);
}

TEST_F(DashboardTest, ActionsChangeTheShot) {
  startWithHttp();
  RenderSpec spec;
  spec.frameEnd = 1;
  const int64_t id = submit(spec);  // no worker yet: it waits in the queue
  EXPECT_EQ(post(shotPath(id) + "/pause")["summary"]["state"], "paused");
  EXPECT_EQ(get(shotPath(id))["summary"]["state"], "paused");
  EXPECT_EQ(post(shotPath(id) + "/resume")["summary"]["state"], "queued");
  EXPECT_EQ(post(shotPath(id) + "/priority", R"({"priority": 7})")["summary"]["priority"], 7);
  EXPECT_EQ(get("/api/shots")["shots"][0]["priority"], 7);
  EXPECT_TRUE(post(shotPath(id) + "/blocklist/0/clear")["blocklist"].empty());

  startWorker("w1");
  ASSERT_EQ(waitForShot(id, 60s).state(), farm::SHOT_DONE);
  // Frame 1 runs again: its tiles and assembly, and nothing of frame 0.
  const json requeued = post(shotPath(id) + "/frames/1/requeue")["summary"];
  EXPECT_NE(requeued["state"], "done");
  EXPECT_EQ(requeued["frames_done"], spec.frames() - 1);
  EXPECT_EQ(requeued["tasks_done"], spec.tasks() - (spec.tilesPerFrame() + 1));
  ASSERT_EQ(waitForShot(id, 60s).state(), farm::SHOT_DONE);
  const json task = get(shotPath(id) + "/tasks?limit=1")["tasks"][0];
  EXPECT_NE(post(shotPath(id) + "/tasks/" + std::to_string(task["id"].get<int64_t>()) + "/requeue")["summary"]["state"],
            "done");
  ASSERT_EQ(waitForShot(id, 60s).state(), farm::SHOT_DONE);
  const json events = get(shotPath(id))["events"];
  EXPECT_TRUE(contains(events.dump(), "requeued frame 1")) << events;

  const int64_t second = submit(spec);
  EXPECT_EQ(post(shotPath(second) + "/cancel")["summary"]["state"], "cancelled");
  EXPECT_TRUE(contains(post(shotPath(second) + "/frames/0/requeue", "{}", 409)["error"], "cancelled"));
}

TEST_F(DashboardTest, BadRequestsGetJsonErrors) {
  startWithHttp();
  const int64_t id = submit(RenderSpec{});
  for (const char* path : {"/api/shots/999", "/api/shots/999/tasks", "/api/shots/999/report",
                           "/api/shots/999/frames/0/thumbnail.png", "/api/nothing"})
    EXPECT_FALSE(get(path, 404)["error"].get<std::string>().empty()) << path;
  for (const std::string& path : std::vector<std::string>{"/api/shots/abc", "/api/shots/1x/tasks", "/api/shots/-3",
                                 shotPath(id) + "/frames/one/thumbnail.png", shotPath(id) + "/tasks?state=sleeping",
                                 shotPath(id) + "/tasks?limit=99999", shotPath(id) + "/tasks?offset=-1",
                                 "/api/shots/99999999999999999999999"})
    EXPECT_FALSE(get(path, 400)["error"].get<std::string>().empty()) << path;
  post("/api/shots/999/pause", "{}", 404);
  post("/api/shots/zz/pause", "{}", 400);
  post(shotPath(id) + "/priority", R"({"priority": "high"})", 400);
  post(shotPath(id) + "/priority", R"({"priority": 1e40})", 400);
  post(shotPath(id) + "/priority", "not json", 400);
  post(shotPath(id) + "/tasks/x/requeue", "{}", 400);
  post(shotPath(id) + "/tasks/987654/requeue", "{}", 404);  // no such task
  post(shotPath(id) + "/explode", "{}", 404);
  // An action is a JSON POST: not a GET, not a form.
  get(shotPath(id) + "/pause", 404);
  const auto form = http().Post((shotPath(id) + "/cancel").c_str(), "x=1", "application/x-www-form-urlencoded");
  ASSERT_TRUE(form);
  EXPECT_EQ(form->status, 415);
  EXPECT_EQ(get(shotPath(id))["summary"]["state"], "queued") << "nothing refused changed the shot";
}

}  // namespace
}  // namespace pathfarm::farmtest
