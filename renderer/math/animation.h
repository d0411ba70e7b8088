#pragma once
// Keyframe animation of a translation-rotation-scale transform. Each component has its
// own track; translation and scale interpolate linearly, rotation with slerp, and a
// track holds its first/last value outside its keys. Times are in seconds.
#include <vector>

#include "renderer/math/affine_motion.h"
#include "renderer/math/transform.h"

namespace pathfarm {

template <class T>
struct Keyframe {
  double time;
  T value;
};

class AnimatedTrs {
 public:
  AnimatedTrs() = default;
  explicit AnimatedTrs(const Trs& rest) : rest_(rest) {}

  // Keys must be sorted by strictly increasing time; an empty track keeps the rest value.
  void setTranslationKeys(std::vector<Keyframe<Vec3f>> keys) { translation_ = std::move(keys); }
  void setRotationKeys(std::vector<Keyframe<Quaternion>> keys) { rotation_ = std::move(keys); }
  void setScaleKeys(std::vector<Keyframe<Vec3f>> keys) { scale_ = std::move(keys); }

  // Composes every rotation (rest and keys) with q on the right, R(t) becomes R(t) * q,
  // so q acts first.
  void rotateAfter(const Quaternion& q);

  Trs at(double seconds) const;
  Transform transformAt(double seconds) const { return Transform::fromTrs(at(seconds)); }
  // The same placement in double precision with its time derivative (per second), for
  // solvers that differentiate through the animation. At a key the derivative is the
  // following segment's; outside the keys it is zero.
  AffineMotion motionAt(double seconds) const;
  bool isAnimated() const;
  // True when some key lies strictly inside (t0, t1): the motion there is not one
  // linear segment.
  bool hasKeyInside(double t0, double t1) const;
  // Every value any track takes (rest values and keys), e.g. to validate scales.
  std::vector<Vec3f> allScales() const;

 private:
  Trs rest_;
  std::vector<Keyframe<Vec3f>> translation_;
  std::vector<Keyframe<Quaternion>> rotation_;
  std::vector<Keyframe<Vec3f>> scale_;
};

}  // namespace pathfarm
