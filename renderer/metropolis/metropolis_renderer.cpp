#include "renderer/metropolis/metropolis_renderer.h"

#include <cmath>
#include <stdexcept>

#include "renderer/accel/shot_geometry.h"
#include "renderer/bidirectional/camera_importance.h"
#include "renderer/integrators/light_sampler.h"
#include "renderer/metropolis/path_space/path_space_target.h"
#include "renderer/metropolis/pssmlt/pssmlt_target.h"
#include "renderer/metropolis/window_scene.h"

namespace pathfarm {

std::string nameOf(MetropolisMethod method) {
  switch (method) {
    case MetropolisMethod::Pssmlt: return "pssmlt";
    case MetropolisMethod::PathSpace: return "mlt";
    case MetropolisMethod::Temporal: return "tmlt";
  }
  throw std::invalid_argument("unknown Metropolis method");
}

MetropolisMethod parseMetropolisMethod(const std::string& name) {
  for (MetropolisMethod m : {MetropolisMethod::Pssmlt, MetropolisMethod::PathSpace, MetropolisMethod::Temporal})
    if (nameOf(m) == name) return m;
  throw std::invalid_argument("unknown Metropolis method '" + name + "' (expected pssmlt, mlt or tmlt)");
}

MetropolisSettings MetropolisSettings::defaultsOf(const Scene& scene) {
  MetropolisSettings settings;
  settings.width = scene.defaults.width;
  settings.height = scene.defaults.height;
  settings.maxDepth = scene.defaults.maxDepth;
  return settings;
}

void MetropolisSettings::validate() const {
  chainSettings(0).validate();
  if (maxDepth < 0) throw std::invalid_argument("the maximum depth must not be negative");
  if (!(largeStepProbability >= 0 && largeStepProbability <= 1))
    throw std::invalid_argument("the large step probability must lie in [0, 1]");
  if (!(temporalStepProbability >= 0 && temporalStepProbability <= 1))
    throw std::invalid_argument("the temporal step probability must lie in [0, 1]");
}

ChainSettings MetropolisSettings::chainSettings(uint64_t sceneSeed) const {
  ChainSettings chain;
  chain.sceneSeed = sceneSeed;
  chain.width = width;
  chain.height = height;
  chain.mutationsPerPixel = mutationsPerPixel;
  chain.bootstrapSamples = bootstrapSamples;
  chain.chains = chains;
  chain.chainsPerBlock = chainsPerBlock;
  chain.temporalDelta = temporalDelta;
  chain.tuneDelta = tuneDelta;
  chain.targetTemporalAcceptance = targetTemporalAcceptance;
  chain.threads = threads;
  return chain;
}

struct MetropolisRenderer::Shot {
  EmbreeDevice device;
  ShotGeometry geometry;
  LightSampler lights;
  CameraImportance camera;

  Shot(const Scene& scene, const MetropolisSettings& settings)
      : geometry(scene, device), lights(geometry), camera(scene.camera, settings.width, settings.height) {}
};

MetropolisRenderer::MetropolisRenderer(const Scene& scene, MetropolisSettings settings)
    : scene_(scene), settings_(settings) {
  settings_.validate();
  shot_ = std::make_unique<Shot>(scene, settings_);
}

MetropolisRenderer::~MetropolisRenderer() = default;

// The one place that knows which target each method's chains sample.
template <class Work>
auto MetropolisRenderer::withDriver(FrameWindow window, const Work& work) const {
  if (settings_.method == MetropolisMethod::PathSpace && window.count != 1)
    throw std::invalid_argument("mlt renders frame by frame: its windows are one frame (tmlt spans several)");
  const WindowTime time = WindowTime::of(scene_, window);
  const WindowGeometry geometry(shot_->geometry, window);
  const WindowScene windowScene{time, geometry, shot_->lights, shot_->camera, settings_.maxDepth};
  const ChainSettings chainSettings = settings_.chainSettings(scene_.seed);
  switch (settings_.method) {
    case MetropolisMethod::Pssmlt: {
      const PssmltTarget target(windowScene, settings_.largeStepProbability, settings_.temporalStepProbability);
      return work(ChainDriver(target, time, chainSettings));
    }
    case MetropolisMethod::PathSpace:
    case MetropolisMethod::Temporal: {
      const bool temporal = settings_.method == MetropolisMethod::Temporal;
      const PathSpaceTarget target(windowScene, temporal ? settings_.temporalStepProbability : 0);
      return work(ChainDriver(target, time, chainSettings));
    }
  }
  throw std::invalid_argument("unknown Metropolis method");
}

SeedPool MetropolisRenderer::seedPool(FrameWindow window) const {
  return withDriver(window, [](const auto& driver) { return driver.seedPool(); });
}

BlockResult MetropolisRenderer::runBlock(FrameWindow window, const SeedPool& pool, int block,
                                         const ChainProgress& progress) const {
  return withDriver(window, [&](const auto& driver) { return driver.runBlock(pool, block, progress); });
}

std::vector<FrameImage> MetropolisRenderer::merge(FrameWindow window, const SeedPool& pool,
                                                  std::vector<BlockResult> results) const {
  std::vector<FrameImage> frames = mergeBlocks(window, blocks(), std::move(results));
  for (int f = 0; f < window.count; ++f) {
    auto& a = frames[static_cast<size_t>(f)].attributes();
    a["pathfarm.scene"] = scene_.file.filename().string();
    a["pathfarm.frame"] = std::to_string(window.first + f);
    a["pathfarm.seed"] = std::to_string(scene_.seed);
    a["pathfarm.max_depth"] = std::to_string(settings_.maxDepth);
    a["pathfarm.integrator"] = nameOf(settings_.method);
    a["pathfarm.mlt.window"] = std::to_string(window.first) + ":" + std::to_string(window.end() - 1);
    a["pathfarm.mlt.mutations_per_pixel"] = std::to_string(settings_.mutationsPerPixel);
    a["pathfarm.mlt.normalization"] = std::to_string(pool.normalization);
  }
  return frames;
}

std::vector<FrameImage> MetropolisRenderer::render(FrameWindow window, const ChainProgress& progress) const {
  return withDriver(window, [&](const auto& driver) {
    const SeedPool pool = driver.seedPool();
    std::vector<BlockResult> results;
    for (int b = 0; b < blocks(); ++b) {
      results.push_back(driver.runBlock(pool, b));
      if (progress) progress(static_cast<size_t>(b + 1), static_cast<size_t>(blocks()));
    }
    return merge(window, pool, std::move(results));
  });
}

}  // namespace pathfarm
