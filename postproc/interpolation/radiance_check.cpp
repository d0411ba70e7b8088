#include "postproc/interpolation/radiance_check.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "postproc/filters/decomposed_frame.h"
#include "postproc/interpolation/flag_regions.h"
#include "postproc/interpolation/luminance_planes.h"
#include "postproc/interpolation/solid_regions.h"
#include "postproc/interpolation/window_sums.h"

namespace pathfarm {
namespace {

constexpr const char* kInterpolated = "radiance check: the interpolated frame";
constexpr const char* kFeatures = "radiance check: the features' frame";

}  // namespace

std::vector<uint8_t> radianceMismatch(const FrameImage& interpolated, const FrameImage& features,
                                      const RadianceCheckSettings& settings) {
  if (interpolated.width() != features.width() || interpolated.height() != features.height())
    throw std::invalid_argument("radiance check: the interpolated frame and the features differ in size");
  const int width = features.width(), height = features.height();
  std::vector<uint8_t> mismatch(features.pixelCount(), 0), weak(features.pixelCount(), 0);
  const std::vector<double> beauty = boxSums(luminancePlane(features, "", kFeatures), width, height, settings.radius);
  for (const std::string& c : decompositionComponents(interpolated)) {
    std::vector<double> difference = luminancePlane(interpolated, c + ".color.", kInterpolated);
    const std::vector<double> rendered = luminancePlane(features, c + ".color.", kFeatures);
    for (size_t p = 0; p < difference.size(); ++p) difference[p] -= rendered[p];
    const std::vector<double> differences = boxSums(difference, width, height, settings.radius);
    const std::vector<double> variances =
        boxSums(luminanceVarianceBound(features, c + ".variance.", kFeatures), width, height, settings.radius);
    for (size_t p = 0; p < mismatch.size(); ++p) {
      const double d = std::abs(differences[p]);
      const double deviation = std::sqrt(variances[p]);
      if (d > settings.z * deviation && d > settings.relative * beauty[p]) mismatch[p] = 1;
      if (d > settings.growZ * deviation && d > settings.growRelative * beauty[p]) weak[p] = 1;
    }
  }
  return grownRegions(solidRegions(mismatch, width, height, settings.solidRadius), weak, width, height,
                      settings.growReach);
}

}  // namespace pathfarm
