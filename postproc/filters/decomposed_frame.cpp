#include "postproc/filters/decomposed_frame.h"

#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "renderer/decomposition/effective_irradiance.h"

namespace pathfarm {

namespace {

struct Item {
  std::string name, expression;
};

// The attribute's "name=EXPR" items in order, names trimmed ("" when there is none).
std::vector<Item> decompositionItems(const FrameImage& frame) {
  const auto found = frame.attributes().find("pathfarm.decomposition");
  if (found == frame.attributes().end()) return {};
  std::vector<Item> out;
  std::istringstream items(found->second);
  std::string item;
  while (std::getline(items, item, ',')) {
    const size_t equals = item.find('=');
    std::string name = item.substr(0, equals);
    const auto first = name.find_first_not_of(" \t"), last = name.find_last_not_of(" \t");
    if (first == std::string::npos) continue;
    out.push_back({name.substr(first, last - first + 1), equals == std::string::npos ? "" : item.substr(equals + 1)});
  }
  return out;
}

}  // namespace

std::vector<std::string> decompositionComponents(const FrameImage& frame) {
  const auto found = frame.attributes().find("pathfarm.decomposition");
  if (found == frame.attributes().end()) return {};
  std::vector<std::string> names;
  for (const Item& item : decompositionItems(frame))
    if (item.name != "residual" && std::find(names.begin(), names.end(), item.name) == names.end())
      names.push_back(item.name);
  names.emplace_back("residual");
  return names;
}

bool isSpecularComponent(const FrameImage& frame, const std::string& component) {
  const auto found = frame.attributes().find("pathfarm.specular_components");
  if (found == frame.attributes().end()) return false;
  std::istringstream names(found->second);
  std::string name;
  while (std::getline(names, name, ','))
    if (name == component) return true;
  return false;
}

const std::vector<float>* filterCoverage(const FrameImage& frame, const std::string& component) {
  const std::string name = component + ".coverage.Y";
  if (!frame.hasChannel(name)) return nullptr;
  for (const Item& item : decompositionItems(frame)) {
    if (item.name != component) continue;
    const size_t transmission = item.expression.find('T'), diffuse = item.expression.find('D');
    if (transmission != std::string::npos && transmission < diffuse) return nullptr;
    break;
  }
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
