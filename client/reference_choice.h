#pragma once
// "reference_spp": "auto" (docs/shot-format.md): the reference's samples chosen so that its
// own noise is at most a tenth of the error the shot is expected to reach. When auto's
// probe predicted that error, a pilot render's variance gives plain pt's relMSE per
// sample and so the samples that bring the reference's noise to a tenth of it. Otherwise
// the error is taken as the share of pt's (at the shot's spp) that the pipeline's family
// typically reaches on the moving-camera suite, and pt's variance cancels out: the
// reference takes 10 / share times the shot's samples.
#include <string>

#include "pathfarm/shot.pb.h"

namespace pathfarm {
struct Scene;
}

namespace pathfarm::farm {

// What a spec's reference_spp holds until the client has chosen it; the planner refuses it.
inline constexpr int kAutoReferenceSpp = -1;
// The most samples "auto" gives a reference; the report says when that cannot resolve an error.
inline constexpr int kMaxAutoReferenceSpp = 1 << 16;

// The spec with an "auto" reference_spp chosen (and reference_reason saying why); any
// other spec as it is.
ShotSpec withReferenceChosen(ShotSpec spec, const Scene& scene);

// The spp whose reference noise is a tenth of `smallestError`, for pt's relMSE at one
// sample per pixel `relMsePerSample`: a power of two from the shot's spp to
// kMaxAutoReferenceSpp.
int resolvingReferenceSpp(double relMsePerSample, double smallestError, int shotSpp);

}  // namespace pathfarm::farm
