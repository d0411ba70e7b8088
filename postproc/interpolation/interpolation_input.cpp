#include "postproc/interpolation/interpolation_input.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "image/size_text.h"
#include "postproc/filters/decomposed_frame.h"

namespace pathfarm {

const std::vector<float>& finiteChannel(const FrameImage& frame, const std::string& name, const std::string& label) {
  if (!frame.hasChannel(name)) throw std::invalid_argument(label + ": missing channel \"" + name + "\"");
  const std::vector<float>& plane = frame.channel(name);
  for (size_t p = 0; p < plane.size(); ++p)
    if (!std::isfinite(plane[p]))
      throw std::invalid_argument(label + ": channel \"" + name + "\" has a non-finite value at pixel (" +
                                  std::to_string(p % static_cast<size_t>(std::max(1, frame.width()))) + ", " +
                                  std::to_string(p / static_cast<size_t>(std::max(1, frame.width()))) + ")");
  return plane;
}

void checkField(const MotionField& field, int width, int height, const std::string& what) {
  const size_t pixels = static_cast<size_t>(width) * static_cast<size_t>(height);
  if (field.width != width || field.height != height || field.x.size() != pixels || field.y.size() != pixels ||
      (!field.valid.empty() && field.valid.size() != pixels))
    throw std::invalid_argument(what + " is " + sizeText(field.width, field.height) + " (planes " +
                                std::to_string(field.x.size()) + "/" + std::to_string(field.y.size()) +
                                "), the keyframes " + sizeText(width, height));
  for (size_t p = 0; p < pixels; ++p) {
    const bool valid = field.valid.empty() || field.valid[p] >= 0.5f;
    if ((valid && (!std::isfinite(field.x[p]) || !std::isfinite(field.y[p]))) ||
        (!field.valid.empty() && !std::isfinite(field.valid[p])))
      throw std::invalid_argument(what + " has a non-finite value at pixel " + std::to_string(p));
  }
}

void checkSameLayout(const FrameImage& a, const FrameImage& b, const std::string& labelA, const std::string& labelB) {
  if (a.width() != b.width() || a.height() != b.height())
    throw std::invalid_argument(labelB + " is " + sizeText(b.width(), b.height()) + ", " + labelA + " " +
                                sizeText(a.width(), a.height()));
  if (decompositionComponents(a) != decompositionComponents(b))
    throw std::invalid_argument(labelB + " has another decomposition (pathfarm.decomposition) than " + labelA);
}

}  // namespace pathfarm
