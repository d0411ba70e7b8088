// Keyframe interpolation on the animated Cornell box (Zimmer et al. 2015, Section 5.3 and
// Figures 13-14): its speed, the error it buys and the pixels it leaves to re-render.
//
//   build/bin/interpolation_benchmark [--scene scenes/cornell/scene.json] [--keyframes 4]
//                                     [--spp 16] [--reference-spp 512] [--size 128]
//   build/bin/interpolation_benchmark --bands --scene scenes/walkthrough/scene.json
//                                     [--width 1920 --height 1080] [--band-rows 512] [--spp 16]
//                                     [--reference-spp 512]
//   build/bin/interpolation_benchmark --checks --scene scenes/walkthrough/scene.json
//                                     [--width 320 --height 180] [--spp 16] [--reference-spp 256]
//
// Part 1 times flow (one 1280x720 irradiance layer), interpolation and motion blur of a
// 1280x720 decomposed frame. Part 2 renders frames 0..2k at SIZE x SIZE (keyframes every k
// frames, the frames between as guide features), interpolates every in-between frame
// from its keyframes per component and color-only, re-renders each method's masked
// pixels (from a render at --spp), and prints per frame the relMSE of both against a
// --reference-spp render, and the re-render rates.
//
// With --bands it instead measures what solving the irradiance flow in bands of rows
// (irradiance_flow.h; the farm's flow tasks) costs against one solve over the frame:
// keyframes 0 and 2 at WIDTH x HEIGHT, the flows with each halo, their distance from the
// one-solve flows, and frame 1 interpolated with each, against a --reference-spp render.
// With --checks, the same for the farm's flows (their two directions checked against each
// other) against flows unchecked, checked within 1 px, and of pyramids cut to 1 to 3 levels.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench/command_line.h"
#include "postproc/flow/optical_flow.h"
#include "postproc/interpolation/frame_interpolation.h"
#include "postproc/interpolation/irradiance_flow.h"
#include "postproc/metrics/image_metrics.h"
#include "postproc/motion_blur/motion_blur.h"
#include "bench/bench_support.h"
#include "renderer/integrators/frame_renderer.h"
#include "renderer/scene/scene_loader.h"

