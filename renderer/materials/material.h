#pragma once
// A material as the scene describes it: the kind of BSDF and its parameters.
// Bsdf (bsdf.h) turns it into something that can be evaluated and sampled at a hit.
#include <string_view>

#include "renderer/math/vecmath.h"

namespace pathfarm {

enum class MaterialType {
  Diffuse,          // Lambertian
  Conductor,        // smooth metal: a perfect mirror with conductor Fresnel
  RoughConductor,   // microfacet metal
  Dielectric,       // smooth glass: Fresnel-weighted mirror reflection and refraction
  RoughDielectric,  // microfacet glass (Walter et al. 2007)
  Plastic,          // smooth dielectric coating over a diffuse base (as in Mitsuba)
  RoughPlastic,     // microfacet coating over a diffuse base
  // glTF 2.0 pbrMetallicRoughness with KHR_materials_transmission and KHR_materials_ior:
  // GGX metal mixed with a GGX-coated diffuse and thin-walled transmission
  // (metallic_roughness.h).
  MetallicRoughness,
};

enum class MicrofacetType { GGX, Beckmann };

struct Material {
  MaterialType type = MaterialType::Diffuse;
  // Diffuse albedo (Diffuse, Plastic, RoughPlastic); replaced by the texture when one is set.
  // MetallicRoughness: the base colour (glTF baseColorFactor, linear), multiplied by the
  // texture (baseColorTexture, sRGB-decoded) when one is set.
  Rgb reflectance{0.5f};
  int reflectanceTexture = -1;  // index into Scene::textures, -1 for none
  // Conductors: complex index of refraction eta + i k per channel, or, when
  // useSpecularColor is set, Schlick's approximation with specularColor at normal incidence.
  Rgb eta{0.2f, 0.92f, 1.1f};
  Rgb k{3.9f, 2.45f, 2.14f};
  bool useSpecularColor = false;
  Rgb specularColor{1.0f};
  // Dielectrics and plastic coatings: interior index of refraction (exterior is 1).
  // MetallicRoughness: the dielectric part's index (KHR_materials_ior).
  float ior = 1.5f;
  // Rough materials.
  MicrofacetType distribution = MicrofacetType::GGX;
  float alpha = 0.1f;
  // MetallicRoughness (glTF metallicFactor, roughnessFactor, metallicRoughnessTexture and
  // KHR_materials_transmission's transmissionFactor). Roughness is perceptual: GGX
  // alpha = roughness^2. The texture holds linear data, metal in B and roughness in G,
  // multiplied by the factors.
  float metallic = 1;
  float roughness = 1;
  int metallicRoughnessTexture = -1;  // index into Scene::textures, -1 for none
  float transmission = 0;
  // KHR_materials_specular's specularFactor and specularColorFactor: the dielectric part's
  // reflectance goes from specular * min(specularColor F0, 1) at normal incidence to
  // `specular` at grazing (metallic_roughness.h).
  float specular = 1;
  Rgb dielectricSpecularColor{1.0f};
  // KHR_materials_transmission's transmissionTexture: linear, its R scales `transmission`.
  int transmissionTexture = -1;  // index into Scene::textures, -1 for none
  // A tangent-space normal map (linear data) and the scale of its x and y (any type).
  int normalTexture = -1;
  float normalScale = 1;
  // Partial coverage (cut-outs): index into Scene::coverages, -1 for an opaque surface.
  int coverage = -1;
};

// The papers' vertex symbols (Zimmer et al. 2015): D diffuse, R specular or glossy
// reflection, T specular or glossy transmission. A glossy lobe counts as R or T only
// when its roughness is below the scene's threshold (Beckmann alpha < 0.1 by default).
enum class LobeSymbol : unsigned char { D, R, T };

char lobeSymbolChar(LobeSymbol symbol);
std::string_view materialTypeName(MaterialType type);

}  // namespace pathfarm
