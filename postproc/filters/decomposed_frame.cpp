#include "postproc/filters/decomposed_frame.h"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "renderer/decomposition/effective_irradiance.h"

namespace pathfarm {

std::vector<std::string> decompositionComponents(const FrameImage& frame) {
  const auto found = frame.attributes().find("pathfarm.decomposition");
  if (found == frame.attributes().end()) return {};
  std::vector<std::string> names;
  std::istringstream items(found->second);
  std::string item;
  while (std::getline(items, item, ',')) {
    std::string name = item.substr(0, item.find('='));
    const auto first = name.find_first_not_of(" \t"), last = name.find_last_not_of(" \t");
    if (first == std::string::npos) continue;
    name = name.substr(first, last - first + 1);
    if (name != "residual" && std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  names.emplace_back("residual");
  return names;
}

namespace {

// Component c's expression in the frame's attribute ("" for the residual or none).
std::string expressionOf(const FrameImage& frame, const std::string& component) {
  const auto found = frame.attributes().find("pathfarm.decomposition");
  if (found == frame.attributes().end()) return "";
  std::istringstream items(found->second);
  std::string item;
  while (std::getline(items, item, ',')) {
    const size_t equals = item.find('=');
    if (equals == std::string::npos) continue;
    std::string name = item.substr(0, equals);
    name.erase(0, name.find_first_not_of(" \t"));
    name.erase(name.find_last_not_of(" \t") + 1);
    if (name == component) return item.substr(equals + 1);
  }
  return "";
}

}  // namespace

const std::vector<float>* filterCoverage(const FrameImage& frame, const std::string& component) {
  const std::string name = component + ".coverage.Y";
  if (!frame.hasChannel(name)) return nullptr;
  const std::string expression = expressionOf(frame, component);
  const size_t transmission = expression.find('T'), diffuse = expression.find('D');
  if (transmission != std::string::npos && transmission < diffuse) return nullptr;
  return &frame.channel(name);
}

void deriveIrradiance(FrameImage& frame) {
  const auto channel = [&](const std::string& name) -> std::vector<float>& {
    if (!frame.hasChannel(name)) throw std::invalid_argument("missing channel \"" + name + "\"");
    return frame.channel(name);
  };
  for (const std::string& component : decompositionComponents(frame))
    for (const char* c : {"R", "G", "B"}) {
      const std::vector<float>& color = channel(component + ".color." + c);
      const std::vector<float>& reflectance = channel(component + ".reflectance." + c);
      std::vector<float>& irradiance = channel(component + ".irradiance." + c);
      for (size_t p = 0; p < irradiance.size(); ++p) irradiance[p] = effectiveIrradiance(color[p], reflectance[p]);
    }
}

}  // namespace pathfarm
