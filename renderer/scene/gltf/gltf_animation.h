#pragma once
// Where a glTF node is over time: its local TRS (rest values, or a matrix, overridden by
// the animation channels that target it, with LINEAR, STEP or CUBICSPLINE samplers)
// composed through its parents into a world placement the renderer can move objects
// and cameras with (AnimatedTrs), and the morph target weights animated on it. Every
// animation in the file plays from time 0.
#include <vector>

#include "renderer/math/animation.h"
#include "renderer/math/key_track.h"
#include "renderer/math/vec3d.h"
#include "renderer/scene/gltf/gltf_document.h"

namespace pathfarm {

// A placement as a 3x3 linear part and a translation, in double.
struct Affine3d {
  Mat3d linear = Mat3d::identity();
  Vec3d translation;

  Affine3d operator*(const Affine3d& rhs) const { return {linear * rhs.linear, linear * rhs.translation + translation}; }
  Vec3d point(Vec3d p) const { return linear * p + translation; }
};

class GltfNodeAnimation {
 public:
  // Reads every node's rest placement and every animation; refuses malformed samplers
  // and hierarchies with cycles.
  explicit GltfNodeAnimation(const GltfDocument& document);

  // The node's world placement at `seconds`.
  Affine3d worldAt(int node, double seconds) const;
  // The node's world placement as the renderer's animated transform: keys at every key
  // time of the node and its ancestors, and every 1/96 s in between where composition,
  // cubic splines or steps make the motion nonlinear between keys. `withScale` false
  // drops the scale (cameras). Refuses placements with shear or zero scale.
  AnimatedTrs worldTransform(int node, bool withScale) const;
  // The animation of the node's morph target weights (null if none): a track of one
  // component per target, its width checked against the mesh's targets by the caller.
  const KeyTrack* weightTrack(int node) const;
  // The time of the last key of any animation (0 without animation).
  double duration() const { return duration_; }
  const std::vector<int>& parents() const { return parents_; }

 private:
  enum class Path { Translation, Rotation, Scale };
  struct Channel {
    int node;
    Path path;
    KeyTrack track;  // 3 components, 4 for rotations (x, y, z, w)
  };

  void readAnimations();
  // The sampler a channel plays, its width given (0: whatever the output holds per key).
  KeyTrack readTrack(const tinygltf::Animation& animation, int sampler, size_t width, const std::string& pointer);
  Affine3d localAt(int node, double seconds) const;
  std::vector<double> sampleTimes(int node) const;
  Trs decompose(int node, const Affine3d& placement, bool withScale) const;

  const GltfDocument& document_;
  std::vector<int> parents_;  // -1 for roots
  std::vector<Trs> rest_;
  std::vector<std::vector<Channel>> channels_;  // per node
  std::vector<KeyTrack> weights_;                // per node; no keys when not animated
  double duration_ = 0;
};

}  // namespace pathfarm
