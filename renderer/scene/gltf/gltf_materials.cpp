#include "renderer/scene/gltf/gltf_materials.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <tuple>

namespace pathfarm {
namespace {

// Material extensions whose parameters reach the material below.
const std::set<std::string>& understoodExtensions() {
  static const std::set<std::string> names{"KHR_materials_emissive_strength", "KHR_materials_ior",
                                           "KHR_materials_specular", "KHR_materials_transmission",
                                           "KHR_materials_volume"};
  return names;
}


// KHR_materials_specular's factors; its textures are not read (a warning says so).
void readSpecular(const GltfDocument& document, const std::string& pointer, const tinygltf::Value& extension,
                  Material& material) {
  material.specular = gltfFactor(document, pointer + "/specularFactor", gltfNumberOr(extension, "specularFactor", 1), 0, 1);
  if (extension.Has("specularColorFactor")) {
    const tinygltf::Value& color = extension.Get("specularColorFactor");
    if (!color.IsArray() || color.ArrayLen() != 3) document.fail(pointer + "/specularColorFactor", "a colour has three components");
    float c[3];
    for (int i = 0; i < 3; ++i) {
      const tinygltf::Value& v = color.Get(i);
      const std::string p = pointer + "/specularColorFactor/" + std::to_string(i);
      if (!v.IsNumber()) document.fail(p, "expected a number");
      c[i] = gltfFactor(document, p, v.GetNumberAsDouble(), 0, 1e6);
    }
    material.dielectricSpecularColor = Rgb(c[0], c[1], c[2]);
  }
  for (const char* texture : {"specularTexture", "specularColorTexture"})
    if (extension.Has(texture)) document.warn(pointer + "/" + texture, "not read: the factor alone applies");
}

TextureWrap wrapMode(int gltfWrap) {
  switch (gltfWrap) {
    case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE: return TextureWrap::Clamp;
    case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT: return TextureWrap::Mirror;
    default: return TextureWrap::Repeat;
  }
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
    TextureWrap wrapS = TextureWrap::Repeat, wrapT = TextureWrap::Repeat;
    if (texture.sampler >= 0) {
      if (static_cast<size_t>(texture.sampler) >= model.samplers.size())
        document_.fail(texturePointer + "/sampler", "sampler " + std::to_string(texture.sampler) + " does not exist");
      const tinygltf::Sampler& sampler = model.samplers[static_cast<size_t>(texture.sampler)];
      wrapS = wrapMode(sampler.wrapS);
      wrapT = wrapMode(sampler.wrapT);
    }
    const auto key = std::make_tuple(texture.source, srgb, wrapS, wrapT);
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
    scene_.textures.back().setWrap(wrapS, wrapT);
    const int sceneIndex = static_cast<int>(scene_.textures.size()) - 1;
    cache_[key] = sceneIndex;
    return sceneIndex;
  }

 // The coverage of glTF alphaMode MASK or BLEND: the base colour texture's alpha channel
  // (if its image has one) times the factor's alpha.
  AlphaCoverage coverage(const tinygltf::Material& m, const std::string& pointer) const {
    const tinygltf::PbrMetallicRoughness& pbr = m.pbrMetallicRoughness;
    const double factorAlpha = pbr.baseColorFactor.size() == 4 ? pbr.baseColorFactor[3] : 1.0;
    const float factorValue = gltfFactor(document_, pointer + "/pbrMetallicRoughness/baseColorFactor", factorAlpha, 0, 1);
    const auto mode = m.alphaMode == "MASK" ? AlphaCoverage::Mode::Mask : AlphaCoverage::Mode::Blend;
    const float cutoff = gltfFactor(document_, pointer + "/alphaCutoff", m.alphaCutoff, 0, 1);
    const tinygltf::Model& model = document_.model();
    if (pbr.baseColorTexture.index < 0) return AlphaCoverage(mode, cutoff, factorValue, 0, 0, {});
    // get() has checked the texture and its image already.
    const tinygltf::Texture& texture = model.textures[static_cast<size_t>(pbr.baseColorTexture.index)];
    const tinygltf::Image& image = model.images[static_cast<size_t>(texture.source)];
    if (image.component != 2 && image.component != 4) return AlphaCoverage(mode, cutoff, factorValue, 0, 0, {});
    const size_t n = static_cast<size_t>(image.width) * static_cast<size_t>(image.height);
    const size_t channels = static_cast<size_t>(image.component);
    std::vector<float> alpha(n);
    for (size_t i = 0; i < n; ++i) {
      const size_t at = i * channels + channels - 1;
      alpha[i] = image.bits == 16 ? (image.image[2 * at] | (image.image[2 * at + 1] << 8)) / 65535.0f
                                  : image.image[at] / 255.0f;
    }
    return AlphaCoverage(mode, cutoff, factorValue, image.width, image.height, std::move(alpha));
  }

