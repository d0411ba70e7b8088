// The filters of Zimmer et al. 2015 on the animated Cornell box: their speed, and the
// error they buy (the paper's Figure 9 as a table).
//
//   build/bin/filter_benchmark [--scene scenes/cornell/scene.json] [--frame 5]
//                              [--spp 16] [--reference-spp 2048] [--size 256]
//
// Part 1 renders three 1280x720 frames (4 spp, default decomposition) and prints the
// seconds per frame per component of the spatial denoise (r = 10), the 3-frame denoise
// (r = 5) and the 2x upsampling. Part 2 renders the frame at SIZE x SIZE with --spp and
// a reference with --reference-spp, and prints the relMSE against the reference of the
// input, the color-only denoise, the decomposition without features, and the
// decomposition with features (3 frames).
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>

#include "postproc/filters/component_denoiser.h"
#include "postproc/filters/component_upsampler.h"
#include "postproc/metrics/image_metrics.h"
#include "bench/bench_support.h"
#include "renderer/integrators/frame_renderer.h"
#include "renderer/scene/scene_loader.h"

namespace {

using namespace pathfarm;

using bench::render;
using bench::seconds;

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"pathfarm filter benchmark"};
  std::string scenePath = "scenes/cornell/scene.json";
  int frame = 5, spp = 16, referenceSpp = 2048, size = 256;
  app.add_option("--scene", scenePath);
  app.add_option("--frame", frame);
  app.add_option("--spp", spp);
  app.add_option("--reference-spp", referenceSpp);
  app.add_option("--size", size);
  CLI11_PARSE(app, argc, argv);
  const Scene scene = loadScene(scenePath);

  // Part 1: speed at 1280x720.
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

  // Part 2: error against a reference.
  const FrameImage reference = render(scene, size, size, referenceSpp, frame, false);
  const FrameImage input = render(scene, size, size, spp, frame, true);
  const FrameImage before = render(scene, size, size, spp, frame - 1, true);
  const FrameImage after = render(scene, size, size, spp, frame + 1, true);
  const auto error = [&](const FrameImage& image) { return compareImages(image, reference, {"R", "G", "B"}).relMse; };
  DenoiseSettings colorOnly, withoutFeatures, withFeatures;
  colorOnly.mode = DenoiseMode::ColorOnly;
  withoutFeatures.mode = DenoiseMode::DecompositionWithoutFeatures;
  std::printf("\n%dx%d, frame %d, %d spp against %d spp (relMSE)\n", size, size, frame, spp, referenceSpp);
  std::printf("input:                              %.5f\n", error(input));
  std::printf("color only (spatial):               %.5f\n", error(denoiseFrame(input, nullptr, nullptr, colorOnly)));
  std::printf("decomposition, no features:         %.5f\n",
              error(denoiseFrame(input, nullptr, nullptr, withoutFeatures)));
  std::printf("decomposition + features (spatial): %.5f\n", error(denoiseFrame(input, nullptr, nullptr, withFeatures)));
  std::printf("decomposition + features (3 frames): %.5f\n", error(denoiseFrame(input, &before, &after, withFeatures)));
  return 0;
}
