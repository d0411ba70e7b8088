#include "postproc/interpolation/component_motion.h"

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
