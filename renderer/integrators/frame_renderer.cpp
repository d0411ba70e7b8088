#include "renderer/integrators/frame_renderer.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <array>
#include <atomic>
#include <chrono>
#include <stdexcept>

#include "renderer/accel/shot_geometry.h"
#include "renderer/decomposition/decomposed_film.h"
#include "renderer/decomposition/primary_motion.h"
#include "renderer/decomposition/specular_motion.h"
#include "renderer/integrators/sample_moments.h"
#include "renderer/integrators/shutter_buckets.h"

namespace pathfarm {

RenderSettings RenderSettings::defaultsOf(const Scene& scene) {
  RenderSettings settings;
  settings.width = scene.defaults.width;
  settings.height = scene.defaults.height;
  settings.spp = scene.defaults.spp;
  settings.maxDepth = scene.defaults.maxDepth;
  return settings;
}

struct FrameRenderer::Shot {
  EmbreeDevice device;
  ShotGeometry geometry;
  LightSampler lights;
  bool decomposing;
  std::vector<PreciseShape> preciseShapes;  // for the specular motion of a decomposition

  Shot(const Scene& scene, bool decomposes)
      : geometry(scene, device),
        lights(geometry),
        decomposing(decomposes),
        preciseShapes(decomposes ? preciseShapesOf(scene) : std::vector<PreciseShape>{}) {}
};

FrameRenderer::FrameRenderer(const Scene& scene, RenderSettings settings)
    : scene_(scene), settings_(settings), shot_(std::make_shared<Shot>(scene, settings.decomposition != nullptr)) {}

// A decomposing renderer needs the precise shapes, which a base renderer without a
// decomposition did not build: then it builds its own shot.
FrameRenderer::FrameRenderer(const FrameRenderer& shot, RenderSettings settings)
    : scene_(shot.scene_),
      settings_(settings),
      shot_(settings.decomposition && !shot.shot_->decomposing ? std::make_shared<Shot>(shot.scene_, true)
                                                               : shot.shot_) {}

FrameRenderer::~FrameRenderer() = default;

std::shared_ptr<const FrameGeometry> FrameRenderer::geometryFor(int64_t frame) const {
  const std::lock_guard lock(geometryMutex_);
  if (!lastGeometry_ || lastGeometry_->frame() != frame)
    lastGeometry_ = std::make_shared<const FrameGeometry>(shot_->geometry, frame);
  return lastGeometry_;
}

namespace {

// Primary motion, with the camera's placements per shutter bucket in the frames the
// motion reaches, made once per window like the frame's own.
struct MotionSampler {
  MotionSampler(const PrimaryMotion& primary, const Scene& scene, const Camera& camera, int64_t frame, MotionSpan span)
      : primary(primary), forward(scene, camera, frame + span.forward), backward(scene, camera, frame - span.backward) {}

  // `time`: a bucket's centre; `cameraNow`: the frame's placement there, which made `ray`.
  MotionPair of(const PathRecord& record, const Ray& ray, float time, const Transform& cameraNow) const {
    const CameraPlacements camera{cameraNow, forward.cameraToWorld(time), backward.cameraToWorld(time)};
    return record.hit ? primary.ofSurface(record.primary, time, camera) : primary.ofBackground(ray.direction, camera);
  }

  const PrimaryMotion& primary;
  ShutterBuckets forward, backward;
};

SampleExtras extrasOf(const PathRecord& record, const Ray& ray, float time, const MotionSampler* motion,
                      const Transform& cameraNow) {
  SampleExtras extras;
  extras.hit = record.hit;
  if (record.hit) {
    const SurfaceHit& hit = record.primary;
    extras.object = hit.object;
    extras.position = hit.position;
    extras.depth = hit.distance;
  }
  if (!motion) return extras;
  const MotionPair moved = motion->of(record, ray, time, cameraNow);
  extras.motionSampled = true;
  extras.motion = moved.forward;
  extras.motionBack = moved.backward;
  return extras;
}

std::optional<Vec2f> toFloat(const std::optional<Vec2d>& v) {
  if (!v) return std::nullopt;
  return Vec2f{static_cast<float>(v->x), static_cast<float>(v->y)};
}

void checkWindow(const PixelWindow& window, const RenderSettings& settings, const std::vector<uint8_t>* only) {
  if (window.x0 < 0 || window.y0 < 0 || window.x1 > settings.width || window.y1 > settings.height ||
      window.width() <= 0 || window.height() <= 0)
    throw std::invalid_argument("the pixel window lies outside the frame or is empty");
  if (only && only->size() != static_cast<size_t>(window.width()) * static_cast<size_t>(window.height()))
    throw std::invalid_argument("the pixel mask does not have the window's size");
}

// R, G, B and variance.R, variance.G, variance.B, added to `image`.
std::array<float*, 6> addBeautyChannels(FrameImage& image) {
  std::array<float*, 6> channels;
  const char* names[6] = {"R", "G", "B", "variance.R", "variance.G", "variance.B"};
  for (size_t c = 0; c < 6; ++c) channels[c] = image.addChannel(names[c]).data();
  return channels;
}

// A tile's path decomposer (with a decomposition): it splits each sample's radiance into
// `components`, and `record` keeps where the sample's camera ray hit.
struct TileDecomposer {
  SampleComponents components;
  std::optional<PathDecomposer> decomposer;
  PathRecord record;
};

// Renders the pixels of a window into its image, tile by tile: each pixel's beauty (the
// mean of its finite samples and the variance of that mean) and, with a decomposition,
// its components' buffers.
struct WindowPixels {
  const Scene& scene;
  const RenderSettings& settings;
  int64_t frame;
  const PixelWindow& window;
  const std::vector<uint8_t>* only;  // null: every pixel
  const Camera& camera;
  const ShutterBuckets& shutter;
  const PathTracer& tracer;
  const MotionSampler* motion;  // null: no motion measured
  const Decomposition* decomposition;  // null: beauty only; else the film is there too
  const DecomposedFilm* film;
  const SpecularMotion* specular;  // null: no motion measured
  std::array<float*, 6> channels;  // addBeautyChannels'

