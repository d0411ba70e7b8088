// `pathfarm submit | status | watch | fetch | report | cancel | pause | resume | retry | priority |
// requeue | blocklist | workers`: thin calls through FarmClient.
#include <spdlog/spdlog.h>

#include <cstdio>
#include <memory>
#include <optional>

#include "cli/command.h"
#include "cli/reference_cache_options.h"
#include "cli/frame_name_options.h"
#include "cli/shot_hook_options.h"
#include "cli/shot_key_options.h"
#include "cli/shot_progress.h"
#include "cli/tls_options.h"
#include "cli/usage_parsing.h"
#include "proto/wire/connection.h"
#include "renderer/scene/json_node.h"
#include "client/farm_client.h"
#include "image/beauty_copy.h"
#include "client/scene_upload.h"
#include "client/shot_preparation.h"
#include "client/shot_source.h"
#include "scheduler/shot_report.h"

namespace pathfarm {
namespace {

struct ClientArguments {
  std::string scheduler = "127.0.0.1:7700";
  std::string tokenFile;
  std::string shotFile;
  ShotKeyArguments shotKeys;
  std::string submitKey;
  int64_t shotId = 0;
  int priority = 0;
  bool clear = false;
  int64_t workerId = 0;
  std::optional<int64_t> taskId;
  std::optional<int64_t> frame;
  std::string out;
  bool json = false;
  bool sharedPaths = false;
  bool beauty = false;
  farm::ShotHooks hooks;
  std::string frameNames;
  std::vector<int64_t> after;
  std::string referenceCache;
  farm::ClientTls tls;
};

void addConnectionOptions(CLI::App* command, ClientArguments& arguments) {
  command->add_option("--scheduler", arguments.scheduler, "scheduler address HOST:PORT")->capture_default_str();
  command->add_option("--token-file", arguments.tokenFile,
                      "file holding the farm's access token (or PATHFARM_TOKEN[_FILE])");
  addClientTlsOptions(command, arguments.tls);
}

// Runs a client call, turning the farm's refusals into messages and exit statuses.
template <class Body>
int withClient(const ClientArguments& arguments, Body body) {
  try {
    farm::FarmClient client(arguments.scheduler, farm::loadToken(arguments.tokenFile),
                            farm::clientTlsFromEnvironment(arguments.tls));
    return body(client);
  } catch (const SceneError& e) {
    spdlog::error("{}", e.what());
    return kExitBadInput;
  } catch (const UsageError& e) {
    spdlog::error("{}", e.what());
    return kExitBadInput;
  } catch (const farm::FarmError& e) {
    spdlog::error("{}", e.what());
    const bool badRequest = e.code() == grpc::StatusCode::INVALID_ARGUMENT || e.code() == grpc::StatusCode::NOT_FOUND ||
                            e.code() == grpc::StatusCode::FAILED_PRECONDITION;
    return badRequest ? kExitBadInput : kExitFailure;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return kExitFailure;
  }
}

int exitFor(const farm::ShotSummary& summary) { return summary.state() == farm::SHOT_DONE ? kExitOk : kExitFailure; }

// Adds client subcommands to an app, each with the connection options, run through
// withClient.
class ClientCommands {
 public:
  explicit ClientCommands(CLI::App& app) : app_(app) {}

  // `configure(command, arguments)` adds the command's own options; `run(client, arguments)`
  // returns its exit status.
  template <class Configure, class Run>
  void command(const char* name, const char* description, Configure configure, Run run) {
    auto arguments = std::make_shared<ClientArguments>();
    CLI::App* command = app_.add_subcommand(name, description);
    addConnectionOptions(command, *arguments);
    configure(command, *arguments);
    commands_.push_back({command, [arguments, run] {
                           return withClient(*arguments, [&](farm::FarmClient& c) { return run(c, *arguments); });
                         }});
  }
  std::vector<Command> commands() && { return std::move(commands_); }