namespace {

using namespace pathfarm;

using bench::render;
using bench::seconds;

// The pipeline's result: the interpolated frame with its masked pixels re-rendered (taken
// from `rerendered`, a render at the keyframes' sample count).
FrameImage withRerender(const InterpolationResult& result, const FrameImage& rerendered) {
  FrameImage out = result.frame;
  for (const char* c : {"R", "G", "B"})
    for (size_t p = 0; p < out.pixelCount(); ++p)
      if (result.mask[p]) out.channel(c)[p] = rerendered.channel(c)[p];
  return out;
}

Planes irradiance(const FrameImage& frame) {
  Planes planes(frame.width(), frame.height(), 0);
  for (const char* c : {"R", "G", "B"}) planes.channels.push_back(frame.channel(std::string("diffuse_direct.irradiance.") + c));
  return planes;
}

// What a component's flows are like where there is light to track (its irradiance in the
// keyframe a flow starts from above a hundredth of its mean; in the dark the flow follows
// its smoothness alone and moves nothing visible), over both directions: the pixels whose
// flow is valid (trusted by the interpolation), those valid and departing more than a pixel
// from the primary motion they were bootstrapped by, those whose forward and backward flows
// agree within half a pixel, and the mean distance from another way's flows where both are
// valid.
struct FlowSummary {
  size_t lit = 0, valid = 0, departing = 0, consistent = 0, compared = 0;
  double distance = 0.0;
};

FlowSummary summarize(const ComponentMotion& motion, const ComponentMotion& other, const FrameImage& k0,
                      const FrameImage& k1, const std::string& name) {
  FlowSummary summary;
  for (const bool forward : {true, false}) {
    const MotionField& flow = forward ? motion.irradianceForward : motion.irradianceBackward;
    const MotionField& back = forward ? motion.irradianceBackward : motion.irradianceForward;
    const MotionField& primary = forward ? motion.forward : motion.backward;
    const MotionField& reference = forward ? other.irradianceForward : other.irradianceBackward;
    const std::vector<float>& light = (forward ? k0 : k1).channel(name + ".irradiance.G");
    double mean = 0.0;
    for (const float v : light) mean += v;
    mean /= static_cast<double>(std::max<size_t>(1, light.size()));
    const auto field = [](const MotionField& m) {
      FlowField f(m.width, m.height);
      f.dx = m.x;
      f.dy = m.y;
      return f;
    };
    const OcclusionResult check = forwardBackward(field(flow), field(back), 0.5f);
    for (size_t p = 0; p < flow.x.size(); ++p) {
      if (!(light[p] > 0.01 * mean)) continue;
      ++summary.lit;
      if (check.mask[p] == 0.0f) ++summary.consistent;
      if (flow.valid[p] < 0.5f) continue;
      ++summary.valid;
      const bool primaryHolds = primary.valid.empty() || primary.valid[p] >= 0.5f;
      if (primaryHolds && std::hypot(flow.x[p] - primary.x[p], flow.y[p] - primary.y[p]) > 1.0f) ++summary.departing;
      if (reference.valid[p] < 0.5f) continue;
      ++summary.compared;
      summary.distance += std::hypot(flow.x[p] - reference.x[p], flow.y[p] - reference.y[p]);
    }
  }
  return summary;
}

// A summary's counts as shares of the lit pixels, and its mean distance.
std::string shares(const FlowSummary& summary) {
  const double lit = static_cast<double>(std::max<size_t>(1, summary.lit));
  const auto share = [&](size_t count) { return 100.0 * static_cast<double>(count) / lit; };
  char text[160];
  std::snprintf(text, sizeof text, "%10zu  %5.1f %%  %7.1f %%  %8.1f %%  %12.2f px", summary.lit, share(summary.valid),
                share(summary.departing), share(summary.consistent),
                summary.distance / static_cast<double>(std::max<size_t>(1, summary.compared)));
  return text;
}

// One way to solve the irradiance flows: in bands (or one solve) with some settings.
struct FlowVariant {
  std::string label;
  FlowBanding banding;
  FlowSettings settings;
  float consistency = kFlowConsistency;
};

// Frame 1 between keyframes 0 and 2 with the flows of each variant, against those of the
// first variant.
int compareFlows(const Scene& scene, int width, int height, int spp, int referenceSpp,
                 const std::vector<FlowVariant>& variants) {
  const MotionSpan reach{2, 2};
  const FrameImage k0 = render(scene, width, height, spp, 0, true, 0, reach);
  const FrameImage k1 = render(scene, width, height, spp, 2, true, 0, reach);
  const FrameImage between = render(scene, width, height, spp, 1, true);
  const FrameImage reference = render(scene, width, height, referenceSpp, 1, false, kIndependentFirstSample);
  const ComponentMotions primary = concatenatePrimaryMotion({k0, k1});
  std::printf("%dx%d, %d spp keyframes 0 and 2, frame 1 against %d spp\n", width, height, spp, referenceSpp);
  std::printf("%-9s  component        flow s  lit pixels  valid    departing  consistent  from %-9s  "
              "relMSE frame 1  against %-9s  re-render\n", "flow", variants.front().label.c_str(),
              variants.front().label.c_str());
  // As the farm's interpolation task, which leaves light seen from one keyframe to its checks.
  InterpolationSettings settings;
  settings.unknownChangeMasks = false;
  ComponentMotions first;
  FrameImage firstFrame;
  for (const FlowVariant& variant : variants) {
    ComponentMotions motions = primary;
    const double took = seconds(
        [&] { addIrradianceFlow(motions, k0, k1, variant.settings, variant.banding, variant.consistency); });
    const bool isFirst = &variant == &variants.front();
    if (isFirst) first = motions;
    const InterpolationResult result = interpolateFrameDetailed(k0, k1, motions, 0.5f, settings);
    const FrameImage interpolated = withRerender(result, between);
    if (isFirst) firstFrame = interpolated;
    const char* label = variant.label.c_str();
    FlowSummary all;
    for (const auto& [name, motion] : motions.components) {
      if (name.empty()) continue;
      const FlowSummary one = summarize(motion, first.components.at(name), k0, k1, name);
      std::printf("%-9s  %-15s  %6s  %s\n", label, name.c_str(), "", shares(one).c_str());
      all.lit += one.lit;
      all.valid += one.valid;
      all.departing += one.departing;
      all.consistent += one.consistent;
      all.compared += one.compared;
      all.distance += one.distance;
    }
    std::printf("%-9s  %-15s  %6.2f  %s  %14.5f  %17.2e  %7.2f %%\n", label, "all", took, shares(all).c_str(),
                compareImages(interpolated, reference, {"R", "G", "B"}).relMse,
                compareImages(interpolated, firstFrame, {"R", "G", "B"}).relMse, 100 * result.rerenderRate);
  }
  return 0;
}

// Bands of at most `bandRows` rows with each halo, against one solve over the frame.
std::vector<FlowVariant> bandVariants(int bandRows) {
  std::vector<FlowVariant> variants{{"one", FlowBanding{0, 0}, FlowSettings{}}};
  for (const int halo : {64, 128, 256}) variants.push_back({"halo " + std::to_string(halo), {bandRows, halo}, {}});
  return variants;
}

// The farm's flows (their two directions checked against each other), against flows not
// checked, flows checked within a looser bound and flows of shallower pyramids.
std::vector<FlowVariant> checkVariants(int bandRows) {
  const FlowBanding farm{bandRows, FlowBanding{}.halo};
  std::vector<FlowVariant> variants{{"farm", farm, {}}, {"unchecked", farm, {}, 0.0f}, {"1 px", farm, {}, 1.0f}};
  for (const int levels : {1, 2, 3}) {
    FlowSettings settings;
    settings.maxLevels = levels;
    variants.push_back({std::to_string(levels) + " levels", farm, settings, 0.0f});
  }
  return variants;
}

}  // namespace