  void renderTile(int x0, int y0, int tile, SampleCounters& local) const {
    const int width = window.width(), height = window.height();
    TileDecomposer paths;
    if (film) paths.decomposer.emplace(*decomposition, paths.components);
    for (int iy = y0; iy < std::min(y0 + tile, height); ++iy) {
      for (int ix = x0; ix < std::min(x0 + tile, width); ++ix) {
        const size_t pixel = static_cast<size_t>(iy) * static_cast<size_t>(width) + static_cast<size_t>(ix);
        if (only && (*only)[pixel] == 0) continue;
        renderPixel(ix, iy, pixel, paths, local);
      }
    }
  }

  struct CameraSample {
    SampleStream stream;  // past the lens's dimensions
    float time;
    const Transform& cameraNow;  // the camera's placement at `time`, which made `ray`
    Ray ray;
  };

  // Sample `s` of frame pixel (x, y): its position in the pixel and its shutter time are
  // stratified over the pixel's samples, the time then taken to its shutter bucket's
  // centre; the stream's first dimensions are the lens's.
  CameraSample cameraSample(int x, int y, const StratifiedPixel& pattern, const PixelStreams& streams, int s) const {
    const uint32_t sampleIndex = settings.firstSample + static_cast<uint32_t>(s);
    SampleStream stream = streams.stream(sampleIndex);
    const StratifiedSample stratified = pattern.sample(sampleIndex);
    const Vec2f lens = stream.next2D();
    const Transform& cameraNow = shutter.cameraToWorld(stratified.time);
    const Ray ray = camera.generateRay(
        {static_cast<float>(x) + stratified.film.x, static_cast<float>(y) + stratified.film.y}, lens, cameraNow);
    return {stream, ShutterBuckets::time(stratified.time), cameraNow, ray};
  }

  void renderPixel(int ix, int iy, size_t pixel, TileDecomposer& paths, SampleCounters& local) const {
    const int x = window.x0 + ix, y = window.y0 + iy;  // frame pixel coordinates
    SampleMoments moments;
    uint32_t accepted = 0;
    std::optional<DecomposedFilm::Pixel> sums;
    if (film) sums.emplace(decomposition->size());
    const StratifiedPixel pattern(scene.seed, frame, x, y);
    const PixelStreams streams(scene.seed, frame, x, y);
    for (int s = 0; s < settings.spp; ++s) {
      CameraSample sample = cameraSample(x, y, pattern, streams, s);
      if (film) {
        paths.decomposer->begin();
        paths.record = {&*paths.decomposer, false, {}};
      }
      const Rgb L = tracer.radiance(sample.ray, sample.time, sample.stream, local.rays, film ? &paths.record : nullptr);
      ++local.samples;
      if (!L.isFinite()) {
        ++local.nonFinite;
        continue;
      }
      if (film)
        sums->add(paths.components, extrasOf(paths.record, sample.ray, sample.time,
                                             s < DecomposedFilm::kMotionSamples ? motion : nullptr, sample.cameraNow));
      ++accepted;
      moments.add(L);
    }
    // The reflectance's own samples continue the pixel's stratified pattern.
    for (int s = settings.spp; film && s < settings.reflectanceSpp; ++s) {
      CameraSample sample = cameraSample(x, y, pattern, streams, s);
      paths.decomposer->begin();
      tracer.traceFeatures(sample.ray, sample.time, sample.stream, local.rays, *paths.decomposer);
      sums->addReflectance(paths.components);
    }
    for (size_t c = 0; c < 3; ++c) {
      channels[c][pixel] = static_cast<float>(moments.mean(c, accepted));
      channels[3 + c][pixel] = static_cast<float>(moments.varianceOfMean(c, accepted));
    }
    if (film) writeComponents(x, y, pixel, *sums);
  }

