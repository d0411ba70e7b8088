// `pathfarm local SHOT.json --workers N --out DIR`: the embedded farm. Starts a
// scheduler and N worker processes, submits the shot, watches it, fetches the frames
// into DIR and stops everything. A finished shot keeps its frames, its report and the
// farm's logs; the intermediate chunks, the workers' caches and the database go, unless
// --keep-farm asks to keep them (a shot that did not finish keeps them, to be looked into).
// With --http the dashboard serves while the shot runs (docs/dashboard.md). References are
// taken from and kept in the shot's reference cache (cli/reference_cache_options.h).
// --on-done and --on-failed run a command when the shot ends (client/shot_hooks.h).
#include <spdlog/spdlog.h>

#include <memory>
#include <optional>

#include "cli/command.h"
#include "cli/reference_cache_options.h"
#include "cli/shot_progress.h"
#include "cli/frame_name_options.h"
#include "cli/shot_hook_options.h"
#include "cli/shot_key_options.h"
#include "cli/shot_size_options.h"
#include "cli/usage_parsing.h"
#include "renderer/scene/json_node.h"
#include "client/local_farm.h"
#include "client/shot_preparation.h"
#include "client/shot_source.h"
#include "scheduler/shot_report.h"

namespace pathfarm {
namespace {

struct LocalArguments {
  std::string shotFile;
  ShotKeyArguments keys;
  farm::ShotHooks hooks;
  std::string frameNames;
  std::string out;
  int workers = 2;
  int threads = 0;
  bool keepFarm = false;
  std::string referenceCache;
  std::string http;
  farm::ShotLimits limits;
  farm::FarmSettings farm;
};

uintmax_t folderBytes(const std::filesystem::path& folder) {
  uintmax_t bytes = 0;
  std::error_code error;
  for (auto it = std::filesystem::recursive_directory_iterator(folder, error);
       !error && it != std::filesystem::recursive_directory_iterator(); it.increment(error))
    if (it->is_regular_file(error)) bytes += it->file_size(error);
  return bytes;
}

// Everything of the embedded farm but its logs.
void removeIntermediateData(const std::filesystem::path& farmFolder) {
  const uintmax_t before = folderBytes(farmFolder);
  for (const auto& entry : std::filesystem::directory_iterator(farmFolder))
    if (entry.path().filename() != "logs") std::filesystem::remove_all(entry.path());
  spdlog::info("removed {:.1f} MB of intermediate chunks, worker caches and the farm database from {} "
               "(--keep-farm keeps them)", static_cast<double>(before - folderBytes(farmFolder)) / 1e6,
               farmFolder.string());
}

int runLocal(const LocalArguments& arguments) {
  std::optional<farm::ShotFile> file;
  std::optional<farm::FrameNames> names;
  farm::ShotSpec spec;
  try {
    names = frameNamesOf(arguments.frameNames);
    file = farm::loadShotSource(arguments.shotFile, shotKeysOf(arguments.keys));
    spec = farm::preparedShot(*file);
  } catch (const SceneError& e) {
    spdlog::error("{}", e.what());
    return kExitBadInput;
  } catch (const UsageError& e) {
    spdlog::error("{}", e.what());
    return kExitBadInput;
  }
  const std::filesystem::path out(arguments.out.empty() ? spec.output() : arguments.out);
  try {
    farm::LocalFarm farm({out / "farm", arguments.workers, arguments.threads, farm::currentExecutable(),
                          arguments.farm, arguments.limits, arguments.http});
    farm::FarmClient client = farm.client();
    spec = withChosenPipeline(client, *file, spec, out / "probe");
    const std::optional<farm::ReferenceCache> references = referenceCacheOf(*file, arguments.referenceCache);
    file.reset();  // its scene, no longer needed while the farm renders
    if (references) attachCachedReferences(*references, client, spec);
    const int64_t id = client.submit(spec);
    spdlog::info("shot {} submitted: {} frames {}..{} at {}x{}, {} spp, {}-pixel tiles", id, spec.name(),
                 spec.frame_start(), spec.frame_end(), spec.width(), spec.height(), spec.spp(), spec.tile());
    farm::ShotSummary summary;
    {
      ShotProgress progress;
      summary = client.watch(id, [&](const farm::ShotSummary& s) { progress.update(s); });
    }
    auto files = client.fetch(id, out);
    if (names) files = farm::renameFrames(files, out, *names, spec.name(), id);
    const farm::ShotReport report = client.report(id);
    if (references && summary.state() == farm::SHOT_DONE) keepRenderedReferences(*references, client, id, spec);
    farm.stop();
    farm::writeReportFiles(report, out);
    spdlog::info("{}", describeShot(summary));
    spdlog::info("{} EXR frames in {}; report.md and report.json there too", files.size(), out.string());
    spdlog::info("relative cost {:.3f} (resolution gain {:.2f}, overhead {:.2f}), re-render rate {:.1f}%",
                 report.relative_cost(), report.resolution_gain(), report.overhead(), 100 * report.rerender_rate());
    if (const std::string prediction = farm::predictionSummary(report); !prediction.empty())
      spdlog::info("{}", prediction);
    if (report.cost_at_equal_error() >= 1) {
      spdlog::warn("{}", report.verdict());
    } else if (!report.verdict().empty()) {
      spdlog::info("{}", report.verdict());
    }
    const bool done = summary.state() == farm::SHOT_DONE;
    if (done && !arguments.keepFarm) removeIntermediateData(out / "farm");
    farm::runShotHook(arguments.hooks, outcomeOf(spec, summary, out.string()));
    return done ? kExitOk : kExitFailure;
  } catch (const SceneError& e) {  // the shot file does not read as one of auto's candidates
    spdlog::error("{}", e.what());
    return kExitBadInput;
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return kExitFailure;
  }
}

}  // namespace

std::vector<Command> addLocalCommand(CLI::App& app) {
  auto arguments = std::make_shared<LocalArguments>();
  CLI::App* local = app.add_subcommand("local", "render a shot on a farm of local worker processes");
  local->add_option("shot", arguments->shotFile,
                    "shot file (JSON, see docs/shot-format.md), or a scene file (glTF, JSON scene) to render as a shot")
      ->required();
  addShotKeyOptions(local, arguments->keys);
  addShotHookOptions(local, arguments->hooks);
  addFrameNamesOption(local, arguments->frameNames);
  local->add_option("--workers", arguments->workers, "worker processes")->check(CLI::Range(1, 256))->capture_default_str();
  local->add_option("--threads", arguments->threads, "render threads per worker (0: the cores shared out)");
  local->add_option("--out", arguments->out, "output folder (default: the shot's output)");
  local->add_option("--http", arguments->http,
                    "HOST:PORT (loopback; port 0: any) serving the dashboard while the shot runs; its link, "
                    "with the farm's token, is logged");
  addShotSizeOptions(local, arguments->limits, arguments->farm);
  addReferenceCacheOption(local, arguments->referenceCache);
  local->add_flag("--keep-farm", arguments->keepFarm,
                  "keep the farm's database, chunks and worker caches after the shot is done (default: only its logs)");
  return {{local, [arguments] { return runLocal(*arguments); }}};
}

}  // namespace pathfarm
