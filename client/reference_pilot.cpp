#include "client/reference_pilot.h"

#include <algorithm>

#include "postproc/metrics/relmse.h"
#include "renderer/integrators/frame_renderer.h"

namespace pathfarm::farm {
namespace {

constexpr int kMinPilotSize = 16;

}  // namespace

double pilotRelMsePerSample(const Scene& scene, const ShotSpec& spec, int64_t frame) {
  RenderSettings settings;
  settings.width = std::max(kMinPilotSize, spec.width() / kPilotScale);
  settings.height = std::max(kMinPilotSize, spec.height() / kPilotScale);
  settings.spp = kPilotSpp;
  settings.maxDepth = spec.max_depth();
  settings.firstSample = kIndependentFirstSample;
  return expectedRelMse(FrameRenderer(scene, settings).render(frame)) * kPilotSpp;
}

}  // namespace pathfarm::farm
