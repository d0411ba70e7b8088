// "lights": punctual lights in JSON scenes (docs/scene-format.md, punctual_light.h).
#include <cmath>

#include "renderer/scene/scene_parsers.h"

namespace pathfarm {
namespace {

constexpr float kMaxIntensity = 1e12f;

// The rotation that turns a light's local -z onto `direction`.
Quaternion aimedAlong(Vec3f direction) {
  const Vec3f z = -normalize(direction);
  const Vec3f up = std::abs(z.y) < 0.999f ? Vec3f{0, 1, 0} : Vec3f{1, 0, 0};
  const Vec3f x = normalize(cross(up, z));
  return Quaternion::fromBasis(x, cross(z, x), z);
}

PunctualType parsePunctualType(const JsonNode& node) {
  const std::string type = node.string();
  if (type == "point") return PunctualType::Point;
  if (type == "spot") return PunctualType::Spot;
  if (type == "directional") return PunctualType::Directional;
  node.fail("unknown light type \"" + type + "\" (expected point, spot or directional)");
}

Trs parseRestPlacement(const JsonNode& node) {
  if (node.has("transform")) {
    if (node.has("position") || node.has("direction"))
      node.fail("give either \"transform\" or \"position\"/\"direction\", not both");
    return parseTrs(node["transform"]);
  }
  Trs rest;
  if (auto position = node.optional("position")) rest.translation = position->vec3(-kMaxCoordinate, kMaxCoordinate);
  if (auto direction = node.optional("direction")) {
    const Vec3f d = direction->vec3(-kMaxCoordinate, kMaxCoordinate);
    if (!(length(d) > 1e-6f)) direction->fail("the direction must not be zero");
    rest.rotation = aimedAlong(d);
  }
  return rest;
}

}  // namespace

PunctualLight parsePunctualLight(const JsonNode& node, double fps) {
  node.expectKeys({"name", "type", "intensity", "position", "direction", "transform", "animation", "inner_cone",
                   "outer_cone"});
  PunctualLight light;
  if (auto name = node.optional("name")) light.name = name->string();
  light.type = parsePunctualType(node["type"]);
  light.intensity = node["intensity"].rgb(0, kMaxIntensity);
  if (light.type == PunctualType::Spot) {
    const double inner = node.has("inner_cone") ? node["inner_cone"].number(0, 90) : 0;
    const double outer = node.has("outer_cone") ? node["outer_cone"].number(0, 90) : 45;
    if (!(outer > 0)) node["outer_cone"].fail("the outer cone must be wider than 0 degrees");
    if (!(inner < outer)) node["inner_cone"].fail("the inner cone must be narrower than the outer cone");
    light.cosInner = static_cast<float>(std::cos(inner * kPi / 180));
    light.cosOuter = static_cast<float>(std::cos(outer * kPi / 180));
  } else if (node.has("inner_cone") || node.has("outer_cone")) {
    node.fail("only spot lights have cones");
  }
  if (light.type == PunctualType::Directional && node.has("position"))
    node["position"].fail("a directional light has no position");
  light.transform = AnimatedTrs(parseRestPlacement(node));
  if (auto animation = node.optional("animation")) parseAnimation(*animation, fps, light.transform);
  return light;
}

}  // namespace pathfarm
