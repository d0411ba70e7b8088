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

// Mitsuba's plugin names, so scene files and logs read the same as in the papers' setups.
std::string_view materialTypeName(MaterialType type) {
  switch (type) {
    case MaterialType::Conductor: return "conductor";
    case MaterialType::RoughConductor: return "roughconductor";
    case MaterialType::Dielectric: return "dielectric";
    case MaterialType::RoughDielectric: return "roughdielectric";
    case MaterialType::Plastic: return "plastic";
    case MaterialType::RoughPlastic: return "roughplastic";
    case MaterialType::Diffuse: break;
  }
  return "diffuse";
}

}  // namespace pathfarm
