#include "client/reference_choice.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>

#include "client/reference_pilot.h"
#include "contract/pipeline.h"

namespace pathfarm::farm {
namespace {

// The error a pipeline of each family reaches against pt's at the same spp, as the
// moving-camera suite measured it (docs/performance.md, "Figures with their intervals"):
// the filtering pipelines' median about 1/16 of pt's (from 1/7 on the dolly to 1/80 on the
// courtyard), gradient-domain about 1/5; Metropolis and pt itself are taken at pt's. A
// shot that does better than its family's median gets a reference that resolves its error
// only coarsely, and its report says so and which spp would resolve it.
double typicalErrorShare(Pipeline pipeline) {
  switch (traitsOf(pipeline).family) {
    case PipelineFamily::Filtering:
      return 1.0 / 16;
    case PipelineFamily::Gradient:
      return 1.0 / 5;
    default:
      return 1;
  }
}

std::string figure(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

}  // namespace

int resolvingReferenceSpp(double relMsePerSample, double smallestError, int shotSpp) {
  const double needed = 10 * relMsePerSample / smallestError;
  int spp = 1;
  while (spp < std::max<double>(needed, shotSpp) && spp < kMaxAutoReferenceSpp) spp *= 2;
  return spp;
}

ShotSpec withReferenceChosen(ShotSpec spec, const Scene& scene) {
  if (spec.reference_spp() != kAutoReferenceSpp) return spec;
  const std::string pipeline(pipelineName(spec.pipeline()));
  std::string reason = "reference_spp \"auto\": ";
  int spp = 0;
  if (spec.predicted_relmse() > 0) {
    // The probe predicted the error in absolute terms: the pilot says what pt's relMSE per
    // sample is, and so how many samples bring the reference's noise to a tenth of it.
    const int64_t frame = spec.evaluation_frames().empty() ? spec.frame_start() : spec.evaluation_frames(0);
    const double perSample = pilotRelMsePerSample(scene, spec, frame);
    spp = resolvingReferenceSpp(perSample, spec.predicted_relmse(), spec.spp());
    reason += "a " + std::to_string(kPilotSpp) + "-spp pilot of frame " + std::to_string(frame) +
              " at a quarter of the size puts pt's relMSE per sample at " + figure("%.4f", perSample) +
              "; a tenth of the probe's predicted error for " + pipeline + ", " +
              figure("%.5f", spec.predicted_relmse()) + ", takes " + std::to_string(spp) + " spp";
  } else {
    // Against a share of pt's error at the shot's spp, pt's own variance cancels out: the
    // reference needs 10 / share times the shot's samples, whatever the scene.
    const double share = typicalErrorShare(spec.pipeline());
    spp = resolvingReferenceSpp(1, share / spec.spp(), spec.spp());
    reason += (share < 1 ? pipeline + "'s error is typically " + figure("%.3g", share) +
                               " of pt's at the same spp on the suite; a tenth of that takes "
                         : "the error to resolve is pt's at the shot's spp; a tenth of it takes ") +
              std::to_string(static_cast<int>(10 * spec.spp() / share)) + " spp, so " + std::to_string(spp);
  }
  if (spp == kMaxAutoReferenceSpp) reason += " (the most auto gives)";
  spec.set_reference_spp(spp);
  spec.set_reference_reason(reason);
  spdlog::info("{}", reason);
  return spec;
}

}  // namespace pathfarm::farm
