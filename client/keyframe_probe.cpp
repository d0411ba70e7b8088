#include "client/keyframe_probe.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

#include "postproc/filters/direct_emission.h"
#include "postproc/interpolation/frame_interpolation.h"
#include "postproc/interpolation/in_between_checks.h"
#include "renderer/decomposition/decomposition.h"
#include "renderer/integrators/frame_renderer.h"

namespace pathfarm::farm {
namespace {

constexpr int kProbeScale = 4;   // the probe's resolution is 1/4 of the shot's per axis
constexpr int kProbeSpp = 8;
constexpr int kMinProbeSize = 16;

std::string percent(double rate) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f%%", 100.0 * rate);
  return text;
}

// The share of span[inBetween] that an interpolate task would flag, interpolating it from
// span's first and last frames as keyframes, by the task's rules
// (worker/interpolation_tasks.cpp): the directly seen light is not interpolated but taken
// from the frame's own render, which the interpolation is then checked against.
double predictedRerenderRate(std::vector<FrameImage> span, size_t inBetween) {
  const float fraction = static_cast<float>(inBetween) / static_cast<float>(span.size() - 1);
  const ComponentMotions motions = concatenatePrimaryMotion(span);
  FrameImage& before = span.front();
  FrameImage& after = span.back();
  takeDirectEmission(before);
  takeDirectEmission(after);
  const FrameImage& features = span[inBetween];
  LayeredKeyframes keys = wholeKeyframes(before, after, motions);
  keys.inBetween = &features;
  // Light with no change known nearby is not flagged, as in the task, which leaves it to
  // its light check (which the probe leaves out, below).
  InterpolationSettings interpolation;
  interpolation.unknownChangeMasks = false;
  InterpolationResult result = interpolateFrameDetailed(keys, fraction, interpolation);
  const FrameImage directLight = directEmissionOf(features);
  addDirectEmission(result.frame, directLight);
  // Not the light check: it bounds the difference by the frame's own noise, taking the
  // interpolation from denoised keyframes to have none, but the probe's keyframes are raw
  // 8-spp renders, whose noise it would read as changed light (on the Cornell box at 64x64,
  // k = 8: 20 % of the pixels, where the farm re-renders 11 % for every cause).
  const InBetweenChecks checks = checkInBetween(result.frame, features, directLight);
  size_t flagged = 0;
  for (size_t p = 0; p < result.mask.size(); ++p)
    flagged += (result.mask[p] | checks.mismatch[p] | checks.lightEdges[p] | checks.caustics[p]) != 0;
  return static_cast<double>(flagged) / static_cast<double>(result.mask.size());
}

}  // namespace

KeyframeChoice chooseKeyframeInterval(const Scene& scene, const ShotSpec& spec, double rerenderBound,
                                      int maxInterval) {
  const int64_t frames = spec.frame_end() - spec.frame_start() + 1;
  const int longest = static_cast<int>(std::min<int64_t>(maxInterval, frames - 1));
  if (longest < 2) return {1, "k = 1: the shot is too short to interpolate any frame"};

  const auto start = std::chrono::steady_clock::now();
  RenderSettings settings;
  settings.width = std::max(kMinProbeSize, spec.width() / kProbeScale);
  settings.height = std::max(kMinProbeSize, spec.height() / kProbeScale);
  settings.spp = kProbeSpp;
  settings.maxDepth = spec.max_depth();
  settings.decomposition = std::make_shared<Decomposition>(Decomposition::parse(spec.decompose()));
  const FrameRenderer renderer(scene, settings);
  std::vector<FrameImage> rendered;
  for (int i = 0; i <= longest; ++i) rendered.push_back(renderer.render(spec.frame_start() + i));

  std::string predictions;
  int chosen = 1;
  for (int k = longest; k >= 2; --k) {
    const double rate =
        predictedRerenderRate({rendered.begin(), rendered.begin() + k + 1}, static_cast<size_t>(k / 2));
    predictions += (predictions.empty() ? "" : ", ") + std::string("k = ") + std::to_string(k) + ": " + percent(rate);
    if (rate <= rerenderBound) {
      chosen = k;
      break;
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  char probe[160];
  std::snprintf(probe, sizeof probe, " (probe: frames %lld..%lld at %dx%d, %d spp, %.2f s)",
                static_cast<long long>(spec.frame_start()), static_cast<long long>(spec.frame_start() + longest),
                settings.width, settings.height, kProbeSpp, seconds);
  const std::string bound = percent(rerenderBound);
  const std::string reason =
      chosen > 1 ? "k = " + std::to_string(chosen) + ": the largest interval whose predicted re-render rate stays under " +
                       bound + "; predicted " + predictions + probe
                 : "k = 1: every interval tried predicts a re-render rate above " + bound + " (" + predictions + ")" +
                       probe;
  return {chosen, reason};
}

}  // namespace pathfarm::farm
