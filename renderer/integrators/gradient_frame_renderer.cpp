#include "renderer/integrators/gradient_frame_renderer.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <array>
#include <atomic>
#include <chrono>
#include <limits>
#include <stdexcept>

#include "renderer/accel/shot_geometry.h"
#include "renderer/gradient/adaptive_sampling.h"
#include "renderer/gradient/temporal_correspondence.h"
#include "renderer/integrators/gradient_path_tracer.h"
#include "renderer/integrators/sample_moments.h"

namespace pathfarm {

struct GradientFrameRenderer::Shot {
  EmbreeDevice device;
  ShotGeometry geometry;
  LightSampler lights;

  explicit Shot(const Scene& scene) : geometry(scene, device), lights(geometry) {}
};

namespace {

struct PixelSums {
  uint32_t drawn = 0;             // sample indices used so far
  uint32_t samples = 0;           // finite samples accumulated
  uint32_t mixedSamples = 0;      // of which with the temporal offset's spatial offsets
  SampleMoments direct, own, temporal;  // own: the base's parts of its pixel, averaged over the 4 pairs
  std::array<SampleMoments, 4> offset, difference;
  std::array<SampleMoments, 4> mixed;  // the temporal offset's difference minus the base's, per direction
};

const char* const kChannels[3] = {"R", "G", "B"};

bool isFinite(const GradientSample& g) {
  Rgb total = g.direct + g.radiance;
  for (size_t k = 0; k < 4; ++k) total += g.base[k] + g.offset[k] + g.difference[k];
  return total.isFinite();
}

// The frame's layers from the per-pixel sums: each pair (p, p + d) is estimated from
// both pixels' samples, so this is where neighbours meet.
class FrameLayers {
 public:
  FrameLayers(const std::vector<PixelSums>& sums, int width, int height)
      : sums_(sums), width_(width), height_(height) {}

  size_t neighbour(size_t p, size_t k) const {
    const int x = static_cast<int>(p % static_cast<size_t>(width_)) + kShiftDirections[k][0];
    const int y = static_cast<int>(p / static_cast<size_t>(width_)) + kShiftDirections[k][1];
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return SIZE_MAX;
    return static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x);
  }
  // The primal estimate: for each of the 4 pairs the pixel is in, its own samples' part
  // plus the neighbour's offsets' part, averaged over the pairs.
  double primal(size_t p, size_t c, double* variance) const {
    const PixelSums& s = sums_[p];
    double value = s.own.mean(c, s.samples), v = s.own.varianceOfMean(c, s.samples);
    for (size_t k = 0; k < 4; ++k) {
      const size_t n = neighbour(p, k);
      if (n == SIZE_MAX) continue;
      const SampleMoments& m = sums_[n].offset[k ^ 1];
      value += 0.25 * m.mean(c, sums_[n].samples);
      v += 0.0625 * m.varianceOfMean(c, sums_[n].samples);
    }
    if (variance) *variance = v;
    return value;
  }
  // I(p + d) - I(p) for d = +x (k = 0) or +y (k = 2): p's forward differences minus the
  // neighbour's backward ones (which estimate I(p) - I(p + d)).
  double gradient(size_t p, size_t k, size_t c, double* variance) const {
    const size_t n = neighbour(p, k);
    if (n == SIZE_MAX) {
      if (variance) *variance = 0;
      return 0;
    }
    const SampleMoments& forward = sums_[p].difference[k];
    const SampleMoments& backward = sums_[n].difference[k ^ 1];
    if (variance)
      *variance = forward.varianceOfMean(c, sums_[p].samples) + backward.varianceOfMean(c, sums_[n].samples);
    return forward.mean(c, sums_[p].samples) - backward.mean(c, sums_[n].samples);
  }
  // What adaptive sampling follows: the spatial differences' variance relative to the
  // squared primal value (relMSE's denominator).
  std::vector<float> relativeVariance() const {
    std::vector<float> out(sums_.size());
    for (size_t p = 0; p < sums_.size(); ++p) {
      double total = 0;
      for (size_t c = 0; c < 3; ++c) {
        double vx = 0, vy = 0;
        gradient(p, 0, c, &vx);
        gradient(p, 2, c, &vy);
        const double value = primal(p, c, nullptr);
        total += (vx + vy) / (value * value + 0.01);
      }
      out[p] = static_cast<float>(total);
    }
    return out;
  }

