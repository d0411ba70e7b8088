#include "cli/command.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "cli/progress_bar.h"
#include "image/exr_io.h"
#include "image/png_preview.h"
#include "renderer/bidirectional/bdpt_frame_renderer.h"
#include "renderer/decomposition/auto_decomposition.h"
#include "renderer/integrators/frame_renderer.h"
#include "renderer/integrators/gradient_frame_renderer.h"
#include "renderer/metropolis/metropolis_renderer.h"
#include "renderer/scene/scene_loader.h"

namespace pathfarm {
namespace {

struct RenderOptions {
  std::string scene;
  std::string frames;
  std::string resolution;
  std::optional<int> spp, maxDepth;
  std::string out;
  int threads = 0;
  int tileSize = 32;
  bool png = false;
  float exposure = 1;
  std::string decompose = "none";
  std::string integrator = "pt";
  int batches = 1;
  bool noMotion = false;
  int mixedEvery = GradientSettings{}.mixedEvery;
  // Metropolis integrators (docs/metropolis.md).
  int window = 0;  // frames per window; 0: the whole range
  std::optional<double> mutationsPerPixel;
  std::optional<int> chains, chainsPerBlock;
  std::optional<uint64_t> bootstrap;
  std::optional<double> delta;
  bool tuneDelta = false;
};

bool isMetropolis(const std::string& integrator) { return integrator == "pssmlt" || integrator == "mlt" || integrator == "tmlt"; }

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "A:B" (inclusive) or "A".
std::pair<int64_t, int64_t> parseFrames(const std::string& text) {
  const auto colon = text.find(':');
  try {
    size_t used = 0;
    const int64_t first = std::stoll(text.substr(0, colon), &used);
    if (used != (colon == std::string::npos ? text.size() : colon)) throw std::invalid_argument(text);
    int64_t last = first;
    if (colon != std::string::npos) {
      const std::string tail = text.substr(colon + 1);
      last = std::stoll(tail, &used);
      if (used != tail.size()) throw std::invalid_argument(text);
    }
    if (first < 0 || last < first) throw std::invalid_argument(text);
    return {first, last};
  } catch (const std::logic_error&) {
    throw UsageError("--frames \"" + text + "\": expected FIRST:LAST with 0 <= FIRST <= LAST");
  }
}

// "WxH".
std::pair<int, int> parseResolution(const std::string& text) {
  int width = 0, height = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%dx%d%c", &width, &height, &tail) != 2 || width < 1 || height < 1 ||
      width > 16384 || height > 16384)
    throw UsageError("--res \"" + text + "\": expected WIDTHxHEIGHT, each from 1 to 16384");
  return {width, height};
}

std::string frameName(int64_t frame, const char* extension) {
  char name[64];
  std::snprintf(name, sizeof name, "frame_%04lld.%s", static_cast<long long>(frame), extension);
  return name;
}

void writeFrame(const RenderOptions& options, int64_t frame, const FrameImage& image) {
  const std::filesystem::path out(options.out);
  writeExr(out / frameName(frame, "exr"), image);
  if (options.png) writePngPreview(out / frameName(frame, "png"), image, options.exposure);
}

MetropolisSettings metropolisSettingsOf(const RenderOptions& options, const Scene& scene, const RenderSettings& render) {
  MetropolisSettings settings = MetropolisSettings::defaultsOf(scene);
  settings.method = parseMetropolisMethod(options.integrator);
  settings.width = render.width;
  settings.height = render.height;
  settings.maxDepth = render.maxDepth;
  settings.threads = options.threads;
  if (options.mutationsPerPixel) settings.mutationsPerPixel = *options.mutationsPerPixel;
  if (options.chains) settings.chains = *options.chains;
  if (options.chainsPerBlock) settings.chainsPerBlock = *options.chainsPerBlock;
  if (options.bootstrap) settings.bootstrapSamples = *options.bootstrap;
  if (options.delta) settings.temporalDelta = *options.delta;
  settings.tuneDelta = options.tuneDelta;
  return settings;
}

// Frames first..last in windows of options.window frames, one Metropolis render each.
void renderMetropolisWindows(const RenderOptions& options, const Scene& scene, const MetropolisSettings& settings,
                             std::pair<int64_t, int64_t> frames) {
  const MetropolisRenderer renderer(scene, settings);
  // mlt is frame by frame; the others default to one window over the whole range.
  const int64_t windowLength = options.window > 0                          ? options.window
                               : settings.method == MetropolisMethod::PathSpace ? 1
                                                                                : frames.second - frames.first + 1;
  for (int64_t first = frames.first; first <= frames.second; first += windowLength) {
    const FrameWindow window{first, static_cast<int>(std::min(windowLength, frames.second - first + 1))};
    std::vector<FrameImage> images;
    const auto started = std::chrono::steady_clock::now();
    {
      ProgressBar bar("frames " + std::to_string(window.first) + ".." + std::to_string(window.end() - 1));
      images = renderer.render(window, [&](size_t done, size_t total) { bar.update(done, total); });
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    const auto& attributes = images.front().attributes();
    std::string acceptance;
    for (const auto& [key, value] : attributes)
      if (key.starts_with("pathfarm.mlt.acceptance.")) acceptance += " " + key.substr(24) + " " + value;
    spdlog::info("frames {}..{}: {} mutations in {:.2f} s, acceptance{}{}", window.first, window.end() - 1,
                 attributes.at("pathfarm.mlt.mutations"), seconds, acceptance,
                 attributes.count("pathfarm.mlt.final_delta") ? ", final D " + attributes.at("pathfarm.mlt.final_delta")
                                                              : std::string());
    for (int f = 0; f < window.count; ++f) writeFrame(options, window.first + f, images[static_cast<size_t>(f)]);
  }
}

int runRender(const RenderOptions& options) {
  Scene scene;
  RenderSettings settings;
  std::pair<int64_t, int64_t> frames;
  try {
    scene = loadScene(options.scene);
    settings = RenderSettings::defaultsOf(scene);
    frames = options.frames.empty() ? std::pair<int64_t, int64_t>{scene.defaults.frameStart, scene.defaults.frameEnd}
                                    : parseFrames(options.frames);
    if (!options.resolution.empty()) std::tie(settings.width, settings.height) = parseResolution(options.resolution);
  } catch (const SceneError& e) {
    spdlog::error("{}", e.what());
    return kExitBadInput;
  } catch (const UsageError& e) {
    spdlog::error("{}", e.what());
    return kExitBadInput;
  }
  try {
    settings.decomposition = decompositionFor(scene, options.decompose);
  } catch (const std::invalid_argument& e) {
    spdlog::error("--decompose: {}", e.what());
    return kExitBadInput;
  }
  const bool metropolis = isMetropolis(options.integrator);
  const bool gradient = options.integrator == "gpt" || options.integrator == "tgpt";
  const bool bidirectional = options.integrator == "bdpt";
  if (options.integrator != "pt" && options.decompose != "none") {
    spdlog::error("--integrator {} renders no path-space components: leave out --decompose", options.integrator);
    return kExitBadInput;
  }
  if (!gradient && (options.batches != 1 || options.noMotion)) {
    spdlog::error("--batches and --no-motion apply to --integrator gpt and tgpt only");
    return kExitBadInput;
  }
  if (options.integrator != "tgpt" && options.mixedEvery != GradientSettings{}.mixedEvery) {
    spdlog::error("--mixed-every applies to --integrator tgpt only");
    return kExitBadInput;
  }
  const bool metropolisOptions = options.window != 0 || options.mutationsPerPixel || options.chains ||
                                 options.chainsPerBlock || options.bootstrap || options.delta || options.tuneDelta;
  if (!metropolis && metropolisOptions) {
    spdlog::error("--window, --mutations-per-pixel, --chains, --chains-per-block, --bootstrap, --delta and "
                  "--tune-delta apply to --integrator pssmlt, mlt and tmlt only");
    return kExitBadInput;
  }
  if (options.integrator == "mlt" && options.window > 1) {
    spdlog::error("--integrator mlt renders frame by frame (windows of one frame); tmlt and pssmlt take --window");
    return kExitBadInput;
  }
  if (metropolis && options.spp) {
    spdlog::error("--integrator {} takes --mutations-per-pixel (and --bootstrap), not --spp", options.integrator);
    return kExitBadInput;
  }
  const GradientSettings gradientSettings{options.integrator == "tgpt", !options.noMotion, options.batches,
                                          options.mixedEvery};
  if (options.spp) settings.spp = *options.spp;
  if (options.maxDepth) settings.maxDepth = *options.maxDepth;
  settings.threads = options.threads;
  settings.tileSize = options.tileSize;
  MetropolisSettings metropolisSettings;
  if (metropolis) {
    try {
      metropolisSettings = metropolisSettingsOf(options, scene, settings);
      metropolisSettings.validate();
      WindowTime::of(scene, {frames.first, 1});  // a zero-length shutter is bad input, refused before any work
    } catch (const std::invalid_argument& e) {
      spdlog::error("{}", e.what());
      return kExitBadInput;
    }
  }

  const std::filesystem::path out(options.out);
  std::error_code error;
  std::filesystem::create_directories(out, error);
  if (error) {
    spdlog::error("{}: cannot create the output folder: {}", out.string(), error.message());
    return kExitFailure;
  }
  if (metropolis) {
    spdlog::info("rendering {} frames {}..{} at {}x{} with {}, {} mutations per pixel, {} chains, max depth {}",
                 options.scene, frames.first, frames.second, settings.width, settings.height, options.integrator,
                 metropolisSettings.mutationsPerPixel, metropolisSettings.chains, settings.maxDepth);
    try {
      renderMetropolisWindows(options, scene, metropolisSettings, frames);
    } catch (const std::exception& e) {
      spdlog::error("{}", e.what());
      return kExitFailure;
    }
    spdlog::info("EXR frames{} in {}", options.png ? " and PNG previews" : "", out.string());
    return kExitOk;
  }
  spdlog::info("rendering {} frames {}..{} at {}x{}, {} spp, max depth {}", options.scene, frames.first,
               frames.second, settings.width, settings.height, settings.spp, settings.maxDepth);
  try {
    std::optional<FrameRenderer> renderer;
    std::optional<GradientFrameRenderer> gradientRenderer;
    std::optional<BdptFrameRenderer> bidirectionalRenderer;
    if (gradient)
      gradientRenderer.emplace(scene, settings, gradientSettings);
    else if (bidirectional)
      bidirectionalRenderer.emplace(scene, settings);
    else
      renderer.emplace(scene, settings);
    for (int64_t frame = frames.first; frame <= frames.second; ++frame) {
      RenderStats stats;
      FrameImage image;
      {
        ProgressBar bar("frame " + std::to_string(frame));
        const ProgressCallback update = [&](size_t done, size_t total) { bar.update(done, total); };
        image = gradient        ? gradientRenderer->render(frame, update, &stats)
                : bidirectional ? bidirectionalRenderer->render(frame, update, &stats)
                                : renderer->render(frame, update, &stats);
      }
      const auto exr = out / frameName(frame, "exr");
      writeFrame(options, frame, image);
      spdlog::info("frame {}: {:.2f} s, {:.2f} M samples/s, {:.2f} M rays/s -> {}", frame, stats.seconds,
                   stats.samples / stats.seconds * 1e-6,
                   (stats.rays.closestHit + stats.rays.shadow) / stats.seconds * 1e-6, exr.string());
      if (stats.nonFiniteSamples > 0)
        spdlog::warn("frame {}: dropped {} non-finite samples of {}", frame, stats.nonFiniteSamples, stats.samples);
    }
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return kExitFailure;
  }
  spdlog::info("EXR frames{} in {}", options.png ? " and PNG previews" : "", out.string());
  return kExitOk;
}

}  // namespace

std::vector<Command> addRenderCommand(CLI::App& app) {
  auto options = std::make_shared<RenderOptions>();
  CLI::App* render = app.add_subcommand("render", "render frames of a scene to multi-layer EXR files");
  render->add_option("scene", options->scene, "scene file (JSON, see docs/scene-format.md)")->required();
  render->add_option("--frames", options->frames, "inclusive frame range A:B, or A (default: the scene's)");
  render->add_option("--spp", options->spp, "samples per pixel (default: the scene's)")->check(CLI::Range(1, 1 << 20));
  render->add_option("--res", options->resolution, "resolution WxH (default: the scene's)");
  render->add_option("--max-depth", options->maxDepth, "maximum scattering events per path")
      ->check(CLI::Range(0, 1024));
  render->add_option("--out", options->out, "output folder for frame_NNNN.exr")->required();
  render->add_option("--threads", options->threads, "worker threads (0: every core)")->check(CLI::Range(0, 1024));
  render->add_option("--tile", options->tileSize, "tile size in pixels")->check(CLI::Range(1, 4096));
  render->add_flag("--png", options->png, "also write frame_NNNN.png previews (sRGB)");
  render->add_option("--decompose", options->decompose,
                     "path-space components: none, default, auto, or \"name=EXPR,...\" (docs/decomposition.md)")
      ->capture_default_str();
  render->add_option("--integrator", options->integrator,
                     "pt (path tracing), bdpt (bidirectional, docs/metropolis.md), gpt (gradient-domain) or tgpt "
                     "(temporal gradient-domain); gpt and tgpt frames are reconstructed by `pathfarm poisson` "
                     "(docs/gradient-domain.md); pssmlt (primary-sample-space Metropolis over windows of frames, "
                     "docs/metropolis.md)")
      ->check(CLI::IsMember({"pt", "bdpt", "gpt", "tgpt", "pssmlt", "mlt", "tmlt"}))
      ->capture_default_str();
  render->add_option("--batches", options->batches,
                     "gpt/tgpt: sampling batches; after a uniform first batch the others follow the relative variance "
                     "of the differences")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  render->add_flag("--no-motion", options->noMotion, "tgpt: temporal offsets keep their pixel instead of following the motion");
  render->add_option("--mixed-every", options->mixedEvery,
                     "tgpt: the temporal offset traces its spatial offsets (the mixed differences) on one sample in N")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  render->add_option("--window", options->window,
                     "pssmlt/tmlt: frames per window of Markov chains (default: the whole frame range; mlt: 1)")
      ->check(CLI::Range(1, 100000));
  render->add_option("--mutations-per-pixel", options->mutationsPerPixel,
                     "pssmlt/mlt/tmlt: mutations per pixel and frame (default 64)")
      ->check(CLI::Range(1e-3, 1e9));
  render->add_option("--chains", options->chains, "pssmlt/mlt/tmlt: Markov chains per window (default 64)")
      ->check(CLI::Range(1, 1 << 24));
  render->add_option("--chains-per-block", options->chainsPerBlock,
                     "pssmlt/mlt/tmlt: chains per block, the farm's unit of work (default 16)")
      ->check(CLI::Range(1, 1 << 24));
  render->add_option("--bootstrap", options->bootstrap,
                     "pssmlt/mlt/tmlt: bootstrap samples for the normalization and the chain seeds (default 10000)")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1} << 30));
  render->add_option("--delta", options->delta,
                     "pssmlt/mlt/tmlt: reach D of the temporal mutation, in frames (default 1)")
      ->check(CLI::Range(1e-3, 1e6));
  render->add_flag("--tune-delta", options->tuneDelta,
                   "pssmlt/mlt/tmlt: tune D towards a 23 % temporal acceptance during the first tenth of each chain");
  render->add_option("--exposure", options->exposure, "exposure multiplier of the PNG previews")
      ->check(CLI::Range(1e-6, 1e6));
  return {{render, [options] { return runRender(*options); }}};
}

}  // namespace pathfarm