int main(int argc, char** argv) {
  bench::CommandLine app("pathfarm interpolation benchmark");
  std::string scenePath = "scenes/cornell/scene.json";
  int keyframes = 4, spp = 16, referenceSpp = 512, size = 128;
  app.option("--scene", scenePath);
  app.option("--keyframes", keyframes);
  app.option("--spp", spp);
  app.option("--reference-spp", referenceSpp);
  app.option("--size", size);
  bool bands = false;
  int width = 1920, height = 1080;
  bool checks = false;
  app.flag("--bands", bands, "measure the flow solved in bands of rows against one solve");
  app.flag("--checks", checks, "measure the farm's flows against flows unchecked, checked looser, of fewer levels");
  app.option("--width", width, "with --bands or --checks").positive();
  app.option("--height", height, "with --bands or --checks").positive();
  int bandRows = FlowBanding{}.rows;
  app.option("--band-rows", bandRows, "with --bands or --checks: the rows a band keeps (the farm's: 512)").positive();
  if (const auto exit = app.parse(argc, argv)) return *exit;
  const Scene scene = loadScene(scenePath);
  if (bands) return compareFlows(scene, width, height, spp, referenceSpp, bandVariants(bandRows));
  if (checks) return compareFlows(scene, width, height, spp, referenceSpp, checkVariants(bandRows));

  // Part 1: speed at 1280x720.
  const FrameImage a = render(scene, 1280, 720, 2, 4, true), b = render(scene, 1280, 720, 2, 5, true);
  FlowField primary(a.width(), a.height());
  primary.dx = a.channel("diffuse_direct.motion.X");
  primary.dy = a.channel("diffuse_direct.motion.Y");
  FlowSettings flowSettings;
  flowSettings.logDomain = true;
  const double flow = seconds([&] { bootstrappedFlow(irradiance(a), irradiance(b), primary, flowSettings); });
  ComponentMotions motions720 = concatenatePrimaryMotion({a, b});
  const double componentFlows = seconds([&] { addIrradianceFlow(motions720, a, b, flowSettings); });
  const double interpolation = seconds([&] { interpolateFrameDetailed(a, b, motions720, 0.5f, {}); });
  const double blur = seconds([&] { motionBlur(a, 0.5f); });
  std::printf("1280x720: flow %.3f s (one RGB layer), irradiance flows of all components %.3f s,\n"
              "          interpolation %.3f s, motion blur %.3f s (5 components)\n",
              flow, componentFlows, interpolation, blur);

  // Part 2: error and re-render rate.
  std::vector<FrameImage> frames;
  for (int f = 0; f <= 2 * keyframes; ++f) frames.push_back(render(scene, size, size, spp, f, true));
  std::printf("\n%dx%d, keyframes every %d frames, %d spp, reference %d spp\n", size, size, keyframes, spp,
              referenceSpp);
  std::printf("frame  relMSE per component  relMSE color only  re-render per component  re-render color only\n");
  for (int k = 0; k + keyframes < static_cast<int>(frames.size()); k += keyframes) {
    const std::vector<FrameImage> chain(frames.begin() + k, frames.begin() + k + keyframes + 1);
    const ComponentMotions primary = concatenatePrimaryMotion(chain);
    ComponentMotions motions = primary;
    addIrradianceFlow(motions, chain.front(), chain.back(), FlowSettings{});
    for (int f = 1; f < keyframes; ++f) {
      const float s = static_cast<float>(f) / static_cast<float>(keyframes);
      InterpolationSettings colorOnly;
      colorOnly.colorOnly = true;
      const InterpolationResult split = interpolateFrameDetailed(chain.front(), chain.back(), motions, s, {});
      const InterpolationResult plain = interpolateFrameDetailed(chain.front(), chain.back(), primary, s, colorOnly);
      const FrameImage reference = render(scene, size, size, referenceSpp, k + f, false, kIndependentFirstSample);
      const FrameImage& rendered = frames[static_cast<size_t>(k + f)];
      std::printf("%5d  %20.5f  %17.5f  %21.2f %%  %18.2f %%\n", k + f,
                  compareImages(withRerender(split, rendered), reference, {"R", "G", "B"}).relMse,
                  compareImages(withRerender(plain, rendered), reference, {"R", "G", "B"}).relMse,
                  100 * split.rerenderRate, 100 * plain.rerenderRate);
    }
  }
  return 0;
}
