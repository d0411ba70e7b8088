#include "postproc/interpolation/luminance_planes.h"

#include <algorithm>
#include <cmath>

#include "image/luminance.h"

namespace pathfarm {

std::vector<double> luminancePlane(const FrameImage& frame, const std::string& prefix, const std::string& whose) {
  std::vector<double> out(frame.pixelCount(), 0.0);
  for (int c = 0; c < 3; ++c) {
    const std::vector<float>& values = channelOf(frame, prefix + kRgbChannels[c], whose);
    for (size_t p = 0; p < out.size(); ++p) out[p] += kLuminanceWeights<float>[c] * values[p];
  }
  return out;
}

std::vector<double> luminanceVarianceBound(const FrameImage& frame, const std::string& prefix,
                                           const std::string& whose) {
  std::vector<double> out(frame.pixelCount(), 0.0);
  for (int c = 0; c < 3; ++c) {
    const std::vector<float>& values = channelOf(frame, prefix + kRgbChannels[c], whose);
    for (size_t p = 0; p < out.size(); ++p)
      out[p] += kLuminanceWeights<float>[c] * std::sqrt(std::max(0.0f, values[p]));
  }
  for (double& v : out) v *= v;
  return out;
}

}  // namespace pathfarm
