#include "postproc/interpolation/component_motion.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "postproc/filters/decomposed_frame.h"
#include "postproc/interpolation/interpolation_input.h"

namespace pathfarm {
namespace {

void checkFinite(const std::vector<float>& plane, const std::string& what) {
  for (float v : plane)
    if (!std::isfinite(v)) throw std::invalid_argument(what + " has a non-finite value");
}

}  // namespace

void addIrradianceFlow(ComponentMotions& motions, const FrameImage& k0, const FrameImage& k1,
                       const FlowSettings& settings) {
  const int width = k0.width(), height = k0.height();
  if (width <= 0 || height <= 0) throw std::invalid_argument("irradiance flow: keyframe 0 is empty");
  checkSameLayout(k0, k1, "keyframe 0", "keyframe 1");
  const std::vector<std::string> components = decompositionComponents(k0);
  FlowSettings logSettings = settings;
  logSettings.logDomain = true;
  const size_t pixels = k0.pixelCount();
  auto irradiance = [&](const FrameImage& frame, const std::string& c, const std::string& label) {
    Planes planes(width, height, 3);
    const char* rgb[3] = {"R", "G", "B"};
    for (size_t i = 0; i < 3; ++i) planes.channels[i] = finiteChannel(frame, c + ".irradiance." + rgb[i], label);
    return planes;
  };
  // The primary motion as the initial guess: 0 where it is invalid.
  auto guess = [&](const MotionField& motion, const std::string& what) {
    checkField(motion, width, height, what);
    FlowField flow(width, height);
    for (size_t p = 0; p < pixels; ++p)
      if (motion.valid.empty() || motion.valid[p] >= 0.5f) {
        flow.dx[p] = motion.x[p];
        flow.dy[p] = motion.y[p];
      }
    return flow;
  };
  auto toMotion = [&](const FlowField& flow) {
    MotionField motion;
    motion.width = width;
    motion.height = height;
    motion.x = flow.dx;
    motion.y = flow.dy;
    motion.valid.assign(pixels, 0.0f);
    for (size_t p = 0; p < pixels; ++p) {
      const float tx = static_cast<float>(p % static_cast<size_t>(width)) + flow.dx[p];
      const float ty = static_cast<float>(p / static_cast<size_t>(width)) + flow.dy[p];
      if (std::isfinite(tx) && std::isfinite(ty) && tx > -0.5f && tx < static_cast<float>(width) - 0.5f &&
          ty > -0.5f && ty < static_cast<float>(height) - 0.5f)
        motion.valid[p] = 1.0f;
    }
    return motion;
  };
  std::vector<std::pair<const std::string, ComponentMotion>*> flowing;
  for (auto& entry : motions.components) {
    if (entry.first.empty()) continue;
    if (std::find(components.begin(), components.end(), entry.first) == components.end())
      throw std::invalid_argument("irradiance flow: the keyframes have no component \"" + entry.first + "\"");
    flowing.push_back(&entry);
  }
  tbb::parallel_for(size_t(0), flowing.size(), [&](size_t i) {
    const std::string& c = flowing[i]->first;
    ComponentMotion& motion = flowing[i]->second;
    const std::string what = "irradiance flow: component \"" + c + "\"";
    const Planes e0 = irradiance(k0, c, "keyframe 0"), e1 = irradiance(k1, c, "keyframe 1");
    const FlowField forward = bootstrappedFlow(e0, e1, guess(motion.forward, what + " forward motion"), logSettings);
    const FlowField backward = bootstrappedFlow(e1, e0, guess(motion.backward, what + " backward motion"), logSettings);
    motion.irradianceForward = toMotion(forward);
    motion.irradianceBackward = toMotion(backward);
    motion.hasIrradianceMotion = true;
  });
}

ComponentMotions concatenatePrimaryMotion(const std::vector<FrameImage>& frames) {
  if (frames.size() < 2)
    throw std::invalid_argument("motion concatenation: needs at least two frames, got " + std::to_string(frames.size()));
  const int width = frames[0].width(), height = frames[0].height();
  if (width <= 0 || height <= 0) throw std::invalid_argument("motion concatenation: frame 0 is empty");
  for (size_t k = 1; k < frames.size(); ++k)
    checkSameLayout(frames[0], frames[k], "frame 0", "frame " + std::to_string(k));
  const size_t pixels = frames[0].pixelCount();
  std::vector<std::string> names = {""};
  for (const std::string& c : decompositionComponents(frames[0])) names.push_back(c);

  auto chain = [&](const std::string& prefix, bool forward) {
    MotionField result;
    result.width = width;
    result.height = height;
    result.x.assign(pixels, 0.0f);
    result.y.assign(pixels, 0.0f);
    result.valid.assign(pixels, 1.0f);
    const size_t n = frames.size();
    for (size_t step = 0; step + 1 < n; ++step) {
      const size_t k = forward ? step : n - 1 - step;
      const std::string label = "motion concatenation: frame " + std::to_string(k);
      const MotionField link =
          motionTowards(frames[k], forward ? NeighbourFrame::Next : NeighbourFrame::Previous, prefix, label);
      const std::string what = label + " layer \"" + prefix + (forward ? "motion" : "motion_back") + "\"";
      checkFinite(link.x, what);
      checkFinite(link.y, what);
      checkFinite(link.valid, label + " channel \"" + prefix + "motion_valid.Y\"");
      MotionField reached;  // frame `front` -> frame k so far
      reached.width = width;
      reached.height = height;
      reached.x = result.x;
      reached.y = result.y;
      const std::vector<float> inside = warpValidity(reached);
      Planes motion(width, height, 2);
      motion.channels[0] = link.x;
      motion.channels[1] = link.y;
      const Planes looked = warpPlanes(motion, reached);
      std::vector<float> linkValid(pixels, 1.0f);
      if (!link.valid.empty()) {
        Planes valid(width, height, 1);
        valid.channels[0] = link.valid;
        linkValid = warpPlanes(valid, reached, WarpLookup::Nearest).channels[0];
      }
      for (size_t p = 0; p < pixels; ++p) {
        if (inside[p] < 0.5f || linkValid[p] < 0.5f) result.valid[p] = 0.0f;
        result.x[p] += looked.channels[0][p];
        result.y[p] += looked.channels[1][p];
      }
    }
    MotionField end = result;
    end.valid.clear();
    const std::vector<float> inside = warpValidity(end);
    for (size_t p = 0; p < pixels; ++p)
      if (inside[p] < 0.5f) result.valid[p] = 0.0f;
    return result;
  };

  ComponentMotions motions;
  for (const std::string& name : names) {
    const std::string prefix = name.empty() ? "" : name + ".";
    motions.components[name] = ComponentMotion{chain(prefix, true), chain(prefix, false)};
  }
  return motions;
}

}  // namespace pathfarm
