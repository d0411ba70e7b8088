#include <cmath>

#include "renderer/scene/scene_parsers.h"

namespace pathfarm {
namespace {

Vec3f parseScale(const JsonNode& node) {
  const float limit = 1e6f;
  if (node.isNumber()) {
    const auto s = static_cast<float>(node.number(-limit, limit));
    if (s == 0) node.fail("a scale of 0 collapses the object");
    return {s, s, s};
  }
  const Vec3f s = node.vec3(-limit, limit);
  if (s.x == 0 || s.y == 0 || s.z == 0) node.fail("a scale of 0 collapses the object");
  return s;
}

double parseKeyTime(const JsonNode& key, double fps) {
  if (key.has("time") == key.has("frame")) key.fail("a key needs exactly one of \"time\" or \"frame\"");
  if (key.has("time")) return key["time"].number(-1e9, 1e9);
  return key["frame"].number(-1e9, 1e9) / fps;
}

// Reads a track's keys, checking that times strictly increase.
template <class T, class ReadValue>
std::vector<Keyframe<T>> parseTrack(const JsonNode& track, double fps, ReadValue readValue) {
  std::vector<Keyframe<T>> keys;
  for (const JsonNode& key : track.elements()) {
    const double time = parseKeyTime(key, fps);
    if (!keys.empty() && time <= keys.back().time)
      key.fail("key times must increase strictly");
    keys.push_back({time, readValue(key)});
  }
  if (keys.empty()) track.fail("a track needs at least one key");
  return keys;
}

}  // namespace

Quaternion parseRotation(const JsonNode& node) {
  if (node.has("quaternion")) {
    node.expectKeys({"quaternion", "time", "frame"});
    const auto q = node["quaternion"].numbers(4);
    const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (norm < 1e-6) node["quaternion"].fail("a rotation quaternion must not be zero");
    return Quaternion{static_cast<float>(q[0]), static_cast<float>(q[1]),
                      static_cast<float>(q[2]), static_cast<float>(q[3])}
        .normalized();
  }
  node.expectKeys({"axis", "angle", "time", "frame"});
  const Vec3f axis = node["axis"].vec3(-1e6f, 1e6f);
  if (length(axis) < 1e-6f) node["axis"].fail("the rotation axis must not be zero");
  const auto degrees = static_cast<float>(node["angle"].number(-1e6, 1e6));
  return Quaternion::fromAxisAngle(axis, degrees * kPi / 180.0f);
}

Trs parseTrs(const JsonNode& node) {
  node.expectKeys({"translate", "rotate", "scale"});
  Trs trs;
  if (auto t = node.optional("translate")) trs.translation = t->vec3(-kMaxCoordinate, kMaxCoordinate);
  if (auto r = node.optional("rotate")) trs.rotation = parseRotation(*r);
  if (auto s = node.optional("scale")) trs.scale = parseScale(*s);
  return trs;
}

void parseAnimation(const JsonNode& node, double fps, AnimatedTrs& animation) {
  node.expectKeys({"translate", "rotate", "scale"});
  if (auto track = node.optional("translate")) {
    animation.setTranslationKeys(parseTrack<Vec3f>(*track, fps, [](const JsonNode& key) {
      key.expectKeys({"time", "frame", "value"});
      return key["value"].vec3(-kMaxCoordinate, kMaxCoordinate);
    }));
  }
  if (auto track = node.optional("rotate")) {
    animation.setRotationKeys(parseTrack<Quaternion>(*track, fps, parseRotation));
  }
  if (auto track = node.optional("scale")) {
    animation.setScaleKeys(parseTrack<Vec3f>(*track, fps, [](const JsonNode& key) {
      key.expectKeys({"time", "frame", "value"});
      return parseScale(key["value"]);
    }));
  }
}

}  // namespace pathfarm