 private:
  const std::vector<PixelSums>& sums_;
  int width_, height_;
};


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
  int width, height;
  const GradientPathTracer& tracer;
  const GradientPathTracer* nextTracer;  // null: no temporal offset
  const std::vector<int32_t>& correspondence;
  uint32_t mixedEvery;

  TemporalPair trace(int x, int y, uint32_t sampleIndex, const StratifiedPixel& pattern, bool withMixed,
                     SampleCounters& local) const {
    const SampleKey key{scene.seed, frame, x, y, sampleIndex};
    SampleStream stream(key);
    // As in FrameRenderer: pixel position and time stratified, the lens from the stream.
    const StratifiedSample stratified = pattern.sample(key.sampleIndex);
    const float time = stratified.time;
    const PrimaryRays rays{camera, width, height, stratified.film, stream.next2D()};
    const double seconds = scene.timeAt(frame, time);
    // The temporal offset replays the path's random numbers from here on.
    SampleStream replay = stream;
    // The base ray and its offsets share their time, so the camera's motion is evaluated
    // once for the five.
    const Transform cameraNow = camera.cameraToWorld(seconds);
    TemporalPair pair{
        tracer.trace(rays.through(x, y, cameraNow), rays.offsets(x, y, cameraNow), time, stream, local.rays),
        std::nullopt};
    ++local.samples;
    const size_t p = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
    if (nextTracer && correspondence[p] >= 0) {
      // The temporal offset: the same random numbers one frame later, through the
      // corresponding pixel, with its own spatial offsets for the mixed differences.
      const int tx = correspondence[p] % width, ty = correspondence[p] / width;
      const Transform cameraLater = camera.cameraToWorld(scene.timeAt(frame + 1, time));
      const auto laterOffsets = withMixed ? rays.offsets(tx, ty, cameraLater) : std::array<std::optional<Ray>, 4>{};
      pair.later = nextTracer->trace(rays.through(tx, ty, cameraLater), laterOffsets, time, replay, local.rays);
    }
    return pair;
  }

  // Adds `count` more samples to pixel (x, y)'s sums.
  void render(int x, int y, uint32_t count, PixelSums& s, SampleCounters& local) const {
    const StratifiedPixel pattern(scene.seed, frame, x, y);
    for (uint32_t i = 0; i < count; ++i) {
      const bool withMixed = (s.drawn + i) % mixedEvery == 0;
      const TemporalPair pair = trace(x, y, s.drawn + i, pattern, withMixed, local);
      if (!isFinite(pair.base) || (pair.later && !isFinite(*pair.later))) {
        ++local.nonFinite;
        continue;
      }
      accumulate(pair, withMixed, s);
    }
    s.drawn += count;
  }

  static void accumulate(const TemporalPair& pair, bool withMixed, PixelSums& s) {
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

// The frame cut into square tiles, numbered row by row.
struct TileGrid {
  int width, height, tile;
  int tilesX = (width + tile - 1) / tile, tilesY = (height + tile - 1) / tile;

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

// One batch: every pixel's `allocation` of samples, the tiles in parallel.
void renderBatch(tbb::task_arena& arena, const TileGrid& grid, const PixelSampler& sampler,
                 const std::vector<uint32_t>& allocation, std::vector<PixelSums>& sums,
                 tbb::enumerable_thread_specific<SampleCounters>& counters, TileProgress& progress) {
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, grid.count(), 1), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t index = r.begin(); index != r.end(); ++index) {
        SampleCounters& local = counters.local();
        const int x0 = static_cast<int>(index % static_cast<size_t>(grid.tilesX)) * grid.tile;
        const int y0 = static_cast<int>(index / static_cast<size_t>(grid.tilesX)) * grid.tile;
        for (int y = y0; y < std::min(y0 + grid.tile, grid.height); ++y)
          for (int x = x0; x < std::min(x0 + grid.tile, grid.width); ++x) {
            const size_t p = static_cast<size_t>(y) * static_cast<size_t>(grid.width) + static_cast<size_t>(x);
            sampler.render(x, y, allocation[p], sums[p], local);
          }
        progress.tileDone();
      }
    });
  });
}