 private:
  const GltfDocument& document_;
  Scene& scene_;
  std::map<std::tuple<int, bool, TextureWrap, TextureWrap>, int> cache_;
};

// The TEXCOORD set and KHR_texture_transform of a texture reference (glTF 2.0 and the
// extension's specification: offset, rotation about the origin, then scale, composed as
// T * R * S).
TextureCoordinates coordinatesOf(const GltfDocument& document, const std::string& pointer, int texCoord,
                                 const tinygltf::ExtensionMap& extensions) {
  TextureCoordinates c;
  c.set = texCoord;
  if (const tinygltf::Value* t = gltfExtension(extensions, "KHR_texture_transform")) {
    const std::string p = pointer + "/extensions/KHR_texture_transform";
    const auto pair = [&](const char* key, double fallback) {
      std::array<double, 2> v{fallback, fallback};
      if (t->IsObject() && t->Has(key) && t->Get(key).IsArray() && t->Get(key).ArrayLen() == 2)
        for (int i = 0; i < 2; ++i) v[static_cast<size_t>(i)] = gltfNumberOr(t->Get(key).Get(i), nullptr, fallback);
      return v;
    };
    const auto offset = pair("offset", 0), scale = pair("scale", 1);
    const double rotation = gltfNumberOr(*t, "rotation", 0);
    const float ox = gltfFactor(document, p + "/offset", offset[0], -1e6, 1e6);
    const float oy = gltfFactor(document, p + "/offset", offset[1], -1e6, 1e6);
    const float sx = gltfFactor(document, p + "/scale", scale[0], -1e6, 1e6);
    const float sy = gltfFactor(document, p + "/scale", scale[1], -1e6, 1e6);
    const double r = gltfFactor(document, p + "/rotation", rotation, -1e6, 1e6);
    const auto cosR = static_cast<float>(std::cos(r)), sinR = static_cast<float>(std::sin(r));
    c.m = {cosR * sx, sinR * sy, ox, -sinR * sx, cosR * sy, oy};
    c.set = static_cast<int>(gltfFactor(document, p + "/texCoord", gltfNumberOr(*t, "texCoord", texCoord), 0, 1));
  }
  if (c.set != 0 && c.set != 1)
    document.fail(pointer + "/texCoord", "TEXCOORD_" + std::to_string(c.set) + " is not supported (only 0 and 1)");
  return c;
}

// What the renderer does not model yet, said once per material.
void warnAboutUnsupported(const GltfDocument& document, const std::string& pointer, const tinygltf::Material& m) {
  for (const auto& [name, value] : m.extensions) {
    if (!understoodExtensions().count(name))
      document.warn(pointer + "/extensions/" + name, "extension not supported; its effect is ignored");
  }
}

// A textureInfo inside an extension's object (tinygltf parses those only as values): the
// texture's index, its TEXCOORD set and its own extensions.
struct ExtensionTextureInfo {
  int index = -1;
  int texCoord = 0;
  tinygltf::ExtensionMap extensions;
};

std::optional<ExtensionTextureInfo> extensionTextureInfo(const GltfDocument& document, const std::string& pointer,
                                                         const tinygltf::Value& extension, const char* key) {
  if (!extension.IsObject() || !extension.Has(key)) return std::nullopt;
  const tinygltf::Value& info = extension.Get(key);
  if (!info.IsObject()) document.fail(pointer, "must be a textureInfo object");
  ExtensionTextureInfo result;
  result.index = static_cast<int>(gltfFactor(document, pointer + "/index", gltfNumberOr(info, "index", -1), 0, 1e9));
  result.texCoord = static_cast<int>(gltfFactor(document, pointer + "/texCoord", gltfNumberOr(info, "texCoord", 0), 0, 1e9));
  if (info.Has("extensions") && info.Get("extensions").IsObject()) {
    const tinygltf::Value& extensions = info.Get("extensions");
    for (const std::string& name : extensions.Keys()) result.extensions[name] = extensions.Get(name);
  }
  return result;
}

// KHR_materials_volume makes a transmissive surface the boundary of a solid: light
// refracts into it and out again. A fully transmissive non-metal becomes pathfarm's
// (rough) dielectric; the volume's attenuation and a tinted base colour are not modelled.
void solidDielectric(const GltfDocument& document, const std::string& pointer, Material& material) {
  const std::string p = pointer + "/extensions/KHR_materials_volume";
  if (material.transmission < 1 || material.transmissionTexture >= 0 || material.metallic > 0 ||
      material.metallicRoughnessTexture >= 0) {
    document.warn(p, "a volume is rendered only for fully transmissive non-metals; this surface stays thin-walled");
    return;
  }
  if (material.reflectance.r < 1 || material.reflectance.g < 1 || material.reflectance.b < 1 ||
      material.reflectanceTexture >= 0)
    document.warn(p, "the base colour's tint of a solid is not rendered; it refracts untinted");
  const float alpha = material.roughness * material.roughness;
  material.type = alpha < 1e-3f ? MaterialType::Dielectric : MaterialType::RoughDielectric;
  material.alpha = alpha;
  material.distribution = MicrofacetType::GGX;
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
      material.reflectance = Rgb(gltfFactor(document, pbrPointer + "/baseColorFactor", pbr.baseColorFactor[0], 0, 1),
                                 gltfFactor(document, pbrPointer + "/baseColorFactor", pbr.baseColorFactor[1], 0, 1),
                                 gltfFactor(document, pbrPointer + "/baseColorFactor", pbr.baseColorFactor[2], 0, 1));
    }
    material.metallic = gltfFactor(document, pbrPointer + "/metallicFactor", pbr.metallicFactor, 0, 1);
    material.roughness = gltfFactor(document, pbrPointer + "/roughnessFactor", pbr.roughnessFactor, 0, 1);
    std::optional<TextureCoordinates> coordinates;
    if (pbr.baseColorTexture.index >= 0) {
      const std::string p = pbrPointer + "/baseColorTexture";
      material.reflectanceTexture = textures.get(pbr.baseColorTexture.index, true, p);
      coordinates = coordinatesOf(document, p, pbr.baseColorTexture.texCoord, pbr.baseColorTexture.extensions);
    }
    // Every texture of a material reads one set of coordinates (the mesh holds one uv per
    // vertex): the first texture's, the base colour's when there is one.
    const auto shareCoordinates = [&](const std::string& p, const auto& info) {
      const TextureCoordinates own = coordinatesOf(document, p, info.texCoord, info.extensions);
      if (!coordinates) {
        coordinates = own;
      } else if (!(own == *coordinates)) {
        document.warn(p, "reads other texture coordinates than the base colour; the base colour's apply to both");
      }
    };
    if (pbr.metallicRoughnessTexture.index >= 0) {
      const std::string p = pbrPointer + "/metallicRoughnessTexture";
      material.metallicRoughnessTexture = textures.get(pbr.metallicRoughnessTexture.index, false, p);
      shareCoordinates(p, pbr.metallicRoughnessTexture);
    }

