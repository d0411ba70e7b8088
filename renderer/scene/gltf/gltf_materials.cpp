#include "renderer/scene/gltf/gltf_materials.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>

namespace pathfarm {
namespace {

// Material extensions whose parameters reach the material below.
const std::set<std::string>& understoodExtensions() {
  static const std::set<std::string> names{"KHR_materials_emissive_strength", "KHR_materials_ior",
                                           "KHR_materials_transmission"};
  return names;
}

// A number member of `object` (or `object` itself when key is null), else `fallback`.
double numberOr(const tinygltf::Value& object, const char* key, double fallback) {
  if (key && (!object.IsObject() || !object.Has(key))) return fallback;
  const tinygltf::Value& v = key ? object.Get(key) : object;
  return v.IsNumber() ? v.GetNumberAsDouble() : fallback;
}

const tinygltf::Value* extension(const tinygltf::ExtensionMap& extensions, const char* name) {
  const auto it = extensions.find(name);
  return it == extensions.end() ? nullptr : &it->second;
}

// A factor from the file, checked to be finite and within [min, max].
float factor(const GltfDocument& document, const std::string& pointer, double value, double min, double max) {
  if (!std::isfinite(value) || value < min || value > max)
    document.fail(pointer, "value " + std::to_string(value) + " is outside [" + std::to_string(min) + ", " +
                               std::to_string(max) + "]");
  return static_cast<float>(value);
}

class TextureImporter {
 public:
  TextureImporter(const GltfDocument& document, Scene& scene) : document_(document), scene_(scene) {}

  // The scene texture for glTF texture `index` decoded as sRGB colour or linear data.
  int get(int index, bool srgb, const std::string& pointer) {
    const tinygltf::Model& model = document_.model();
    if (index < 0 || static_cast<size_t>(index) >= model.textures.size())
      document_.fail(pointer + "/index", "texture " + std::to_string(index) + " does not exist");
    const tinygltf::Texture& texture = model.textures[static_cast<size_t>(index)];
    const std::string texturePointer = gltfPointer("textures", index);
    if (texture.source < 0 || static_cast<size_t>(texture.source) >= model.images.size())
      document_.fail(texturePointer + "/source", "image " + std::to_string(texture.source) + " does not exist");
    if (texture.sampler >= 0 && static_cast<size_t>(texture.sampler) < model.samplers.size()) {
      const tinygltf::Sampler& sampler = model.samplers[static_cast<size_t>(texture.sampler)];
      if ((sampler.wrapS != -1 && sampler.wrapS != TINYGLTF_TEXTURE_WRAP_REPEAT) ||
          (sampler.wrapT != -1 && sampler.wrapT != TINYGLTF_TEXTURE_WRAP_REPEAT))
        document_.warn(gltfPointer("samplers", texture.sampler),
                       "clamp and mirror wrap modes are not supported yet; the texture repeats");
    }
    const auto key = std::make_pair(texture.source, srgb);
    if (const auto it = cache_.find(key); it != cache_.end()) return it->second;
    const tinygltf::Image& image = model.images[static_cast<size_t>(texture.source)];
    const std::string imagePointer = gltfPointer("images", texture.source);
    const size_t bytes = static_cast<size_t>(std::max(image.bits, 0) / 8);
    if (image.width <= 0 || image.height <= 0 || image.component <= 0 ||
        image.image.size() != static_cast<size_t>(image.width) * static_cast<size_t>(image.height) *
                                   static_cast<size_t>(image.component) * bytes)
      document_.fail(imagePointer, "the image could not be decoded (" + image.uri + ")");
    try {
      scene_.textures.push_back(ImageTexture::fromPixels(image.width, image.height, image.component, image.bits,
                                                         image.image.data(), srgb));
    } catch (const TextureError& e) {
      document_.fail(imagePointer, e.what());
    }
    const int sceneIndex = static_cast<int>(scene_.textures.size()) - 1;
    cache_[key] = sceneIndex;
    return sceneIndex;
  }

