#pragma once
// What an interpolated frame is checked against: its own render (the farm's feature render
// of the in-between frame). Four causes flag a pixel for re-rendering beside the
// interpolation's own (frame_interpolation.h): the frame's surfaces disagree with the
// interpolated ones (feature_check.h); an edge of its directly seen light, which the few
// samples of that render leave noisy (direct_emission.h); its light disagrees beyond its
// noise (radiance_check.h); a moving caustic, which no keyframe's motion carries
// (caustic_check.h). The farm's interpolate task and the client's keyframe probe apply the
// same checks, so that the probe predicts the shot's re-render.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "image/frame_image.h"
#include "postproc/filters/direct_emission.h"
#include "postproc/interpolation/caustic_check.h"
#include "postproc/interpolation/radiance_check.h"

namespace pathfarm {

struct InBetweenChecks {
  std::vector<uint8_t> mismatch, lightEdges, lightMismatch, caustics;  // a byte per pixel, 1 = flagged
};

// `interpolated` carries `features`' directly seen light (`directLight`, directEmissionOf).
InBetweenChecks checkInBetween(const FrameImage& interpolated, const FrameImage& features,
                               const FrameImage& directLight);

// How many pixels away from a flagged pixel the checks read.
inline int inBetweenChecksReach() {
  return std::max({radianceCheckReach(RadianceCheckSettings{}), causticCheckReach(CausticCheckSettings{}), kLightEdgeReach});
}

}  // namespace pathfarm