 private:
  CLI::App& app_;
  std::vector<Command> commands_;
};

void shotIdOption(CLI::App* command, ClientArguments& a) { command->add_option("id", a.shotId, "shot id")->required(); }

// Submitting a shot, and following it to its frames and report.
void addShotCommands(ClientCommands& add) {
  add.command(
      "submit", "queue a shot (a shot file, or a scene file with shot keys as options); prints the shot id",
      [](CLI::App* c, ClientArguments& a) {
        c->add_option("shot", a.shotFile, "shot file (JSON), or a scene file (glTF, JSON scene) to render as a shot")
            ->required();
        addShotKeyOptions(c, a.shotKeys);
        c->add_option("--after", a.after,
                      "shot id this one waits for: it starts when every one is done, and fails if one fails or is "
                      "cancelled (repeatable)");
        c->add_option("--submit-key", a.submitKey,
                      "names this submit: submitting again with the same key prints the same shot, adds nothing");
        c->add_flag("--shared-paths", a.sharedPaths,
                    "upload nothing: workers read the scene at its absolute path on storage they share with you");
        addReferenceCacheOption(c, a.referenceCache);
      },
      [](farm::FarmClient& client, const ClientArguments& a) {
        const farm::ShotFile file = farm::loadShotSource(a.shotFile, shotKeysOf(a.shotKeys));
        farm::ShotSpec spec = farm::preparedShot(file);  // validated before anything is queued
        if (!a.sharedPaths) {
          const farm::UploadSummary sent = farm::uploadSceneInputs(client, spec);
          spdlog::info("scene: {} files, {:.1f} MB; sent {} ({:.1f} MB), the farm had the rest", sent.files,
                       static_cast<double>(sent.bytes) / 1e6, sent.filesSent,
                       static_cast<double>(sent.bytesSent) / 1e6);
        }
        spec = withChosenPipeline(client, file, spec, std::filesystem::path(spec.output()) / "probe", a.submitKey);
        for (const int64_t after : a.after) spec.add_after_shots(after);
        if (const auto references = referenceCacheOf(file, a.referenceCache))
          attachCachedReferences(*references, client, spec);
        std::printf("%lld\n", static_cast<long long>(client.submit(spec, a.submitKey)));
        return kExitOk;
      });
  add.command(
      "status", "list every shot, or show one with its events",
      [](CLI::App* c, ClientArguments& a) { c->add_option("id", a.shotId, "shot id"); },
      [](farm::FarmClient& client, const ClientArguments& a) {
        if (a.shotId == 0) {
          for (const auto& s : client.shots()) std::printf("%s\n", describeShot(s).c_str());
          return kExitOk;
        }
        const farm::ShotReply reply = client.shot(a.shotId);
        std::printf("%s\n", describeShot(reply.summary()).c_str());
        for (const auto& event : reply.events()) std::printf("  %.3f  %s\n", event.time(), event.message().c_str());
        return kExitOk;
      });
  add.command(
      "watch", "follow a shot until it ends",
      [](CLI::App* c, ClientArguments& a) {
        shotIdOption(c, a);
        addShotHookOptions(c, a.hooks);
      },
      [](farm::FarmClient& client, const ClientArguments& a) {
        farm::ShotSummary summary;
        {
          ShotProgress progress;
          summary = client.watch(a.shotId, [&](const farm::ShotSummary& s) { progress.update(s); });
        }
        std::printf("%s\n", describeShot(summary).c_str());
        std::fflush(stdout);
        const farm::ShotSpec spec = client.shot(a.shotId).spec();
        farm::runShotHook(a.hooks, outcomeOf(spec, summary, spec.output()));
        return exitFor(summary);
      });
  add.command(
      "fetch", "write a shot's finished frames as EXR files",
      [](CLI::App* c, ClientArguments& a) {
        c->add_option("id", a.shotId, "shot id")->required();
        c->add_option("--out", a.out, "output folder")->required();
        c->add_option("--reference-cache", a.referenceCache, "also keep the shot's references in this folder");
        c->add_flag("--beauty", a.beauty,
                    "also write each frame's R, G, B alone into OUT/beauty/, for viewers that refuse the other "
                    "layers (Blender)");
        addFrameNamesOption(c, a.frameNames);
      },
      [](farm::FarmClient& client, const ClientArguments& a) {
        const std::optional<farm::FrameNames> names = frameNamesOf(a.frameNames);
        const farm::ShotReply shot = client.shot(a.shotId);
        const auto& summary = shot.summary();
        const std::filesystem::path out(a.out);
        auto files = client.fetch(a.shotId, out);
        if (names) files = farm::renameFrames(files, out, *names, shot.spec().name(), a.shotId);
        if (a.beauty) {
          for (const auto& file : files) {
            const std::filesystem::path copy = out / "beauty" / std::filesystem::relative(file, out);
            std::filesystem::create_directories(copy.parent_path());
            writeBeautyCopy(file, copy);
          }
        }
        if (!a.referenceCache.empty() && summary.state() == farm::SHOT_DONE)
          keepRenderedReferences(farm::ReferenceCache(a.referenceCache), client, a.shotId, shot.spec());
        std::printf("%zu frames in %s\n", files.size(), a.out.c_str());
        if (summary.state() != farm::SHOT_DONE)
          spdlog::warn("shot {} is {}: fetched the {} frames finished so far", a.shotId,
                       farm::ShotState_Name(summary.state()), files.size());
        return kExitOk;
      });
  add.command(
      "report", "a shot's speed against error: core-seconds per stage, re-render rates, errors",
      [](CLI::App* c, ClientArguments& a) {
        c->add_option("id", a.shotId, "shot id")->required();
        c->add_option("--out", a.out, "also write report.json and report.md into this folder");
        c->add_flag("--json", a.json, "print JSON instead of Markdown");
      },
      [](farm::FarmClient& client, const ClientArguments& a) {
        const farm::ShotReport report = client.report(a.shotId);
        std::printf("%s", (a.json ? farm::reportJson(report) : farm::reportMarkdown(report)).c_str());
        if (!a.out.empty()) farm::writeReportFiles(report, a.out);
        return kExitOk;
      });
}

// Changing what the farm does with a shot, and what it knows of its workers.
void addControlCommands(ClientCommands& add) {
  const auto control = [&](const char* name, const char* description, auto call) {
    add.command(name, description, shotIdOption, [call](farm::FarmClient& client, const ClientArguments& a) {
      std::printf("%s\n", describeShot(call(client, a.shotId)).c_str());
      return kExitOk;
    });
  };
  control("cancel", "cancel a shot", [](farm::FarmClient& c, int64_t id) { return c.cancel(id); });
  control("pause", "stop leasing a shot's tasks", [](farm::FarmClient& c, int64_t id) { return c.pause(id); });
  control("resume", "lease a paused shot's tasks again", [](farm::FarmClient& c, int64_t id) { return c.resume(id); });
  control("retry", "run a failed shot again from what is done",
          [](farm::FarmClient& c, int64_t id) { return c.retry(id); });
  add.command(
      "priority", "change a shot's priority (higher runs first)",
      [](CLI::App* c, ClientArguments& a) {
        c->add_option("id", a.shotId, "shot id")->required();
        c->add_option("priority", a.priority, "the new priority")->required();
      },
      [](farm::FarmClient& client, const ClientArguments& a) {
        std::printf("%s\n", describeShot(client.setPriority(a.shotId, a.priority)).c_str());
        return kExitOk;
      });
  add.command(
      "requeue", "run a task or a frame again, with every task that used it (a done shot runs again)",
      [](CLI::App* c, ClientArguments& a) {
        c->add_option("id", a.shotId, "shot id")->required();
        auto* task = c->add_option("--task", a.taskId, "the task id (as the shot's events and the dashboard name it)");
        task->excludes(c->add_option("--frame", a.frame, "the frame number"));
      },
      [](farm::FarmClient& client, const ClientArguments& a) {
        if (!a.taskId && !a.frame) throw std::invalid_argument("requeue: give --task ID or --frame N");
        const auto summary =
            a.taskId ? client.requeueTask(a.shotId, *a.taskId) : client.requeueFrame(a.shotId, *a.frame);
        std::printf("%s\n", describeShot(summary).c_str());
        return kExitOk;
      });
  add.command(
      "blocklist", "list the workers kept away from a shot (every shot without an id), or --clear them",
      [](CLI::App* c, ClientArguments& a) {
        c->add_option("id", a.shotId, "shot id");
        c->add_flag("--clear", a.clear, "let the shot's blocklisted workers (or --worker W) lease its tasks again");
        c->add_option("--worker", a.workerId, "with --clear: only this worker id");
      },
      [](farm::FarmClient& client, const ClientArguments& a) {
        if (a.clear && a.shotId == 0) throw std::invalid_argument("--clear needs a shot id");
        const auto entries = a.clear ? client.clearBlocklist(a.shotId, a.workerId) : client.blocklist(a.shotId);
        for (const auto& e : entries)
          std::printf("shot %lld: worker %lld %s, %d failures\n", static_cast<long long>(e.shot_id()),
                      static_cast<long long>(e.worker_id()), e.worker_name().c_str(), e.failures());
        if (entries.empty()) std::printf("no worker is blocklisted\n");
        return kExitOk;
      });
  add.command(
      "workers", "list the workers the scheduler knows", [](CLI::App*, ClientArguments&) {},
      [](farm::FarmClient& client, const ClientArguments&) {
        for (const auto& w : client.workers())
          std::printf("%lld %s: %d/%d slots busy, seen %.1f s ago\n", static_cast<long long>(w.id()), w.name().c_str(),
                      w.busy(), w.slots(), w.seconds_since_seen());
        return kExitOk;
      });
}

}  // namespace

std::vector<Command> addClientCommands(CLI::App& app) {
  ClientCommands commands(app);
  addShotCommands(commands);
  addControlCommands(commands);
  return std::move(commands).commands();
}

}  // namespace pathfarm
