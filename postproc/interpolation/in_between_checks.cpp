#include "postproc/interpolation/in_between_checks.h"

#include "postproc/interpolation/feature_check.h"

namespace pathfarm {

InBetweenChecks checkInBetween(const FrameImage& interpolated, const FrameImage& features,
                               const FrameImage& directLight) {
  return {featureMismatch(interpolated, features), directLightEdges(directLight, features),
          radianceMismatch(interpolated, features, RadianceCheckSettings{}),
          movingCausticPixels(features, CausticCheckSettings{})};
}

}  // namespace pathfarm
