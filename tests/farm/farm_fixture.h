#pragma once
// The multi-process farm tests' fixture: every test gets a fresh folder, starts a real
// `pathfarm scheduler` and real `pathfarm worker` processes on loopback (ChildProcess,
// so none outlives the test), runs CLI commands, reads the scheduler's SQLite database,
// and compares the farm's frames with `pathfarm render`'s byte for byte. Every wait has
// a deadline; a helper that times out throws with a message saying what it waited for,
// which fails the test. TearDown stops every process and removes the folder, printing
// the processes' logs first when the test failed (PATHFARM_FARM_TEST_KEEP=1 keeps it).
#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>
#include <stdlib.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "client/child_process.h"
#include "client/farm_client.h"

namespace pathfarm::farmtest {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

inline fs::path pathfarmBinary() { return PATHFARM_BINARY; }
inline fs::path cornellScene() { return fs::path(PATHFARM_SOURCE_DIR) / "scenes" / "cornell" / "scene.json"; }

inline std::string readFile(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return "";
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

inline void writeFile(const fs::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

inline bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

inline std::string number(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

// Polls `condition` every `poll` until it holds or `timeout` has passed; true if it held.
template <class Condition>
bool waitUntil(Condition condition, std::chrono::milliseconds timeout, std::chrono::milliseconds poll = 20ms) {
  const auto deadline = Clock::now() + timeout;
  for (;;) {
    if (condition()) return true;
    if (Clock::now() >= deadline) return false;
    std::this_thread::sleep_for(poll);
  }
}

// Done, failed or cancelled: nothing more runs for the shot.
inline bool isOver(farm::ShotState state) {
  return state == farm::SHOT_DONE || state == farm::SHOT_FAILED || state == farm::SHOT_CANCELLED;
}

inline std::string describe(const farm::ShotSummary& s) {
  std::ostringstream text;
  text << "shot " << s.id() << " (" << s.name() << ") " << farm::ShotState_Name(s.state()) << ": " << s.tasks_done()
       << "/" << s.tasks_total() << " tasks done, " << s.tasks_running() << " running, " << s.tasks_failed()
       << " failed, " << s.attempts() << " attempts";
  if (!s.failure().empty()) text << "; failure: " << s.failure();
  return text.str();
}

// What a shot renders; the same settings go to the farm and to `pathfarm render`.
struct RenderSpec {
  std::string name = "shot";
  int64_t frameStart = 0;
  int64_t frameEnd = 0;
  int width = 64;
  int height = 48;
  int spp = 4;
  int maxDepth = 4;
  int tile = 32;
  int maxAttempts = 3;
  fs::path scene = cornellScene();

  int64_t frames() const { return frameEnd - frameStart + 1; }
  int64_t tilesPerFrame() const {
    return static_cast<int64_t>((width + tile - 1) / tile) * ((height + tile - 1) / tile);
  }
  int64_t tasks() const { return frames() * (tilesPerFrame() + 1); }  // the tiles and an assembly per frame
};

struct SchedulerConfig {
  std::string listen = "127.0.0.1:0";
  double leaseSeconds = 30;
  double retryBackoffSeconds = 1;
  fs::path tokenFile;  // empty: no access token
  std::vector<std::string> extraArguments;
};

struct CommandResult {
  int status = -1;     // the exit status; -1 when the command did not end in time
  std::string output;  // stdout and stderr, interleaved
};

// Reads the scheduler's database the way an operator would, with its own connection.
class FarmDatabase {
 public:
  explicit FarmDatabase(fs::path file) : file_(std::move(file)) {}

  // Every row as text (NULL reads as "").
  std::vector<std::vector<std::string>> rows(const std::string& sql) const {
    sqlite3* db = nullptr;
    if (sqlite3_open_v2(file_.c_str(), &db, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) {
      const std::string message = db ? sqlite3_errmsg(db) : "out of memory";
      sqlite3_close(db);
      throw std::runtime_error(file_.string() + ": cannot open the farm database: " + message);
    }
    sqlite3_busy_timeout(db, 5000);
    sqlite3_stmt* statement = nullptr;
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &statement, nullptr) != SQLITE_OK) {
      const std::string message = sqlite3_errmsg(db);
      sqlite3_close(db);
      throw std::runtime_error("cannot prepare \"" + sql + "\": " + message);
    }
    std::vector<std::vector<std::string>> out;
    int result = 0;
    while ((result = sqlite3_step(statement)) == SQLITE_ROW) {
      std::vector<std::string> row;
      for (int c = 0; c < sqlite3_column_count(statement); ++c) {
        const auto* text = sqlite3_column_text(statement, c);
        row.emplace_back(text ? reinterpret_cast<const char*>(text) : "");
      }
      out.push_back(std::move(row));
    }
    const std::string message = sqlite3_errmsg(db);
    sqlite3_finalize(statement);
    sqlite3_close(db);
    if (result != SQLITE_DONE) throw std::runtime_error("\"" + sql + "\" failed: " + message);
    return out;
  }

  // The first column of the one row a query returns, as an integer.
  int64_t integer(const std::string& sql) const {
    const auto result = rows(sql);
    if (result.size() != 1 || result[0].empty() || result[0][0].empty())
      throw std::runtime_error("\"" + sql + "\" did not return one integer");
    return std::stoll(result[0][0]);
  }

 private:
  fs::path file_;
};

class FarmTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // The tests decide who carries a token; nothing is inherited from the caller.
    ::unsetenv("PATHFARM_TOKEN");
    ::unsetenv("PATHFARM_TOKEN_FILE");
    std::string pattern = (fs::temp_directory_path() / "pathfarm-farm-test-XXXXXX").string();
    ASSERT_NE(::mkdtemp(pattern.data()), nullptr) << "cannot create a temporary folder";
    dir_ = pattern;
    fs::create_directories(dir_ / "logs");
  }

  void TearDown() override {
    stopWorkers();
    if (scheduler_) scheduler_->stop(5s);
    scheduler_.reset();
    if (HasFailure()) dumpLogs();
    if (std::getenv("PATHFARM_FARM_TEST_KEEP")) {
      std::cerr << "kept the test's folder: " << dir_.string() << "\n";
    } else if (!dir_.empty()) {
      std::error_code ignored;
      fs::remove_all(dir_, ignored);
    }
  }

  const fs::path& dir() const { return dir_; }
  fs::path databaseFile() const { return dir_ / "farm.db"; }
  fs::path storeFolder() const { return dir_ / "store"; }
  fs::path logFile(const std::string& name) const { return dir_ / "logs" / (name + ".log"); }
  FarmDatabase database() const { return FarmDatabase(databaseFile()); }
  const std::string& address() const { return address_; }
  int port() const { return port_; }

  // Starts `pathfarm scheduler` on the test's database and store and waits for its port
  // file; returns its address. Any earlier scheduler must have been stopped or killed.
  std::string startScheduler(const SchedulerConfig& config = {}) {
    if (scheduler_) throw std::logic_error("a scheduler is already running");
    const int run = ++schedulerRuns_;
    const fs::path portFile = dir_ / ("port-" + std::to_string(run));
    std::vector<std::string> argv = {pathfarmBinary().string(), "scheduler",     "--listen",
                                     config.listen,             "--port-file",   portFile.string(),
                                     "--db",                    databaseFile().string(), "--store",
                                     storeFolder().string(),    "--lease-seconds", number(config.leaseSeconds),
                                     "--retry-backoff",         number(config.retryBackoffSeconds)};
    if (!config.tokenFile.empty()) {
      argv.push_back("--token-file");
      argv.push_back(config.tokenFile.string());
    }
    argv.insert(argv.end(), config.extraArguments.begin(), config.extraArguments.end());
    const fs::path log = logFile("scheduler-" + std::to_string(run));
    scheduler_.emplace(argv, log.string());
    std::string text;
    const bool exited = waitUntil(
        [&] {
          text = readFile(portFile);
          return !text.empty() || scheduler_->wait(0ms).has_value();
        },
        15s);
    if (text.empty()) {
      const auto status = scheduler_->wait(0ms);
      scheduler_.reset();
      throw std::runtime_error(
          std::string(exited ? "the scheduler exited with status " + std::to_string(status.value_or(-1))
                                : "the scheduler wrote no port file within 15 s") +
          "; its log:\n" + readFile(log));
    }
    port_ = std::stoi(text);
    address_ = "127.0.0.1:" + std::to_string(port_);
    return address_;
  }

  // SIGKILL: the scheduler gets no chance to tidy up.
  void killScheduler() {
    if (!scheduler_) throw std::logic_error("no scheduler to kill");
    scheduler_->signal(SIGKILL);
    const auto status = scheduler_->wait(10s);
    if (status != 128 + SIGKILL)
      throw std::runtime_error("the killed scheduler did not die of SIGKILL (status " +
                               std::to_string(status.value_or(-1)) + ")");
    scheduler_.reset();
  }

  // Starts `pathfarm worker --threads 1` against the current scheduler.
  farm::ChildProcess& startWorker(const std::string& name, const std::vector<std::string>& extraArguments = {},
                                  const std::vector<std::string>& environment = {}) {
    if (workers_.count(name)) throw std::logic_error("worker " + name + " exists already");
    std::vector<std::string> argv = {pathfarmBinary().string(), "worker", "--scheduler", address_, "--threads", "1",
                                     "--name", name, "--cache", (dir_ / "cache" / name).string()};
    argv.insert(argv.end(), extraArguments.begin(), extraArguments.end());
    return workers_.try_emplace(name, argv, logFile("worker-" + name).string(), environment).first->second;
  }

  farm::ChildProcess& worker(const std::string& name) { return workers_.at(name); }
  std::string workerLog(const std::string& name) const { return readFile(logFile("worker-" + name)); }

  // SIGTERM to every worker at once, then each gets a few seconds before SIGKILL.
  // Returns the exit statuses by name.
  std::map<std::string, int> stopWorkers() {
    for (auto& [name, process] : workers_) process.signal(SIGTERM);
    std::map<std::string, int> statuses;
    for (auto& [name, process] : workers_) statuses[name] = process.stop(4s);
    workers_.clear();
    return statuses;
  }

  // Runs `pathfarm ARGS...` to completion (or kills it after `timeout`).
  CommandResult runPathfarm(const std::vector<std::string>& arguments, const std::vector<std::string>& environment = {},
                            std::chrono::milliseconds timeout = 30s) {
    std::vector<std::string> argv = {pathfarmBinary().string()};
    argv.insert(argv.end(), arguments.begin(), arguments.end());
    const fs::path log = logFile("command-" + std::to_string(++commands_) + "-" + arguments.front());
    CommandResult result;
    {
      farm::ChildProcess process(argv, log.string(), environment);
      const auto status = process.wait(timeout);
      if (status) {
        result.status = *status;
      } else {
        process.signal(SIGKILL);
        process.wait(5s);
      }
    }
    result.output = readFile(log);
    if (result.status == -1) {
      std::string command = "pathfarm";
      for (const std::string& a : arguments) command += " " + a;
      ADD_FAILURE() << "`" << command << "` did not finish within " << timeout.count() << " ms; output:\n"
                    << result.output;
    }
    return result;
  }

  farm::FarmClient client(const std::string& token = "") const { return farm::FarmClient(address_, token, clientTls_); }
  // client() and waitForShot() connect over TLS from now on.
  void useTls(const farm::ClientTls& tls) { clientTls_ = tls; }

  // Polls the shot until it is done, failed or cancelled; throws on timeout. Calls that
  // fail (a scheduler restarting) are retried until the deadline.
  farm::ShotSummary waitForShot(int64_t id, std::chrono::milliseconds timeout, const std::string& token = "") {
    farm::ShotSummary last;
    std::string error;
    const bool ended = waitUntil(
        [&] {
          try {
            last = client(token).shot(id).summary();
            return isOver(last.state());
          } catch (const farm::FarmError& e) {
            error = e.what();
            return false;
          }
        },
        timeout, 50ms);
    if (!ended)
      throw std::runtime_error("shot " + std::to_string(id) + " did not end within " +
                               std::to_string(timeout.count()) + " ms; last seen: " + describe(last) +
                               (error.empty() ? "" : "; last error: " + error));
    return last;
  }

  // The shot file of `spec` (JSON, docs/shot-format.md), in the test's folder.
  fs::path writeShotFile(const RenderSpec& spec) const {
    std::ostringstream json;
    json << "{\n"
         << "  \"name\": \"" << spec.name << "\",\n"
         << "  \"scene\": \"" << spec.scene.string() << "\",\n"
         << "  \"frames\": {\"start\": " << spec.frameStart << ", \"end\": " << spec.frameEnd << "},\n"
         << "  \"resolution\": [" << spec.width << ", " << spec.height << "],\n"
         << "  \"spp\": " << spec.spp << ",\n"
         << "  \"max_depth\": " << spec.maxDepth << ",\n"
         << "  \"pipeline\": \"pt\",\n"
         << "  \"tile\": " << spec.tile << ",\n"
         << "  \"output\": \"" << (dir_ / "shot-output" / spec.name).string() << "\",\n"
         << "  \"priority\": 0,\n"
         << "  \"max_attempts\": " << spec.maxAttempts << "\n"
         << "}\n";
    const fs::path file = dir_ / (spec.name + ".shot.json");
    writeFile(file, json.str());
    return file;
  }

  // The same shot as a ShotSpec, for submitting with FarmClient (no CLI validation).
  farm::ShotSpec shotSpec(const RenderSpec& spec) const {
    farm::ShotSpec s;
    s.set_name(spec.name);
    s.set_scene(spec.scene.string());
    s.set_frame_start(spec.frameStart);
    s.set_frame_end(spec.frameEnd);
    s.set_width(spec.width);
    s.set_height(spec.height);
    s.set_spp(spec.spp);
    s.set_max_depth(spec.maxDepth);
    s.set_pipeline(farm::PIPELINE_PT);
    s.set_tile(spec.tile);
    s.set_output((dir_ / "shot-output" / spec.name).string());
    s.set_priority(0);
    s.set_max_attempts(spec.maxAttempts);
    return s;
  }

  // `pathfarm submit`'s output: the id on a line of its own.
  static int64_t shotIdFrom(const CommandResult& submitted) {
    std::istringstream lines(submitted.output);
    std::string line;
    while (std::getline(lines, line)) {
      if (!line.empty() && line.find_first_not_of("0123456789") == std::string::npos) return std::stoll(line);
    }
    throw std::runtime_error("`pathfarm submit` printed no shot id:\n" + submitted.output);
  }

  // `pathfarm fetch ID --out DIR`; returns DIR.
  fs::path fetchFrames(int64_t id, const std::string& folder, const std::vector<std::string>& extra = {},
                       const std::vector<std::string>& environment = {}) {
    const fs::path out = dir_ / folder;
    std::vector<std::string> arguments = {"fetch", std::to_string(id), "--out", out.string(), "--scheduler", address_};
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    const CommandResult fetched = runPathfarm(arguments, environment);
    if (fetched.status != 0)
      throw std::runtime_error("`pathfarm fetch` exited with " + std::to_string(fetched.status) + ":\n" +
                               fetched.output);
    return out;
  }

  // `pathfarm render` of the same frames and settings on this machine; returns the folder.
  fs::path renderLocally(const RenderSpec& spec, const std::string& folder = "local") {
    const fs::path out = dir_ / folder;
    const CommandResult rendered = runPathfarm(
        {"render", spec.scene.string(), "--frames",
         std::to_string(spec.frameStart) + ":" + std::to_string(spec.frameEnd), "--res",
         std::to_string(spec.width) + "x" + std::to_string(spec.height), "--spp", std::to_string(spec.spp),
         "--max-depth", std::to_string(spec.maxDepth), "--out", out.string()},
        {}, 60s);
    if (rendered.status != 0)
      throw std::runtime_error("`pathfarm render` exited with " + std::to_string(rendered.status) + ":\n" +
                               rendered.output);
    return out;
  }

  // The farm's frames are the local render's files, byte for byte, and nothing else.
  static void expectSameFrames(const fs::path& farmFolder, const fs::path& localFolder, const RenderSpec& spec) {
    int64_t exrFiles = 0;
    for (const auto& entry : fs::directory_iterator(farmFolder)) exrFiles += entry.path().extension() == ".exr";
    EXPECT_EQ(exrFiles, spec.frames()) << "EXR files fetched into " << farmFolder;
    for (int64_t frame = spec.frameStart; frame <= spec.frameEnd; ++frame) {
      const std::string name = farm::frameFileName(frame);
      const std::string fromFarm = readFile(farmFolder / name), fromLocal = readFile(localFolder / name);
      if (fromFarm.empty() || fromLocal.empty()) {
        ADD_FAILURE() << name << ": missing or empty (farm " << fromFarm.size() << " bytes, local "
                      << fromLocal.size() << " bytes)";
        continue;
      }
      if (fromFarm != fromLocal) {
        size_t at = 0;
        while (at < fromFarm.size() && at < fromLocal.size() && fromFarm[at] == fromLocal[at]) ++at;
        ADD_FAILURE() << name << ": the farm's file differs from `pathfarm render`'s: " << fromFarm.size() << " vs "
                      << fromLocal.size() << " bytes, first difference at byte " << at;
      }
    }
  }

  // The chunk store's file for a digest (objects/ab/cdef...).
  fs::path chunkFile(const std::string& sha256) const {
    return storeFolder() / "objects" / sha256.substr(0, 2) / sha256.substr(2);
  }

 private:
  void dumpLogs() const {
    std::error_code error;
    for (const auto& entry : fs::directory_iterator(dir_ / "logs", error)) {
      std::string text = readFile(entry.path());
      constexpr size_t kTail = 4000;
      if (text.size() > kTail) text = "..." + text.substr(text.size() - kTail);
      std::cerr << "----- " << entry.path().filename().string() << " -----\n" << text << "\n";
    }
  }

  fs::path dir_;
  std::optional<farm::ChildProcess> scheduler_;
  std::map<std::string, farm::ChildProcess> workers_;
  std::string address_;
  farm::ClientTls clientTls_;
  int port_ = 0;
  int schedulerRuns_ = 0;
  int commands_ = 0;
};

}  // namespace pathfarm::farmtest
