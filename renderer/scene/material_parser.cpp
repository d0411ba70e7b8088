#include <map>

#include "renderer/scene/scene_parsers.h"

namespace pathfarm {
namespace {

const std::map<std::string, MaterialType>& materialTypes() {
  static const std::map<std::string, MaterialType> types{
      {"diffuse", MaterialType::Diffuse},
      {"conductor", MaterialType::Conductor},
      {"rough_conductor", MaterialType::RoughConductor},
      {"dielectric", MaterialType::Dielectric},
      {"rough_dielectric", MaterialType::RoughDielectric},
      {"plastic", MaterialType::Plastic},
      {"rough_plastic", MaterialType::RoughPlastic},
      {"metallic_roughness", MaterialType::MetallicRoughness},
  };
  return types;
}

bool isRough(MaterialType t) {
  return t == MaterialType::RoughConductor || t == MaterialType::RoughDielectric ||
         t == MaterialType::RoughPlastic;
}
bool hasDiffuseBase(MaterialType t) {
  return t == MaterialType::Diffuse || t == MaterialType::Plastic ||
         t == MaterialType::RoughPlastic;
}
bool isConductor(MaterialType t) {
  return t == MaterialType::Conductor || t == MaterialType::RoughConductor;
}
bool hasIor(MaterialType t) { return !isConductor(t) && t != MaterialType::Diffuse; }

// Index of the texture `file` names, loaded into `textures`.
int loadTexture(const JsonNode& file, const std::filesystem::path& folder, std::vector<ImageTexture>& textures,
                TextureEncoding encoding) {
  try {
    textures.push_back(ImageTexture::load(folder / file.string(), encoding));
  } catch (const TextureError& e) {
    file.fail(e.what());
  }
  return static_cast<int>(textures.size()) - 1;
}

// "reflectance" (or a metallic_roughness material's "base_color"):
// [r,g,b] | grey | {"texture": "file.png"}
void parseReflectance(const JsonNode& node, const std::filesystem::path& folder,
                      std::vector<ImageTexture>& textures, Material& material) {
  if (!node.isObject()) {
    material.reflectance = node.rgb(0, 1);
    return;
  }
  node.expectKeys({"texture"});
  material.reflectanceTexture = loadTexture(node["texture"], folder, textures, TextureEncoding::Srgb);
}

// glTF's pbrMetallicRoughness (+ transmission, ior, specular). The base colour texture, as in glTF,
// multiplies a factor that stays 1 unless given: {"texture": ...} alone means factor 1.
void parseMetallicRoughness(const JsonNode& node, const std::filesystem::path& folder,
                            std::vector<ImageTexture>& textures, Material& material) {
  node.expectKeys({"type", "base_color", "metallic", "roughness", "metallic_roughness_texture", "transmission",
                   "ior", "specular", "specular_color"});
  material.reflectance = Rgb(1);
  if (auto color = node.optional("base_color")) parseReflectance(*color, folder, textures, material);
  if (auto metallic = node.optional("metallic")) material.metallic = static_cast<float>(metallic->number(0, 1));
  if (auto roughness = node.optional("roughness")) material.roughness = static_cast<float>(roughness->number(0, 1));
  if (auto t = node.optional("transmission")) material.transmission = static_cast<float>(t->number(0, 1));
  // The BSDF's tabulated specular albedo covers [1, 3] (specular_albedo.h); glTF's
  // KHR_materials_ior allows 1 (no reflection) and real materials stay below 2.5.
  if (auto ior = node.optional("ior")) material.ior = static_cast<float>(ior->number(1, 3));
  if (auto specular = node.optional("specular")) material.specular = static_cast<float>(specular->number(0, 1));
  if (auto color = node.optional("specular_color")) material.dielectricSpecularColor = color->rgb(0, 1e6);
  if (auto texture = node.optional("metallic_roughness_texture")) {
    material.metallicRoughnessTexture = loadTexture(*texture, folder, textures, TextureEncoding::Linear);
  }
}

MaterialType parseMaterialType(const JsonNode& node) {
  const std::string name = node.string();
  const auto it = materialTypes().find(name);
  if (it == materialTypes().end()) {
    std::string list;
    for (const auto& [known, type] : materialTypes()) list += (list.empty() ? "" : ", ") + known;
    node.fail("unknown material type \"" + name + "\" (expected one of: " + list + ")");
  }
  return it->second;
}

}  // namespace

Material parseMaterial(const JsonNode& node, const std::filesystem::path& folder,
                       std::vector<ImageTexture>& textures) {
  Material material;
  material.type = parseMaterialType(node["type"]);
  const MaterialType t = material.type;
  if (t == MaterialType::MetallicRoughness) {
    parseMetallicRoughness(node, folder, textures, material);
    return material;
  }

  std::vector<const char*> keys{"type"};
  if (hasDiffuseBase(t)) keys.push_back("reflectance");
  if (hasIor(t)) keys.push_back("ior");
  if (isRough(t)) keys.insert(keys.end(), {"alpha", "distribution"});
  if (isConductor(t)) keys.insert(keys.end(), {"eta", "k", "specular_color"});
  node.expectKeys(keys);

  if (auto r = node.optional("reflectance")) parseReflectance(*r, folder, textures, material);
  if (auto ior = node.optional("ior")) {
    material.ior = static_cast<float>(ior->number(1.0001, 10));
  }
  if (auto alpha = node.optional("alpha")) {
    material.alpha = static_cast<float>(alpha->number(1e-4, 4));
  }
  if (auto d = node.optional("distribution")) {
    const std::string name = d->string();
    if (name == "ggx") {
      material.distribution = MicrofacetType::GGX;
    } else if (name == "beckmann") {
      material.distribution = MicrofacetType::Beckmann;
    } else {
      d->fail("unknown microfacet distribution \"" + name + "\" (expected ggx or beckmann)");
    }
  }
  if (auto color = node.optional("specular_color")) {
    if (node.has("eta") || node.has("k"))
      color->fail("give either specular_color or eta and k, not both");
    material.useSpecularColor = true;
    material.specularColor = color->rgb(0, 1);
  } else if (node.has("eta") != node.has("k")) {
    node.fail("a conductor's complex index of refraction needs both eta and k");
  } else if (node.has("eta")) {
    material.eta = node["eta"].rgb(1e-4f, 100);
    material.k = node["k"].rgb(0, 100);
  }
  return material;
}

}  // namespace pathfarm
