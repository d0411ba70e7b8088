#include "renderer/integrators/gradient_frame_renderer.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <stdexcept>

#include "renderer/accel/shot_geometry.h"
#include "renderer/gradient/adaptive_sampling.h"
#include "renderer/gradient/temporal_correspondence.h"
#include "renderer/integrators/gradient_estimates.h"
#include "renderer/integrators/gradient_path_tracer.h"
#include "renderer/integrators/sample_moments.h"
#include "renderer/integrators/shutter_buckets.h"

namespace pathfarm {

struct GradientFrameRenderer::Shot {
  EmbreeDevice device;
  ShotGeometry geometry;
  LightSampler lights;

  explicit Shot(const Scene& scene) : geometry(scene, device), lights(geometry) {}
};

namespace {

bool isFinite(const GradientSample& g) {
  Rgb total = g.direct + g.radiance;
  for (size_t k = 0; k < 4; ++k) total += g.base[k] + g.offset[k] + g.difference[k];
  return total.isFinite();
}

// The camera rays of one sample: through a pixel and through its neighbours, all with
// the sample's film jitter and lens point.
struct PrimaryRays {
  const Camera& camera;
  int width, height;
  Vec2f jitter, lens;

  Ray through(int px, int py, const Transform& cameraToWorld) const {
    return camera.generateRay({static_cast<float>(px) + jitter.x, static_cast<float>(py) + jitter.y}, lens,
                              cameraToWorld);
  }
  // The offset rays of gradient-domain path tracing; none towards a neighbour outside the image.
  std::array<std::optional<Ray>, 4> offsets(int cx, int cy, const Transform& cameraToWorld) const {
    std::array<std::optional<Ray>, 4> rays;
    for (size_t k = 0; k < 4; ++k) {
      const int nx = cx + kShiftDirections[k][0], ny = cy + kShiftDirections[k][1];
      if (nx >= 0 && ny >= 0 && nx < width && ny < height) rays[k] = through(nx, ny, cameraToWorld);
    }
    return rays;
  }
};

// A base sample of frame f and, where its pixel has a correspondence, its temporal offset.
struct TemporalPair {
  GradientSample base;
  std::optional<GradientSample> later;
};

// Draws the samples of frame f's pixels: the base path with its spatial offsets and, for
// the temporal offset, the same random numbers traced at frame f + 1.
struct PixelSampler {
  const Scene& scene;
  int64_t frame;
  const Camera& camera;
  const ShutterBuckets& shutter;       // frame's
  const ShutterBuckets* laterShutter;  // frame + 1's, with a temporal offset
  int width, height;
  const GradientPathTracer& tracer;
  const GradientPathTracer* nextTracer;  // null: no temporal offset
  const std::vector<int32_t>& correspondence;
  uint32_t mixedEvery;

  TemporalPair trace(int x, int y, uint32_t sampleIndex, const StratifiedPixel& pattern, const PixelStreams& streams,
                     bool withMixed, SampleCounters& local) const {
    SampleStream stream = streams.stream(sampleIndex);
    // As in FrameRenderer: pixel position and time stratified, the time taken to its shutter
    // bucket's centre, the lens from the stream.
    const StratifiedSample stratified = pattern.sample(sampleIndex);
    const float time = ShutterBuckets::time(stratified.time);
    const PrimaryRays rays{camera, width, height, stratified.film, stream.next2D()};
    // The temporal offset replays the path's random numbers from here on.
    SampleStream replay = stream;
    // The base ray and its offsets share their time, and so their camera placement.
    const Transform& cameraNow = shutter.cameraToWorld(stratified.time);
    TemporalPair pair{
        tracer.trace(rays.through(x, y, cameraNow), rays.offsets(x, y, cameraNow), time, stream, local.rays),
        std::nullopt};
    ++local.samples;
    const size_t p = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
    if (nextTracer && correspondence[p] >= 0) {
      // The temporal offset: the same random numbers one frame later, through the
      // corresponding pixel, with its own spatial offsets for the mixed differences.
      const int tx = correspondence[p] % width, ty = correspondence[p] / width;
      const Transform& cameraLater = laterShutter->cameraToWorld(stratified.time);
      const auto laterOffsets = withMixed ? rays.offsets(tx, ty, cameraLater) : std::array<std::optional<Ray>, 4>{};
      pair.later = nextTracer->trace(rays.through(tx, ty, cameraLater), laterOffsets, time, replay, local.rays);
    }
    return pair;
  }

  // Adds `count` more samples to pixel (x, y)'s sums.
  void render(int x, int y, uint32_t count, GradientPixelSums& s, SampleCounters& local) const {
    const StratifiedPixel pattern(scene.seed, frame, x, y);
    const PixelStreams streams(scene.seed, frame, x, y);
    for (uint32_t i = 0; i < count; ++i) {
      const bool withMixed = (s.drawn + i) % mixedEvery == 0;
      const TemporalPair pair = trace(x, y, s.drawn + i, pattern, streams, withMixed, local);
      if (!isFinite(pair.base) || (pair.later && !isFinite(*pair.later))) {
        ++local.nonFinite;
        continue;
      }
      accumulate(pair, withMixed, s);
    }
    s.drawn += count;
  }