// The beauty (primal plus direct emission), the primal estimate, the spatial differences
// and the direct emission, each with its variance.
void writeSpatialLayers(FrameImage& image, const FrameLayers& layers, const std::vector<PixelSums>& sums) {
  for (size_t c = 0; c < 3; ++c) {
    const std::string ch = kChannels[c];
    auto& beauty = image.addChannel(ch);
    auto& beautyVariance = image.addChannel("variance." + ch);
    auto& primal = image.addChannel("primal." + ch);
    auto& primalVariance = image.addChannel("primal.variance." + ch);
    auto& gx = image.addChannel("gradient_x." + ch);
    auto& gxVariance = image.addChannel("gradient_x.variance." + ch);
    auto& gy = image.addChannel("gradient_y." + ch);
    auto& gyVariance = image.addChannel("gradient_y.variance." + ch);
    auto& direct = image.addChannel("direct_emission." + ch);
    for (size_t p = 0; p < sums.size(); ++p) {
      double v = 0;
      primal[p] = static_cast<float>(layers.primal(p, c, &v));
      primalVariance[p] = static_cast<float>(v);
      gx[p] = static_cast<float>(layers.gradient(p, 0, c, &v));
      gxVariance[p] = static_cast<float>(v);
      gy[p] = static_cast<float>(layers.gradient(p, 2, c, &v));
      gyVariance[p] = static_cast<float>(v);
      direct[p] = static_cast<float>(sums[p].direct.mean(c, sums[p].samples));
      beauty[p] = primal[p] + direct[p];
      beautyVariance[p] = primalVariance[p] + static_cast<float>(sums[p].direct.varianceOfMean(c, sums[p].samples));
    }
  }
}

void writeTemporalDifferences(FrameImage& image, const std::vector<PixelSums>& sums) {
  for (size_t c = 0; c < 3; ++c) {
    const std::string ch = kChannels[c];
    auto& temporal = image.addChannel("temporal." + ch);
    auto& variance = image.addChannel("temporal.variance." + ch);
    for (size_t p = 0; p < sums.size(); ++p) {
      temporal[p] = static_cast<float>(sums[p].temporal.mean(c, sums[p].samples));
      variance[p] = static_cast<float>(sums[p].temporal.varianceOfMean(c, sums[p].samples));
    }
  }
}

// Mixed differences where the motion is rigid across the pair: like the spatial
// differences, p's forward part minus its neighbour's backward part. A pair whose
// pixel has no sample with mixed offsets (too few samples for mixedEvery) gets NaN:
// the reconstruction drops it.
void writeMixedDifferences(FrameImage& image, const FrameLayers& layers, const std::vector<PixelSums>& sums,
                           const std::vector<int32_t>& correspondence, int width) {
  const auto rigid = [&](size_t p, size_t k) {
    const size_t n = layers.neighbour(p, k);
    const int step = kShiftDirections[k][0] + kShiftDirections[k][1] * width;
    return n != SIZE_MAX && correspondence[p] >= 0 && correspondence[n] == correspondence[p] + step &&
           (k != 0 || correspondence[p] % width + 1 < width);
  };
  for (size_t k : {size_t{0}, size_t{2}}) {
    const std::string layer = k == 0 ? "mixed_x." : "mixed_y.";
    for (size_t c = 0; c < 3; ++c) {
      auto& mixed = image.addChannel(layer + kChannels[c]);
      auto& variance = image.addChannel(layer + "variance." + kChannels[c]);
      for (size_t p = 0; p < sums.size(); ++p) {
        if (!rigid(p, k)) continue;
        const PixelSums &a = sums[p], &b = sums[layers.neighbour(p, k)];
        if (a.mixedSamples == 0 || b.mixedSamples == 0) {
          mixed[p] = variance[p] = std::numeric_limits<float>::quiet_NaN();
          continue;
        }
        mixed[p] = static_cast<float>(a.mixed[k].mean(c, a.mixedSamples) - b.mixed[k ^ 1].mean(c, b.mixedSamples));
        variance[p] = static_cast<float>(a.mixed[k].varianceOfMean(c, a.mixedSamples) +
                                         b.mixed[k ^ 1].varianceOfMean(c, b.mixedSamples));
      }
    }
  }
}

