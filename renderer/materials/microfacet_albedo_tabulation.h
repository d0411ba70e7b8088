#pragma once
// The nodes and the integration behind multiple_scattering.h's tables: the albedo of
// single-scattering microfacet reflection with Fresnel 1, per distribution, over
// cos(theta) and roughness, and that of rough dielectrics also over ior and side.
// Integrated once at build time with specular_albedo's table (tabulate_specular_albedo.cpp),
// on specular_albedo's nodes.
#include <cstddef>
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

// The rough dielectric's sides: light arriving from outside (eta = ior) or from inside
// (eta = 1 / ior).
inline constexpr int kSides = 2;
enum class Side { Entering = 0, Leaving = 1 };

// The albedo of single-scattering rough refraction and reflection (dielectric.h) as flux
// (the 1 / eta^2 of refraction undone), per distribution and side, over cos(theta),
// roughness and ior on specular_albedo's nodes: albedo [distribution][side][ior][roughness][mu],
// average [distribution][side][ior][roughness]. Deterministic, as tabulate().
Table tabulateDielectric();

// Where a distribution's side starts in tabulateDielectric()'s arrays, in rows of kMu values.
size_t dielectricRows(MicrofacetType type, Side side);

// The table's index of a distribution.
constexpr int distributionIndex(MicrofacetType type) { return type == MicrofacetType::GGX ? 0 : 1; }

}  // namespace pathfarm::microfacet_albedo
