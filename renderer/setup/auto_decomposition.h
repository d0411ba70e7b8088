#pragma once
// `auto`: the decomposition a scene needs, and no more (Zimmer et al. 2015 route paths
// into components the scene can actually produce). Diffuse components always; a
// reflection component only with lobes that count as specular reflection; a
// transmission component only with lobes that count as specular transmission; and a
// deeper one (ETTTTD.*, light through both walls of glass twice) when a cheap
// low-resolution probe render shows such paths carry a noticeable share of the energy.
#include <string>

#include "renderer/decomposition/decomposition.h"
#include "renderer/scene/scene.h"

namespace pathfarm {

struct AutoDecompositionSettings {
  int probeWidth = 48, probeHeight = 32, probeSpp = 4;
  int64_t probeFrame = 0;
  double deepShareThreshold = 0.01;  // of the probe's total luminance
};

Decomposition chooseDecomposition(const Scene& scene, const AutoDecompositionSettings& settings = {});

// "none" (nullptr), "default", "auto" or "name=EXPR,...". Throws std::invalid_argument.
std::shared_ptr<const Decomposition> decompositionFor(const Scene& scene, const std::string& spec);

}  // namespace pathfarm
