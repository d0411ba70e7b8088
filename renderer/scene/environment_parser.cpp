// "environment": {"radiance": RGB} or {"map": FILE, "strength": s, "rotation": degrees}
// (docs/scene-format.md). Maps are Radiance .hdr (stb_image) or OpenEXR .exr files.
#include <stb_image.h>

#include <memory>
#include <stdexcept>
#include <string>

#include "image/exr_io.h"
#include "renderer/scene/scene_inputs.h"
#include "renderer/scene/scene_parsers.h"

namespace pathfarm {
namespace {

struct MapImage {
  int width = 0, height = 0;
  std::vector<Rgb> texels;  // top row first
};

struct StbFree {
  void operator()(void* p) const { stbi_image_free(p); }
};

MapImage readHdr(const std::filesystem::path& file) {
  const std::string name = file.string();
  MapImage image;
  int channels = 0;
  std::unique_ptr<float, StbFree> data(stbi_loadf(name.c_str(), &image.width, &image.height, &channels, 3));
  if (!data) {
    const char* reason = stbi_failure_reason();
    throw std::runtime_error(name + ": cannot load image (" + (reason ? reason : "unknown reason") + ")");
  }
  const size_t n = static_cast<size_t>(image.width) * static_cast<size_t>(image.height);
  const float* p = data.get();
  for (size_t i = 0; i < n; ++i) image.texels.emplace_back(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
  return image;
}

MapImage readExrMap(const std::filesystem::path& file) {
  const FrameImage frame = readExr(file);
  MapImage image{frame.width(), frame.height(), {}};
  const bool grey = !frame.hasChannel("R") && frame.hasChannel("Y");
  if (!grey && !(frame.hasChannel("R") && frame.hasChannel("G") && frame.hasChannel("B")))
    throw std::runtime_error(file.string() + ": expected channels R, G, B (or Y)");
  const auto& r = frame.channel(grey ? "Y" : "R");
  const auto& g = frame.channel(grey ? "Y" : "G");
  const auto& b = frame.channel(grey ? "Y" : "B");
  for (size_t i = 0; i < frame.pixelCount(); ++i) image.texels.emplace_back(r[i], g[i], b[i]);
  return image;
}

EnvironmentLight parseMap(const JsonNode& node, const std::filesystem::path& folder) {
  const JsonNode fileNode = node["map"];
  const std::filesystem::path file = folder / fileNode.string();
  const float strength = node.has("strength") ? static_cast<float>(node["strength"].number(0, 1e9)) : 1.0f;
  const float rotation = node.has("rotation") ? static_cast<float>(node["rotation"].number(-36000, 36000)) : 0.0f;
  noteSceneInput(file);
  try {
    const std::string extension = file.extension().string();
    MapImage image;
    if (extension == ".exr" || extension == ".EXR") {
      image = readExrMap(file);
    } else if (stbi_is_hdr(file.string().c_str())) {
      image = readHdr(file);
    } else if (!std::filesystem::exists(file)) {
      throw std::runtime_error(file.string() + ": no such file");
    } else {
      throw std::runtime_error(file.string() + ": not a Radiance .hdr or OpenEXR .exr image");
    }
    return EnvironmentLight(image.width, image.height, std::move(image.texels), strength, rotation);
  } catch (const std::exception& e) {
    fileNode.fail(e.what());
  }
}

}  // namespace

EnvironmentLight parseEnvironment(const JsonNode& node, const std::filesystem::path& folder) {
  node.expectKeys({"radiance", "map", "strength", "rotation"});
  if (node.has("radiance") && node.has("map")) node.fail("give either radiance or map, not both");
  if (node.has("radiance")) {
    if (node.has("strength") || node.has("rotation")) node.fail("strength and rotation apply to a map only");
    return EnvironmentLight(node["radiance"].rgb(0, 1e9));
  }
  if (!node.has("map")) node.fail("expected radiance or map");
  return parseMap(node, folder);
}

}  // namespace pathfarm
