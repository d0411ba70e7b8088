#include "renderer/materials/material.h"

namespace pathfarm {

char lobeSymbolChar(LobeSymbol symbol) {
  switch (symbol) {
    case LobeSymbol::R: return 'R';
    case LobeSymbol::T: return 'T';
    case LobeSymbol::D: break;
  }
  return 'D';
}

// The `type` names of the scene format (docs/scene-format.md).
std::string_view materialTypeName(MaterialType type) {
  switch (type) {
    case MaterialType::Conductor: return "conductor";
    case MaterialType::RoughConductor: return "rough_conductor";
    case MaterialType::Dielectric: return "dielectric";
    case MaterialType::RoughDielectric: return "rough_dielectric";
    case MaterialType::Plastic: return "plastic";
    case MaterialType::RoughPlastic: return "rough_plastic";
    case MaterialType::MetallicRoughness: return "metallic_roughness";
    case MaterialType::Diffuse: break;
  }
  return "diffuse";
}

}  // namespace pathfarm
