// The filters of Zimmer et al. 2015 on the animated Cornell box: their speed, and the
// error they buy (the paper's Figure 9 as a table).
//
//   build/bin/filter_benchmark [--scene scenes/cornell/scene.json] [--frame 5]
//                              [--spp 16] [--reference-spp 2048] [--size 256] [--error-only]
//
// Part 1 renders three 1280x720 frames (4 spp, default decomposition) and prints the
// seconds per frame per component of the spatial denoise (r = 10), the 3-frame denoise
// (r = 5) and the 2x upsampling; --error-only skips it. Part 2 renders the frame at
// SIZE x SIZE with --spp and a reference with --reference-spp (samples of its own), and
// prints the relMSE against the reference of the input, the color-only denoise, the
// decomposition without features, and the decomposition with features (3 frames), each
// with the fireflies spread (the default) and kept in the filter. Part 3 compares a
// keyframe's two filters on that frame and its neighbours: the paper's (2x2 box-downsampled,
// denoised at half resolution, upsampled under the full-resolution features) and a denoise
// at full resolution, with their relMSE, worst 16x16 tile and seconds.
#include <chrono>
#include <cstdio>
#include <functional>
#include <utility>

#include "bench/command_line.h"
#include "postproc/filters/component_denoiser.h"
#include "postproc/filters/component_upsampler.h"
#include "postproc/filters/decomposed_frame.h"
#include "postproc/metrics/image_metrics.h"
#include "bench/bench_support.h"
#include "renderer/integrators/frame_renderer.h"
#include "renderer/scene/scene_loader.h"
#include "postproc/filters/direct_emission.h"

namespace {

using namespace pathfarm;

using bench::render;
using bench::seconds;

constexpr uint32_t kReferenceFirstSample = 1u << 24;

// Part 1: speed at 1280x720.
void speedAt720p(const Scene& scene, int frame) {
  const FrameImage previous = render(scene, 1280, 720, 4, frame - 1, true);
  const FrameImage current = render(scene, 1280, 720, 4, frame, true);
  const FrameImage next = render(scene, 1280, 720, 4, frame + 1, true);
  const double components = static_cast<double>(decompositionComponents(current).size());
  DenoiseSettings settings;
  const double spatial = seconds([&] { denoiseFrame(current, nullptr, nullptr, settings); });
  const double temporal = seconds([&] { denoiseFrame(current, &previous, &next, settings); });
  const FrameImage low = boxDownsample(current, 2);
  const double upsample = seconds([&] { upsampleFrame(low, current, UpsampleSettings{}); });
  std::printf("1280x720, %.0f components (the default decomposition)\n", components);
  std::printf("denoise, spatial (r=10, f=3):  %.3f s per frame, %.3f s per component\n", spatial, spatial / components);
  std::printf("denoise, 3 frames (r=5, f=3):  %.3f s per frame, %.3f s per component\n", temporal, temporal / components);
  std::printf("upsample 640x360 -> 1280x720:  %.3f s per frame, %.3f s per component\n", upsample, upsample / components);
}

}  // namespace

int main(int argc, char** argv) {
  bench::CommandLine app("pathfarm filter benchmark");
  std::string scenePath = "scenes/cornell/scene.json";
  int frame = 5, spp = 16, referenceSpp = 2048, size = 256;
  app.option("--scene", scenePath);
  app.option("--frame", frame);
  app.option("--spp", spp);
  app.option("--reference-spp", referenceSpp);
  app.option("--size", size);
  bool errorOnly = false;
  app.flag("--error-only", errorOnly, "skip the speed part");
  if (const auto exit = app.parse(argc, argv)) return *exit;
  const Scene scene = loadScene(scenePath);
  if (!errorOnly) speedAt720p(scene, frame);

  // Part 2: error against a reference.
  const FrameImage reference = render(scene, size, size, referenceSpp, frame, false, kReferenceFirstSample);
  const FrameImage input = render(scene, size, size, spp, frame, true);
  const FrameImage before = render(scene, size, size, spp, frame - 1, true);
  const FrameImage after = render(scene, size, size, spp, frame + 1, true);
  const auto error = [&](const FrameImage& image) { return compareImages(image, reference, {"R", "G", "B"}).relMse; };
  std::printf("\n%dx%d, frame %d, %d spp against %d spp (relMSE)   fireflies spread   kept\n", size, size, frame, spp,
              referenceSpp);
  std::printf("input:                               %.5f\n", error(input));
  const auto row = [&](const char* name, DenoiseMode mode, bool neighbours) {
    DenoiseSettings settings;
    settings.mode = mode;
    const auto run = [&] {
      return error(neighbours ? denoiseFrame(input, &before, &after, settings)
                              : denoiseFrame(input, nullptr, nullptr, settings));
    };
    const double spread = run();
    settings.spreadFireflies = false;
    std::printf("%-36s %.5f            %.5f\n", name, spread, run());
  };
  row("color only (spatial):", DenoiseMode::ColorOnly, false);
  row("decomposition, no features:", DenoiseMode::DecompositionWithoutFeatures, false);
  row("decomposition + features (spatial):", DenoiseMode::Decomposition, false);
  row("decomposition + features (3 frames):", DenoiseMode::Decomposition, true);

  // Part 3: a keyframe's two filters over the same samples and neighbours.
  // As the farm's keyframe tasks do, directly seen light stays out of both filters.
  FrameImage keyframe = input, keyBefore = before, keyAfter = after;
  const FrameImage directLight = takeDirectEmission(keyframe);
  takeDirectEmission(keyBefore);
  takeDirectEmission(keyAfter);
  const auto halfResolution = [&] {
    const FrameImage low = boxDownsample(keyframe, 2), lowBefore = boxDownsample(keyBefore, 2),
                     lowAfter = boxDownsample(keyAfter, 2);
    FrameImage denoised = low;
    denoised.paste(denoiseFrame(low, &lowBefore, &lowAfter, DenoiseSettings{}), 0, 0);
    deriveIrradiance(denoised);
    FrameImage out = keyframe;
    out.paste(upsampleFrame(denoised, keyframe, UpsampleSettings{}), 0, 0);
    addDirectEmission(out, directLight);
    return out;
  };
  const auto fullResolution = [&] {
    FrameImage out = keyframe;
    out.paste(denoiseFrame(keyframe, &keyBefore, &keyAfter, DenoiseSettings{}), 0, 0);
    deriveIrradiance(out);
    addDirectEmission(out, directLight);
    return out;
  };
  std::printf("\nkeyframe filter (3 frames)             relMSE    worst tile  seconds\n");
  for (const auto& [name, filter] : {std::pair<const char*, std::function<FrameImage()>>{
                                         "half resolution, then upsampled:", halfResolution},
                                     {"full resolution:", fullResolution}}) {
    FrameImage out;
    const double time = seconds([&] { out = filter(); });
    const ImageMetrics metrics = compareImages(out, reference, {"R", "G", "B"});
    std::printf("%-38s %.5f   %.4f      %.3f\n", name, metrics.relMse, metrics.worstTileRelMse, time);
  }
  return 0;
}

