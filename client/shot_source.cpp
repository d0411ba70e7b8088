#include "client/shot_source.h"

#include <algorithm>
#include <cctype>

#include "renderer/scene/json_node.h"

namespace pathfarm::farm {
namespace {

std::string lowercaseExtension(const std::filesystem::path& file) {
  std::string extension = file.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

bool readsAsScene(const nlohmann::json& document) {
  if (!document.is_object() || document.contains("scene")) return false;
  return document.contains("camera") || document.contains("shapes") || document.contains("include");
}

}  // namespace

bool isSceneFile(const std::filesystem::path& file) {
  const std::string extension = lowercaseExtension(file);
  if (extension == ".gltf" || extension == ".glb") return true;
  const nlohmann::json document = nlohmann::json::parse(readShotFileText(file), nullptr, false);
  return !document.is_discarded() && readsAsScene(document);
}

ShotFile loadShotSource(const std::filesystem::path& file, const nlohmann::json& keys) {
  nlohmann::json shot;
  if (isSceneFile(file)) {
    // Relative to the scene's folder, as a shot file beside it would name it.
    shot = {{"scene", file.filename().string()}};
  } else {
    const std::string text = readShotFileText(file);
    if (keys.empty()) return ShotFile::parse(text, file);  // its messages quote the file's own text
    shot = parseJsonDocument(text, file.string());
    if (!shot.is_object()) throw SceneError(file.string() + ": a shot file is a JSON object");
  }
  for (const auto& [key, value] : keys.items()) shot[key] = value;
  return ShotFile::parse(shot.dump(), file);
}

}  // namespace pathfarm::farm
