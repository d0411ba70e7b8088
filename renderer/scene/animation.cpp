#include "renderer/scene/animation.h"

#include <algorithm>

namespace pathfarm {
namespace {

Vec3f interpolate(const Vec3f& a, const Vec3f& b, float t) { return lerp(a, b, t); }
Quaternion interpolate(const Quaternion& a, const Quaternion& b, float t) { return slerp(a, b, t); }

template <class T>
T evaluate(const std::vector<Keyframe<T>>& keys, const T& rest, double time) {
  if (keys.empty()) return rest;
  if (time <= keys.front().time) return keys.front().value;
  if (time >= keys.back().time) return keys.back().value;
  const auto next = std::upper_bound(keys.begin(), keys.end(), time,
                                     [](double t, const Keyframe<T>& k) { return t < k.time; });
  const auto prev = next - 1;
  const auto t = static_cast<float>((time - prev->time) / (next->time - prev->time));
  return interpolate(prev->value, next->value, t);
}

template <class T>
bool keyInside(const std::vector<Keyframe<T>>& keys, double t0, double t1) {
  return std::any_of(keys.begin(), keys.end(),
                     [&](const Keyframe<T>& k) { return k.time > t0 && k.time < t1; });
}

}  // namespace

Trs AnimatedTrs::at(double seconds) const {
  return {evaluate(translation_, rest_.translation, seconds),
          evaluate(rotation_, rest_.rotation, seconds), evaluate(scale_, rest_.scale, seconds)};
}

void AnimatedTrs::rotateAfter(const Quaternion& q) {
  rest_.rotation = (rest_.rotation * q).normalized();
  for (auto& key : rotation_) key.value = (key.value * q).normalized();
}

bool AnimatedTrs::isAnimated() const {
  return translation_.size() > 1 || rotation_.size() > 1 || scale_.size() > 1;
}

bool AnimatedTrs::hasKeyInside(double t0, double t1) const {
  return keyInside(translation_, t0, t1) || keyInside(rotation_, t0, t1) ||
         keyInside(scale_, t0, t1);
}

std::vector<Vec3f> AnimatedTrs::allScales() const {
  std::vector<Vec3f> scales{rest_.scale};
  for (const auto& k : scale_) scales.push_back(k.value);
  return scales;
}

}  // namespace pathfarm
