#include "renderer/bidirectional/bdpt_frame_renderer.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <stdexcept>

#include "renderer/accel/embree_device.h"
#include "renderer/bidirectional/connection.h"
#include "renderer/bidirectional/subpath.h"
#include "renderer/film/splat_film.h"
#include "renderer/integrators/sample_moments.h"

namespace pathfarm {

struct BdptFrameRenderer::Shot {
  EmbreeDevice device;
  ShotGeometry geometry;
  LightSampler lights;

  explicit Shot(const Scene& scene) : geometry(scene, device), lights(geometry) {}
};

BdptFrameRenderer::BdptFrameRenderer(const Scene& scene, RenderSettings settings)
    : scene_(scene), settings_(std::move(settings)) {
  if (settings_.decomposition)
    throw std::invalid_argument("bidirectional path tracing renders no path-space components");
  shot_ = std::make_unique<Shot>(scene);
}

BdptFrameRenderer::~BdptFrameRenderer() = default;

namespace {

// One thread's subpaths and counts, reused from sample to sample.
struct ThreadState {
  Subpath camera, light;
  SampleCounters counters;
};

}  // namespace

FrameImage BdptFrameRenderer::render(int64_t frame, const ProgressCallback& progress, RenderStats* stats) const {
  const auto start = std::chrono::steady_clock::now();
  const FrameGeometry geometry(shot_->geometry, frame);
  const CameraImportance camera(scene_.camera, settings_.width, settings_.height);
  const BdptScene bdpt{geometry, shot_->lights, camera, settings_.maxDepth};
  const int width = settings_.width, height = settings_.height, tile = settings_.tileSize;
  FrameImage image(width, height);
  SplatFilm splats(width, height);
  std::vector<float> variance[3];
  for (auto& v : variance) v.assign(static_cast<size_t>(width) * static_cast<size_t>(height), 0.0f);

  const int tilesX = (width + tile - 1) / tile, tilesY = (height + tile - 1) / tile;
  const size_t tileCount = static_cast<size_t>(tilesX) * static_cast<size_t>(tilesY);
  std::atomic<size_t> tilesDone{0};
  std::vector<Rgb> means(static_cast<size_t>(width) * static_cast<size_t>(height));
  tbb::enumerable_thread_specific<ThreadState> threadStates;
  const double splatScale = 1.0 / settings_.spp;

  auto renderPixel = [&](ThreadState& state, int x, int y) {
    SampleMoments moments;
    uint32_t accepted = 0;
    const StratifiedPixel pattern(scene_.seed, frame, x, y);
    for (int i = 0; i < settings_.spp; ++i) {
      const SampleKey key{scene_.seed, frame, x, y, settings_.firstSample + static_cast<uint32_t>(i)};
      SampleStream stream(key);
      StreamSource u(stream);
      const StratifiedSample stratified = pattern.sample(key.sampleIndex);
      const Vec2f jitter = stratified.film;
      const float time = stratified.time;
      const Vec2f lens = u.next2D();
      const Vec2f film{static_cast<float>(x) + jitter.x, static_cast<float>(y) + jitter.y};
      generateCameraSubpath(bdpt, time, film, lens, u, maxCameraVertices(bdpt), state.camera);
      generateLightSubpath(bdpt, time, u, maxLightVertices(bdpt), state.light);
      Rgb L;
      forEachStrategy(bdpt, state.camera, state.light, [&](int s, int t) {
        const auto sample = connectStrategy(bdpt, time, state.camera, state.light, s, t, u);
        if (!sample) return;
        if (!sample->lightTracing) {
          L += sample->contribution;
          return;
        }
        const Rgb splat = sample->contribution * static_cast<float>(splatScale);
        splats.add(static_cast<int>(sample->raster.x), static_cast<int>(sample->raster.y), splat);
      });
      ++state.counters.samples;
      if (!L.isFinite()) {
        ++state.counters.nonFinite;
        continue;
      }
      ++accepted;
      moments.add(L);
    }
    const size_t pixel = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
    for (size_t c = 0; c < 3; ++c) variance[c][pixel] = static_cast<float>(moments.varianceOfMean(c, accepted));
    means[pixel] = {static_cast<float>(moments.mean(0, accepted)), static_cast<float>(moments.mean(1, accepted)),
                    static_cast<float>(moments.mean(2, accepted))};
  };

  tbb::task_arena arena(settings_.threads > 0 ? settings_.threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, tileCount, 1), [&](const tbb::blocked_range<size_t>& r) {
      ThreadState& state = threadStates.local();
      for (size_t index = r.begin(); index != r.end(); ++index) {
        const int x0 = static_cast<int>(index % static_cast<size_t>(tilesX)) * tile;
        const int y0 = static_cast<int>(index / static_cast<size_t>(tilesX)) * tile;
        for (int y = y0; y < std::min(y0 + tile, height); ++y)
          for (int x = x0; x < std::min(x0 + tile, width); ++x) renderPixel(state, x, y);
        const size_t done = ++tilesDone;
        if (progress) progress(done, tileCount);
      }
    });
  });

  // Beauty = the camera strategies' mean + the light-tracing splats, summed after every
  // splat has landed.
  const char* names[3] = {"R", "G", "B"};
  for (int c = 0; c < 3; ++c) {
    std::vector<float>& channel = image.addChannel(names[c]);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const size_t pixel = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
        channel[pixel] = means[pixel][c] + splats.value(x, y)[c];
      }
  }
  const char* varianceNames[3] = {"variance.R", "variance.G", "variance.B"};
  for (int c = 0; c < 3; ++c) image.addChannel(varianceNames[c]) = variance[c];

  std::vector<SampleCounters> perThread;
  for (const ThreadState& state : threadStates) perThread.push_back(state.counters);
  const RenderStats total = totalOf(perThread, start);
  writeRenderAttributes(image, scene_, frame, settings_, total);
  image.attributes()["pathfarm.integrator"] = "bdpt";
  image.attributes()["pathfarm.rejected_splats"] = std::to_string(splats.rejected());
  if (stats) *stats = total;
  return image;
}

}  // namespace pathfarm