 private:
  const GltfDocument& document_;
  Scene& scene_;
  std::map<std::pair<int, bool>, int> cache_;
};

// The TEXCOORD set and KHR_texture_transform of a texture reference (glTF 2.0 and the
// extension's specification: offset, rotation about the origin, then scale, composed as
// T * R * S).
TextureCoordinates coordinatesOf(const GltfDocument& document, const std::string& pointer, int texCoord,
                                 const tinygltf::ExtensionMap& extensions) {
  TextureCoordinates c;
  c.set = texCoord;
  if (const tinygltf::Value* t = extension(extensions, "KHR_texture_transform")) {
    const std::string p = pointer + "/extensions/KHR_texture_transform";
    const auto pair = [&](const char* key, double fallback) {
      std::array<double, 2> v{fallback, fallback};
      if (t->IsObject() && t->Has(key) && t->Get(key).IsArray() && t->Get(key).ArrayLen() == 2)
        for (int i = 0; i < 2; ++i) v[static_cast<size_t>(i)] = numberOr(t->Get(key).Get(i), nullptr, fallback);
      return v;
    };
    const auto offset = pair("offset", 0), scale = pair("scale", 1);
    const double rotation = numberOr(*t, "rotation", 0);
    const float ox = factor(document, p + "/offset", offset[0], -1e6, 1e6);
    const float oy = factor(document, p + "/offset", offset[1], -1e6, 1e6);
    const float sx = factor(document, p + "/scale", scale[0], -1e6, 1e6);
    const float sy = factor(document, p + "/scale", scale[1], -1e6, 1e6);
    const double r = factor(document, p + "/rotation", rotation, -1e6, 1e6);
    const auto cosR = static_cast<float>(std::cos(r)), sinR = static_cast<float>(std::sin(r));
    c.m = {cosR * sx, sinR * sy, ox, -sinR * sx, cosR * sy, oy};
    c.set = static_cast<int>(factor(document, p + "/texCoord", numberOr(*t, "texCoord", texCoord), 0, 1));
  }
  if (c.set != 0 && c.set != 1)
    document.fail(pointer + "/texCoord", "TEXCOORD_" + std::to_string(c.set) + " is not supported (only 0 and 1)");
  return c;
}

// What the renderer does not model yet, said once per material.
void warnAboutUnsupported(const GltfDocument& document, const std::string& pointer, const tinygltf::Material& m) {
  if (m.normalTexture.index >= 0)
    document.warn(pointer + "/normalTexture", "normal maps are not supported yet; the surface renders unbumped");
  if (m.emissiveTexture.index >= 0)
    document.warn(pointer + "/emissiveTexture",
                  "emissive textures are not supported yet; the surface emits emissiveFactor uniformly");
  if (m.alphaMode == "MASK" || m.alphaMode == "BLEND")
    document.warn(pointer + "/alphaMode", m.alphaMode + " is not supported yet; the surface renders opaque");
  for (const auto& [name, value] : m.extensions) {
    if (!understoodExtensions().count(name))
      document.warn(pointer + "/extensions/" + name, "extension not supported; its effect is ignored");
  }
  if (const tinygltf::Value* t = extension(m.extensions, "KHR_materials_transmission");
      t && t->IsObject() && t->Has("transmissionTexture"))
    document.warn(pointer + "/extensions/KHR_materials_transmission/transmissionTexture",
                  "transmission textures are not supported yet; transmissionFactor applies everywhere");
}

std::string uniqueName(const std::string& wanted, const std::vector<std::string>& taken) {
  std::string name = wanted;
  for (int suffix = 2; std::find(taken.begin(), taken.end(), name) != taken.end(); ++suffix)
    name = wanted + "#" + std::to_string(suffix);
  return name;
}

}  // namespace

int GltfMaterials::defaultMaterial(Scene& scene) {
  if (default_ < 0) {
    // glTF's default material: white, fully metallic, fully rough.
    Material material;
    material.type = MaterialType::MetallicRoughness;
    material.reflectance = Rgb(1.0f);
    scene.materialNames.push_back(uniqueName("gltf_default", scene.materialNames));
    scene.materials.push_back(material);
    default_ = static_cast<int>(scene.materials.size()) - 1;
  }
  return default_;
}

GltfMaterials importMaterials(const GltfDocument& document, Scene& scene) {
  GltfMaterials result;
  TextureImporter textures(document, scene);
  const auto& materials = document.model().materials;
  for (size_t i = 0; i < materials.size(); ++i) {
    const tinygltf::Material& m = materials[i];
    const std::string pointer = gltfPointer("materials", static_cast<int>(i));
    const tinygltf::PbrMetallicRoughness& pbr = m.pbrMetallicRoughness;
    warnAboutUnsupported(document, pointer, m);

    Material material;
    material.type = MaterialType::MetallicRoughness;
    const std::string pbrPointer = pointer + "/pbrMetallicRoughness";
    if (pbr.baseColorFactor.size() >= 3) {
      material.reflectance = Rgb(factor(document, pbrPointer + "/baseColorFactor", pbr.baseColorFactor[0], 0, 1),
                                 factor(document, pbrPointer + "/baseColorFactor", pbr.baseColorFactor[1], 0, 1),
                                 factor(document, pbrPointer + "/baseColorFactor", pbr.baseColorFactor[2], 0, 1));
    }
    material.metallic = factor(document, pbrPointer + "/metallicFactor", pbr.metallicFactor, 0, 1);
    material.roughness = factor(document, pbrPointer + "/roughnessFactor", pbr.roughnessFactor, 0, 1);
    std::optional<TextureCoordinates> coordinates;
    if (pbr.baseColorTexture.index >= 0) {
      const std::string p = pbrPointer + "/baseColorTexture";
      material.reflectanceTexture = textures.get(pbr.baseColorTexture.index, true, p);
      coordinates = coordinatesOf(document, p, pbr.baseColorTexture.texCoord, pbr.baseColorTexture.extensions);
    }
    if (pbr.metallicRoughnessTexture.index >= 0) {
      const std::string p = pbrPointer + "/metallicRoughnessTexture";
      material.metallicRoughnessTexture = textures.get(pbr.metallicRoughnessTexture.index, false, p);
      const TextureCoordinates own =
          coordinatesOf(document, p, pbr.metallicRoughnessTexture.texCoord, pbr.metallicRoughnessTexture.extensions);
      if (coordinates && !(own == *coordinates))
        document.warn(p, "reads other texture coordinates than the base colour; the base colour's apply to both");
      if (!coordinates) coordinates = own;
    }

    Rgb emission;
    if (m.emissiveFactor.size() == 3) {
      const tinygltf::Value* strengthExtension = extension(m.extensions, "KHR_materials_emissive_strength");
      const double strength = strengthExtension ? numberOr(*strengthExtension, "emissiveStrength", 1.0) : 1.0;
      const float s = factor(document, pointer + "/extensions/KHR_materials_emissive_strength/emissiveStrength",
                             strength, 0, 1e9);
      emission = Rgb(factor(document, pointer + "/emissiveFactor", m.emissiveFactor[0], 0, 1),
                     factor(document, pointer + "/emissiveFactor", m.emissiveFactor[1], 0, 1),
                     factor(document, pointer + "/emissiveFactor", m.emissiveFactor[2], 0, 1)) * s;
    }
    if (const tinygltf::Value* t = extension(m.extensions, "KHR_materials_transmission")) {
      material.transmission = factor(document, pointer + "/extensions/KHR_materials_transmission/transmissionFactor",
                                     numberOr(*t, "transmissionFactor", 0), 0, 1);
    }
    if (const tinygltf::Value* ior = extension(m.extensions, "KHR_materials_ior")) {
      material.ior = factor(document, pointer + "/extensions/KHR_materials_ior/ior", numberOr(*ior, "ior", 1.5), 1.0001,
                            10);
    }

    scene.materialNames.push_back(
        uniqueName(m.name.empty() ? "material" + std::to_string(i) : m.name, scene.materialNames));
    scene.materials.push_back(material);
    result.sceneIndex.push_back(static_cast<int>(scene.materials.size()) - 1);
    result.emission.push_back(emission);
    result.coordinates.push_back(coordinates.value_or(TextureCoordinates{}));
  }
  return result;
}

}  // namespace pathfarm
