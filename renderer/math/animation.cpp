#include "renderer/math/animation.h"

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

// Where a track is at `time`: between keys `from` and `to` (a fraction of the span),
// or holding `from` (to == nullptr) before, after or without keys.
template <class T>
struct TrackPoint {
  const T* from;
  const T* to = nullptr;
  double fraction = 0, span = 0;
};

template <class T>
TrackPoint<T> locate(const std::vector<Keyframe<T>>& keys, const T& rest, double time) {
  if (keys.empty()) return {&rest};
  if (time < keys.front().time) return {&keys.front().value};
  if (time >= keys.back().time) return {&keys.back().value};
  const auto next = std::upper_bound(keys.begin(), keys.end(), time,
                                     [](double t, const Keyframe<T>& k) { return t < k.time; });
  const auto prev = next - 1;
  const double span = next->time - prev->time;
  return {&prev->value, &next->value, (time - prev->time) / span, span};
}

struct VectorState {
  Vec3d value, rate;
};

VectorState vectorAt(const TrackPoint<Vec3f>& p) {
  const Vec3d a(*p.from);
  if (!p.to) return {a, {}};
  const Vec3d delta = Vec3d(*p.to) - a;
  return {a + delta * p.fraction, delta / p.span};
}

struct QuaternionD {
  double w, x, y, z;
  Vec3d vector() const { return {x, y, z}; }
};

QuaternionD unit(const Quaternion& q) {
  const double n = std::sqrt(double(q.w) * q.w + double(q.x) * q.x + double(q.y) * q.y + double(q.z) * q.z);
  return {q.w / n, q.x / n, q.y / n, q.z / n};
}

QuaternionD multiply(const QuaternionD& a, const QuaternionD& b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

Mat3d rotationMatrix(const QuaternionD& q) {
  const double xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z, xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z,
               wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
  return Mat3d::fromColumns({1 - 2 * (yy + zz), 2 * (xy + wz), 2 * (xz - wy)},
                            {2 * (xy - wz), 1 - 2 * (xx + zz), 2 * (yz + wx)},
                            {2 * (xz + wy), 2 * (yz - wx), 1 - 2 * (xx + yy)});
}

Mat3d crossMatrix(Vec3d w) { return Mat3d::fromColumns({0, w.z, -w.y}, {-w.z, 0, w.x}, {w.y, -w.x, 0}); }

struct RotationState {
  Mat3d value;
  Vec3d angularVelocity;  // world frame, radians per second
};

// Slerp along the shorter arc, as slerp() does in float: from `a` the rotation turns at a
// constant rate about the world axis of b a^-1, so its angular velocity is that axis
// times the arc's angle over the span.
RotationState rotationAt(const TrackPoint<Quaternion>& p) {
  const QuaternionD a = unit(*p.from);
  if (!p.to) return {rotationMatrix(a), {}};
  QuaternionD b = unit(*p.to);
  if (a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z < 0) b = {-b.w, -b.x, -b.y, -b.z};
  const QuaternionD relative = multiply(b, {a.w, -a.x, -a.y, -a.z});
  const double sinHalf = length(relative.vector());
  if (sinHalf == 0) return {rotationMatrix(a), {}};
  const Vec3d axis = relative.vector() / sinHalf;
  const double halfAngle = std::atan2(sinHalf, relative.w);
  const double s = std::sin(p.fraction * halfAngle);
  const QuaternionD partial{std::cos(p.fraction * halfAngle), axis.x * s, axis.y * s, axis.z * s};
  return {rotationMatrix(multiply(partial, a)), axis * (2 * halfAngle / p.span)};
}

Mat3d diagonal(Vec3d d) { return Mat3d::fromColumns({d.x, 0, 0}, {0, d.y, 0}, {0, 0, d.z}); }

}  // namespace

AffineMotion AnimatedTrs::motionAt(double seconds) const {
  const VectorState translation = vectorAt(locate(translation_, rest_.translation, seconds));
  const RotationState rotation = rotationAt(locate(rotation_, rest_.rotation, seconds));
  const VectorState scale = vectorAt(locate(scale_, rest_.scale, seconds));
  AffineMotion m;
  m.linear = rotation.value * diagonal(scale.value);
  m.translation = translation.value;
  // d(R S)/dt = [w]x R S + R dS/dt
  m.linearRate = crossMatrix(rotation.angularVelocity) * m.linear + rotation.value * diagonal(scale.rate);
  m.translationRate = translation.rate;
  return m;
}

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
