#include "cli/command.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>

#include "cli/progress_bar.h"
#include "cli/usage_parsing.h"
#include "image/exr_io.h"
#include "image/png_preview.h"
#include "renderer/metropolis/metropolis_renderer.h"
#include "renderer/scene/scene_loader.h"
#include "renderer/setup/auto_decomposition.h"
#include "renderer/setup/integrator_factory.h"

namespace pathfarm {
namespace {

struct RenderOptions {
  std::string scene;
  std::string frames;
  std::string resolution;
  std::optional<int> spp, maxDepth;
  std::optional<uint64_t> seed;  // instead of the scene's
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

// What the options ask to render: the scene, its frames and the settings.
struct RenderJob {
  Scene scene;
  RenderSettings settings;
  std::pair<int64_t, int64_t> frames;
};

// Throws SceneError, UsageError, or std::invalid_argument for a decomposition.
RenderJob renderJobOf(const RenderOptions& options) {
  RenderJob job;
  job.scene = loadScene(options.scene);
  if (options.seed) job.scene.seed = *options.seed;
  job.settings = RenderSettings::defaultsOf(job.scene);
  job.frames = options.frames.empty()
                   ? std::pair<int64_t, int64_t>{job.scene.defaults.frameStart, job.scene.defaults.frameEnd}
                   : parseFrames(options.frames);
  if (!options.resolution.empty()) std::tie(job.settings.width, job.settings.height) = parseResolution(options.resolution);
  try {
    job.settings.decomposition = decompositionFor(job.scene, options.decompose);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--decompose: ") + e.what());
  }
  if (options.spp) job.settings.spp = *options.spp;
  if (options.maxDepth) job.settings.maxDepth = *options.maxDepth;
  job.settings.threads = options.threads;
  job.settings.tileSize = options.tileSize;
  return job;
}

// Options that only some integrators take, refused for the others with UsageError.
void checkIntegratorOptions(const RenderOptions& options, const IntegratorTraits& integrator) {
  const std::string name(integrator.name);
  if (!integrator.decomposes && options.decompose != "none")
    throw UsageError("--integrator " + name + " renders no path-space components: leave out --decompose");
  if (!integrator.gradient && (options.batches != 1 || options.noMotion))
    throw UsageError("--batches and --no-motion apply to --integrator gpt and tgpt only");
  if (!(integrator.gradient && integrator.temporal) && options.mixedEvery != GradientSettings{}.mixedEvery)
    throw UsageError("--mixed-every applies to --integrator tgpt only");
  const bool metropolisOptions = options.window != 0 || options.mutationsPerPixel || options.chains ||
                                 options.chainsPerBlock || options.bootstrap || options.delta || options.tuneDelta;
  if (!integrator.rendersWindows && metropolisOptions)
    throw UsageError("--window, --mutations-per-pixel, --chains, --chains-per-block, --bootstrap, --delta and "
                     "--tune-delta apply to --integrator pssmlt, mlt and tmlt only");
  if (integrator.rendersWindows && options.spp)
    throw UsageError("--integrator " + name + " takes --mutations-per-pixel (and --bootstrap), not --spp");
}

// The Metropolis integrators' settings; throws std::invalid_argument for bad ones.
MetropolisSettings checkedMetropolisSettings(const RenderOptions& options, const RenderJob& job) {
  MetropolisSettings settings = metropolisSettingsOf(options, job.scene, job.settings);
  if (settings.method == MetropolisMethod::PathSpace && options.window > 1)
    throw std::invalid_argument("--integrator mlt renders frame by frame (windows of one frame); tmlt and pssmlt take "
                                "--window");
  settings.validate();
  WindowTime::of(job.scene, {job.frames.first, 1});  // a zero-length shutter is bad input, refused before any work
  return settings;
}

void renderFrames(const RenderOptions& options, const RenderJob& job) {
  const GradientSettings gradient{false, !options.noMotion, options.batches, options.mixedEvery};
  const std::unique_ptr<FrameIntegrator> integrator =
      makeFrameIntegrator(options.integrator, job.scene, job.settings, gradient);
  const std::filesystem::path out(options.out);
  for (int64_t frame = job.frames.first; frame <= job.frames.second; ++frame) {
    RenderStats stats;
    FrameImage image;
    {
      ProgressBar bar("frame " + std::to_string(frame));
      image = integrator->render(frame, [&](size_t done, size_t total) { bar.update(done, total); }, &stats);
    }
    writeFrame(options, frame, image);
    spdlog::info("frame {}: {:.2f} s, {:.2f} M samples/s, {:.2f} M rays/s -> {}", frame, stats.seconds,
                 stats.samples / stats.seconds * 1e-6, (stats.rays.closestHit + stats.rays.shadow) / stats.seconds * 1e-6,
                 (out / frameName(frame, "exr")).string());
    if (stats.nonFiniteSamples > 0)
      spdlog::warn("frame {}: dropped {} non-finite samples of {}", frame, stats.nonFiniteSamples, stats.samples);
  }
}

// Bad input: said, and exit status 2.
int refused(const std::exception& e) {
  spdlog::error("{}", e.what());
  return kExitBadInput;
}

int runRender(const RenderOptions& options) {
  RenderJob job;
  MetropolisSettings metropolis;
  const IntegratorTraits& integrator = integratorNamed(options.integrator);  // CLI11 checked the name
  try {
    job = renderJobOf(options);
    checkIntegratorOptions(options, integrator);
    if (integrator.rendersWindows) metropolis = checkedMetropolisSettings(options, job);
  } catch (const SceneError& e) {
    return refused(e);
  } catch (const UsageError& e) {
    return refused(e);
  } catch (const std::invalid_argument& e) {  // settings the integrator refuses
    return refused(e);
  }
  const std::filesystem::path out(options.out);
  std::error_code error;
  std::filesystem::create_directories(out, error);
  if (error) {
    spdlog::error("{}: cannot create the output folder: {}", out.string(), error.message());
    return kExitFailure;
  }
  try {
    if (integrator.rendersWindows) {
      spdlog::info("rendering {} frames {}..{} at {}x{} with {}, {} mutations per pixel, {} chains, max depth {}",
                   options.scene, job.frames.first, job.frames.second, job.settings.width, job.settings.height,
                   options.integrator, metropolis.mutationsPerPixel, metropolis.chains, job.settings.maxDepth);
      renderMetropolisWindows(options, job.scene, metropolis, job.frames);
    } else {
      spdlog::info("rendering {} frames {}..{} at {}x{}, {} spp, max depth {}", options.scene, job.frames.first,
                   job.frames.second, job.settings.width, job.settings.height, job.settings.spp, job.settings.maxDepth);
      renderFrames(options, job);
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
  render->add_option("--seed", options->seed,
                     "mixed into every sample stream instead of the scene's seed: an independent render of the scene");
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
      ->check(CLI::IsMember(integratorNames()))
      ->capture_default_str();
  render->add_option("--batches", options->batches,
                     "gpt/tgpt: sampling batches; after a uniform first batch the others follow the relative variance "
                     "of the differences")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  render->add_flag("--no-motion", options->noMotion, "tgpt: temporal offsets keep their pixel instead of following the motion");
  render->add_option("--mixed-every", options->mixedEvery,
                     "tgpt: the temporal offset traces its spatial offsets (the mixed differences) on one sample in N, "
                     "lowered to leave every pixel at least " + std::to_string(kMinMixedSamples))
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
                     "pssmlt/mlt/tmlt: bootstrap samples per window for the normalization and the chain seeds (default: one per 256 "
                     "mutations of the window, at least 10000)")
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
