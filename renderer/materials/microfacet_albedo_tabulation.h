#pragma once
// The nodes and the integration behind multiple_scattering.h's table: the albedo of
// single-scattering microfacet reflection with Fresnel 1, per distribution, over
// cos(theta) and roughness. Integrated once at build time with specular_albedo's table
// (tabulate_specular_albedo.cpp), on specular_albedo's nodes in cos(theta) and roughness.
#include <vector>

#include "renderer/materials/material.h"

namespace pathfarm::microfacet_albedo {

inline constexpr int kDistributions = 2;  // MicrofacetType::GGX, MicrofacetType::Beckmann

struct Table {
  std::vector<float> albedo;   // [distribution][roughness][mu]
  std::vector<float> average;  // [distribution][roughness]
};

// Integrates every node; deterministic, so the build's table and this agree bit for bit.
Table tabulate();

// The table's index of a distribution.
constexpr int distributionIndex(MicrofacetType type) { return type == MicrofacetType::GGX ? 0 : 1; }

}  // namespace pathfarm::microfacet_albedo