// Where each pixel's temporal offset went in frame f + 1.
void writeTemporalTargets(FrameImage& image, const std::vector<int32_t>& correspondence, int width) {
  auto& tx = image.addChannel("temporal.target.X");
  auto& ty = image.addChannel("temporal.target.Y");
  auto& valid = image.addChannel("temporal.valid.Y");
  for (size_t p = 0; p < image.pixelCount(); ++p) {
    const int32_t q = correspondence[p];
    tx[p] = q >= 0 ? static_cast<float>(q % width) : -1.0f;
    ty[p] = q >= 0 ? static_cast<float>(q / width) : -1.0f;
    valid[p] = q >= 0 ? 1.0f : 0.0f;
  }
}

}  // namespace

GradientFrameRenderer::GradientFrameRenderer(const Scene& scene, RenderSettings settings, GradientSettings gradient)
    : scene_(scene), settings_(settings), gradient_(gradient), shot_(std::make_unique<Shot>(scene)) {
  if (gradient_.batches < 1) throw std::invalid_argument("adaptive sampling needs at least one batch");
  if (gradient_.mixedEvery < 1) throw std::invalid_argument("mixed differences need at least one sample in every N");
}

GradientFrameRenderer::~GradientFrameRenderer() = default;

FrameImage GradientFrameRenderer::render(int64_t frame, const ProgressCallback& progress, RenderStats* stats) const {
  const auto start = std::chrono::steady_clock::now();
  const int width = settings_.width, height = settings_.height;
  const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
  const FrameGeometry geometry(shot_->geometry, frame);
  const Camera camera(scene_.camera, width, height);
  const PathTracerSettings tracerSettings{settings_.maxDepth};
  const GradientPathTracer tracer(geometry, shot_->lights, tracerSettings);
  tbb::task_arena arena(settings_.threads > 0 ? settings_.threads : tbb::task_arena::automatic);
  std::unique_ptr<const FrameGeometry> nextGeometry;
  std::optional<GradientPathTracer> nextTracer;
  std::vector<int32_t> correspondence;
  if (gradient_.temporal) {
    nextGeometry = std::make_unique<const FrameGeometry>(shot_->geometry, frame + 1);
    nextTracer.emplace(*nextGeometry, shot_->lights, tracerSettings);
    arena.execute([&] {
      correspondence = temporalCorrespondence(geometry, *nextGeometry, camera, width, height, gradient_.motionVectors);
    });
  }

  std::vector<PixelSums> sums(pixels);
  const PixelSampler sampler{scene_, frame, camera, width, height, tracer, nextTracer ? &*nextTracer : nullptr,
                             correspondence, static_cast<uint32_t>(gradient_.mixedEvery)};
  const TileGrid grid{width, height, settings_.tileSize};
  const int batches = gradient_.batches;
  TileProgress tileProgress(progress, grid.count() * static_cast<size_t>(batches));
  tbb::enumerable_thread_specific<SampleCounters> counters;
  std::vector<uint32_t> allocation(pixels, static_cast<uint32_t>(std::max(1, settings_.spp / batches)));
  for (int batch = 0; batch < batches; ++batch) {
    if (batch > 0) {
      const uint64_t budget = static_cast<uint64_t>(settings_.spp) * pixels / static_cast<uint64_t>(batches);
      allocation =
          allocateSamples(samplingDensity(FrameLayers(sums, width, height).relativeVariance(), width, height), budget);
    }
    renderBatch(arena, grid, sampler, allocation, sums, counters, tileProgress);
  }

  FrameImage image(width, height);
  const FrameLayers layers(sums, width, height);
  writeSpatialLayers(image, layers, sums);
  if (gradient_.temporal) {
    writeTemporalDifferences(image, sums);
    writeMixedDifferences(image, layers, sums, correspondence, width);
    writeTemporalTargets(image, correspondence, width);
  }
  auto& sampleCount = image.addChannel("sample_count.Y");
  for (size_t p = 0; p < pixels; ++p) sampleCount[p] = static_cast<float>(sums[p].drawn);

  const RenderStats total = totalOf(counters, start);
  writeRenderAttributes(image, scene_, frame, settings_, total);
  auto& attributes = image.attributes();
  attributes["pathfarm.integrator"] = gradient_.temporal ? "tgpt" : "gpt";
  attributes["pathfarm.adaptive_batches"] = std::to_string(batches);
  if (stats) *stats = total;
  return image;
}

}  // namespace pathfarm