  // The specular components take their motion from the manifold walk.
  void writeComponents(int x, int y, size_t pixel, DecomposedFilm::Pixel& sums) const {
    for (int k = 0; specular && k < decomposition->size(); ++k) {
      if (!specular->isSpecular(k)) continue;
      const SpecularTrack track = specular->track(x, y, k);
      sums.setSpecularMotion(k, toFloat(track.forward), toFloat(track.backward));
    }
    film->write(pixel, sums);
  }
};

// The window's tiles in parallel on `threads` threads (0: every core), each thread
// counting its samples in `counters`.
void renderTiles(const WindowPixels& pixels, int tile, int threads, const ProgressCallback& progress,
                 tbb::enumerable_thread_specific<SampleCounters>& counters) {
  const int width = pixels.window.width(), height = pixels.window.height();
  const int tilesX = (width + tile - 1) / tile, tilesY = (height + tile - 1) / tile;
  const size_t tileCount = static_cast<size_t>(tilesX) * static_cast<size_t>(tilesY);
  std::atomic<size_t> tilesDone{0};
  auto renderTile = [&](size_t index) {
    SampleCounters& local = counters.local();
    const int x0 = static_cast<int>(index % static_cast<size_t>(tilesX)) * tile;
    const int y0 = static_cast<int>(index / static_cast<size_t>(tilesX)) * tile;
    pixels.renderTile(x0, y0, tile, local);
    const size_t done = ++tilesDone;
    if (progress) progress(done, tileCount);
  };
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, tileCount, 1), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) renderTile(i);
    });
  });
}

}  // namespace

void writeRenderAttributes(FrameImage& image, const Scene& scene, int64_t frame, const RenderSettings& settings,
                           const RenderStats& stats) {
  auto& attributes = image.attributes();
  attributes["pathfarm.scene"] = scene.file.filename().string();
  attributes["pathfarm.frame"] = std::to_string(frame);
  attributes["pathfarm.spp"] = std::to_string(settings.spp);
  attributes["pathfarm.max_depth"] = std::to_string(settings.maxDepth);
  attributes["pathfarm.seed"] = std::to_string(scene.seed);
  if (settings.firstSample != 0) attributes["pathfarm.first_sample"] = std::to_string(settings.firstSample);
  if (settings.decomposition && settings.reflectanceSpp > settings.spp)
    attributes["pathfarm.reflectance_spp"] = std::to_string(settings.reflectanceSpp);
  attributes["pathfarm.nonfinite_samples"] = std::to_string(stats.nonFiniteSamples);
}

FrameImage FrameRenderer::render(int64_t frame, const ProgressCallback& progress, RenderStats* stats) const {
  return renderWindow(frame, {0, 0, settings_.width, settings_.height}, progress, stats);
}

FrameImage FrameRenderer::renderWindow(int64_t frame, const PixelWindow& window, const ProgressCallback& progress,
                                       RenderStats* stats, const std::vector<uint8_t>* only) const {
  const auto start = std::chrono::steady_clock::now();
  const std::shared_ptr<const FrameGeometry> geometry = geometryFor(frame);
  const PathTracer tracer(*geometry, shot_->lights, {settings_.maxDepth});
  const Camera camera(scene_.camera, settings_.width, settings_.height);
  const ShutterBuckets shutter(scene_, camera, frame);
  const Decomposition* decomposition = settings_.decomposition.get();
  const PrimaryMotion motion(*geometry, camera, frame, settings_.motionSpan);
  checkWindow(window, settings_, only);

  const int width = window.width(), height = window.height();
  FrameImage image(width, height);
  const std::array<float*, 6> channels = addBeautyChannels(image);
  std::optional<DecomposedFilm> film;
  if (decomposition) film.emplace(image, *decomposition);
  std::optional<SpecularMotion> specular;
  std::optional<MotionSampler> motionSampler;
  const bool measuresMotion = decomposition && settings_.motion;
  if (measuresMotion) {
    motionSampler.emplace(motion, scene_, camera, frame, settings_.motionSpan);
    specular.emplace(*geometry, shot_->preciseShapes, *decomposition, settings_.width, settings_.height,
                     settings_.motionSpan);
  }

  const WindowPixels pixels{.scene = scene_,
                            .settings = settings_,
                            .frame = frame,
                            .window = window,
                            .only = only,
                            .camera = camera,
                            .shutter = shutter,
                            .tracer = tracer,
                            .motion = motionSampler ? &*motionSampler : nullptr,
                            .decomposition = decomposition,
                            .film = film ? &*film : nullptr,
                            .specular = specular ? &*specular : nullptr,
                            .channels = channels};
  tbb::enumerable_thread_specific<SampleCounters> counters;
  renderTiles(pixels, settings_.tileSize, settings_.threads, progress, counters);

  const RenderStats total = totalOf(counters, start);
  writeRenderAttributes(image, scene_, frame, settings_, total);
  if (decomposition) image.attributes()["pathfarm.decomposition"] = decomposition->describe();
  if (decomposition) image.attributes()["pathfarm.specular_components"] = decomposition->describeSpecular();
  if (decomposition && !measuresMotion) image.attributes()["pathfarm.motion"] = "not measured";
  if (stats) *stats = total;
  return image;
}

}  // namespace pathfarm