  static void accumulate(const TemporalPair& pair, bool withMixed, GradientPixelSums& s) {
    const GradientSample& g = pair.base;
    s.direct.add(g.direct);
    Rgb own;
    for (size_t k = 0; k < 4; ++k) {
      own += g.base[k] * 0.25f;
      s.offset[k].add(g.offset[k]);
      s.difference[k].add(g.difference[k]);
    }
    s.own.add(own);
    if (pair.later) s.temporal.add(pair.later->radiance - g.radiance);
    if (pair.later && withMixed) {
      for (size_t k = 0; k < 4; ++k) s.mixed[k].add(pair.later->difference[k] - g.difference[k]);
      ++s.mixedSamples;
    }
    ++s.samples;
  }
};

// A window of the frame cut into square tiles, numbered row by row.
struct TileGrid {
  PixelWindow window;
  int tile;
  int tilesX = (window.width() + tile - 1) / tile, tilesY = (window.height() + tile - 1) / tile;

  size_t count() const { return static_cast<size_t>(tilesX) * static_cast<size_t>(tilesY); }
};

// Reports tiles done over all batches.
class TileProgress {
 public:
  TileProgress(const ProgressCallback& callback, size_t total) : callback_(callback), total_(total) {}

  void tileDone() {
    const size_t done = ++done_;
    if (callback_) callback_(done, total_);
  }

 private:
  const ProgressCallback& callback_;
  size_t total_;
  std::atomic<size_t> done_{0};
};

// One batch: every pixel's `allocation` of samples (both per pixel of the window, row by
// row), the tiles in parallel.
void renderBatch(tbb::task_arena& arena, const TileGrid& grid, const PixelSampler& sampler,
                 const std::vector<uint32_t>& allocation, std::vector<GradientPixelSums>& sums,
                 tbb::enumerable_thread_specific<SampleCounters>& counters, TileProgress& progress) {
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, grid.count(), 1), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t index = r.begin(); index != r.end(); ++index) {
        SampleCounters& local = counters.local();
        const PixelWindow& w = grid.window;
        const int x0 = w.x0 + static_cast<int>(index % static_cast<size_t>(grid.tilesX)) * grid.tile;
        const int y0 = w.y0 + static_cast<int>(index / static_cast<size_t>(grid.tilesX)) * grid.tile;
        for (int y = y0; y < std::min(y0 + grid.tile, w.y1); ++y)
          for (int x = x0; x < std::min(x0 + grid.tile, w.x1); ++x) {
            const size_t p = static_cast<size_t>(y - w.y0) * static_cast<size_t>(w.width()) +
                             static_cast<size_t>(x - w.x0);
            sampler.render(x, y, allocation[p], sums[p], local);
          }
        progress.tileDone();
      }
    });
  });
}

}  // namespace

GradientFrameRenderer::GradientFrameRenderer(const Scene& scene, RenderSettings settings, GradientSettings gradient)
    : scene_(scene), settings_(settings), gradient_(gradient), shot_(std::make_unique<Shot>(scene)) {
  if (gradient_.batches < 1) throw std::invalid_argument("adaptive sampling needs at least one batch");
  if (gradient_.mixedEvery < 1) throw std::invalid_argument("mixed differences need at least one sample in every N");
}

GradientFrameRenderer::~GradientFrameRenderer() = default;

int GradientFrameRenderer::effectiveMixedEvery() const {
  const int firstBatch = settings_.spp / gradient_.batches;
  return std::clamp(firstBatch / kMinMixedSamples, 1, gradient_.mixedEvery);
}

// What every window of a frame shares: its placed geometry, the next frame's and the
// temporal correspondence (over the whole frame: a contested target goes to the nearest
// point, wherever the contenders are).
struct GradientFrameRenderer::FrameSetup {
  int64_t frame;
  std::unique_ptr<const FrameGeometry> geometry, nextGeometry;
  std::vector<int32_t> correspondence;  // empty without temporal offsets
};

std::shared_ptr<const GradientFrameRenderer::FrameSetup> GradientFrameRenderer::setupFor(int64_t frame,
                                                                                          tbb::task_arena& arena) const {
  const std::lock_guard lock(setupMutex_);
  if (lastSetup_ && lastSetup_->frame == frame) return lastSetup_;
  auto setup = std::make_shared<FrameSetup>();
  setup->frame = frame;
  setup->geometry = std::make_unique<const FrameGeometry>(shot_->geometry, frame);
  if (gradient_.temporal) {
    setup->nextGeometry = std::make_unique<const FrameGeometry>(shot_->geometry, frame + 1);
    const Camera camera(scene_.camera, settings_.width, settings_.height);
    arena.execute([&] {
      setup->correspondence = temporalCorrespondence(*setup->geometry, *setup->nextGeometry, camera, settings_.width,
                                                     settings_.height, gradient_.motionVectors);
    });
  }
  lastSetup_ = setup;
  return lastSetup_;
}