    if (m.alphaMode == "MASK" || m.alphaMode == "BLEND") {
      scene.coverages.push_back(textures.coverage(m, pointer));
      material.coverage = static_cast<int>(scene.coverages.size()) - 1;
    } else if (!m.alphaMode.empty() && m.alphaMode != "OPAQUE") {
      document.fail(pointer + "/alphaMode", "unknown alpha mode \"" + m.alphaMode + "\"");
    }
    if (m.normalTexture.index >= 0) {
      const std::string p = pointer + "/normalTexture";
      material.normalTexture = textures.get(m.normalTexture.index, false, p);
      material.normalScale = gltfFactor(document, p + "/scale", m.normalTexture.scale, -100, 100);
      shareCoordinates(p, m.normalTexture);
    }

    Rgb emission;
    if (m.emissiveFactor.size() == 3) {
      const tinygltf::Value* strengthExtension = gltfExtension(m.extensions, "KHR_materials_emissive_strength");
      const double strength = strengthExtension ? gltfNumberOr(*strengthExtension, "emissiveStrength", 1.0) : 1.0;
      const float s = gltfFactor(document, pointer + "/extensions/KHR_materials_emissive_strength/emissiveStrength",
                             strength, 0, 1e9);
      emission = Rgb(gltfFactor(document, pointer + "/emissiveFactor", m.emissiveFactor[0], 0, 1),
                     gltfFactor(document, pointer + "/emissiveFactor", m.emissiveFactor[1], 0, 1),
                     gltfFactor(document, pointer + "/emissiveFactor", m.emissiveFactor[2], 0, 1)) * s;
    }
    int emissionTexture = -1;
    if (m.emissiveTexture.index >= 0 && !emission.isBlack()) {
      const std::string p = pointer + "/emissiveTexture";
      emissionTexture = textures.get(m.emissiveTexture.index, true, p);
      shareCoordinates(p, m.emissiveTexture);
    }
    if (const tinygltf::Value* t = gltfExtension(m.extensions, "KHR_materials_transmission")) {
      const std::string p = pointer + "/extensions/KHR_materials_transmission";
      material.transmission = gltfFactor(document, p + "/transmissionFactor", gltfNumberOr(*t, "transmissionFactor", 0), 0, 1);
      const std::string texturePointer = p + "/transmissionTexture";
      if (const auto info = extensionTextureInfo(document, texturePointer, *t, "transmissionTexture");
          info && material.transmission > 0) {
        material.transmissionTexture = textures.get(info->index, false, texturePointer);
        shareCoordinates(texturePointer, *info);
      }
    }
    if (const tinygltf::Value* ior = gltfExtension(m.extensions, "KHR_materials_ior")) {
      // 1 is air (nothing reflects or bends); the extension's other special value, 0, is
      // refused by the range.
      material.ior = gltfFactor(document, pointer + "/extensions/KHR_materials_ior/ior", gltfNumberOr(*ior, "ior", 1.5), 1, 3);
    }
    if (const tinygltf::Value* specular = gltfExtension(m.extensions, "KHR_materials_specular"))
      readSpecular(document, pointer + "/extensions/KHR_materials_specular", *specular, material);
    if (gltfExtension(m.extensions, "KHR_materials_volume")) solidDielectric(document, pointer, material);

    scene.materialNames.push_back(
        uniqueName(m.name.empty() ? "material" + std::to_string(i) : m.name, scene.materialNames));
    scene.materials.push_back(material);
    result.sceneIndex.push_back(static_cast<int>(scene.materials.size()) - 1);
    result.emission.push_back(emission);
    result.emissionTexture.push_back(emissionTexture);
    result.coordinates.push_back(coordinates.value_or(TextureCoordinates{}));
  }
  return result;
}

}  // namespace pathfarm
