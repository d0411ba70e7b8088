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

// "reflectance": [r,g,b] | grey | {"texture": "file.png"}
void parseReflectance(const JsonNode& node, const std::filesystem::path& folder,
                      std::vector<ImageTexture>& textures, Material& material) {
  if (!node.isObject()) {
    material.reflectance = node.rgb(0, 1);
    return;
  }
  node.expectKeys({"texture"});
  const JsonNode file = node["texture"];
  try {
    textures.push_back(ImageTexture::load(folder / file.string()));
  } catch (const TextureError& e) {
    file.fail(e.what());
  }
  material.reflectanceTexture = static_cast<int>(textures.size()) - 1;
}

MaterialType parseType(const JsonNode& node) {
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
  material.type = parseType(node["type"]);
  const MaterialType t = material.type;

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