FrameImage GradientFrameRenderer::render(int64_t frame, const ProgressCallback& progress, RenderStats* stats) const {
  const FrameImage estimates = estimate(frame, {0, 0, settings_.width, settings_.height}, progress, stats);
  return gradientFrameFromEstimates({{&estimates, 0, 0}}, settings_.width, settings_.height);
}

FrameImage GradientFrameRenderer::renderWindow(int64_t frame, const PixelWindow& window,
                                               const ProgressCallback& progress, RenderStats* stats) const {
  if (window.x0 < 0 || window.y0 < 0 || window.x1 > settings_.width || window.y1 > settings_.height ||
      window.width() <= 0 || window.height() <= 0)
    throw std::invalid_argument("the pixel window lies outside the frame or is empty");
  if (gradient_.batches > 1 && (window.width() != settings_.width || window.height() != settings_.height))
    throw std::invalid_argument("adaptive batches spread samples over the whole frame: it cannot be rendered in windows");
  return estimate(frame, window, progress, stats);
}

FrameImage GradientFrameRenderer::estimate(int64_t frame, const PixelWindow& window, const ProgressCallback& progress,
                                           RenderStats* stats) const {
  const auto start = std::chrono::steady_clock::now();
  const int width = settings_.width, height = settings_.height;
  const size_t pixels = static_cast<size_t>(window.width()) * static_cast<size_t>(window.height());
  tbb::task_arena arena(settings_.threads > 0 ? settings_.threads : tbb::task_arena::automatic);
  const std::shared_ptr<const FrameSetup> setup = setupFor(frame, arena);
  const Camera camera(scene_.camera, width, height);
  const ShutterBuckets shutter(scene_, camera, frame);
  std::optional<ShutterBuckets> laterShutter;
  if (gradient_.temporal) laterShutter.emplace(scene_, camera, frame + 1);
  const PathTracerSettings tracerSettings{settings_.maxDepth};
  const GradientPathTracer tracer(*setup->geometry, shot_->lights, tracerSettings);
  std::optional<GradientPathTracer> nextTracer;
  if (gradient_.temporal) nextTracer.emplace(*setup->nextGeometry, shot_->lights, tracerSettings);
  std::vector<int32_t> targets;  // the window's pixels' correspondence
  if (gradient_.temporal) {
    targets.reserve(pixels);
    for (int y = window.y0; y < window.y1; ++y)
      for (int x = window.x0; x < window.x1; ++x)
        targets.push_back(setup->correspondence[static_cast<size_t>(y) * static_cast<size_t>(width) +
                                                static_cast<size_t>(x)]);
  }

  std::vector<GradientPixelSums> sums(pixels);
  const PixelSampler sampler{scene_,
                             frame,
                             camera,
                             shutter,
                             laterShutter ? &*laterShutter : nullptr,
                             width,
                             height,
                             tracer,
                             nextTracer ? &*nextTracer : nullptr,
                             setup->correspondence,
                             static_cast<uint32_t>(effectiveMixedEvery())};
  const TileGrid grid{window, settings_.tileSize};
  const int batches = gradient_.batches;
  TileProgress tileProgress(progress, grid.count() * static_cast<size_t>(batches));
  tbb::enumerable_thread_specific<SampleCounters> counters;
  std::vector<uint32_t> allocation(pixels, static_cast<uint32_t>(std::max(1, settings_.spp / batches)));
  for (int batch = 0; batch < batches; ++batch) {
    if (batch > 0) {
      // Only ever the whole frame (renderWindow).
      const uint64_t budget = static_cast<uint64_t>(settings_.spp) * pixels / static_cast<uint64_t>(batches);
      const FrameImage sofar = gradientEstimates(sums, width, height, targets, width);
      allocation = allocateSamples(samplingDensity(gradientRelativeVariance(sofar), width, height), budget);
    }
    renderBatch(arena, grid, sampler, allocation, sums, counters, tileProgress);
  }

  FrameImage estimates = gradientEstimates(sums, window.width(), window.height(), targets, width);
  const RenderStats total = totalOf(counters, start);
  writeRenderAttributes(estimates, scene_, frame, settings_, total);
  auto& attributes = estimates.attributes();
  attributes["pathfarm.integrator"] = gradient_.temporal ? "tgpt" : "gpt";
  attributes["pathfarm.adaptive_batches"] = std::to_string(batches);
  if (stats) *stats = total;
  return estimates;
}

}  // namespace pathfarm
