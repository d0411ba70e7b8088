#pragma once
// Motion vectors of the specular components (Zimmer et al. 2015, Section 4.1): per pixel
// and component, the representative path (the pixel-centre ray through its specular
// chain, at the middle of the shutter) is walked to the same point of the shutter in the
// next and the previous frame (or those a MotionSpan away), keeping its non-specular endpoint on the same object
// point; the motion is the change of the path's film position. A pure function of
// (scene, frame, pixel, component): no sampling, independent of tiles and threads.
#include <optional>
#include <vector>

#include "renderer/decomposition/decomposition.h"
#include "renderer/decomposition/manifold_walk.h"
#include "renderer/decomposition/primary_motion.h"

namespace pathfarm {

struct SpecularTrack {
  bool hasChain = false;  // the component has a representative path at this pixel
  bool walked = false;    // false where nothing on the chain moves: motion exactly zero
  // Pixels moved to the next and from the previous frame; nothing where the walk failed.
  std::optional<Vec2d> forward, backward;
  // The paths now and in the next and previous frames (where anything in the scene moves).
  std::optional<ChainPath> now, next, previous;
  WalkCounts counts;  // both walks together

  bool tracked() const { return forward.has_value() && backward.has_value(); }
};

class SpecularMotion {
 public:
  // The shutter point of the representative paths, as a fraction of the shutter.
  static constexpr float kShutterFraction = 0.5f;

  // `shapes`: preciseShapesOf(the scene), built once per shot (meshes get a BVH).
  SpecularMotion(const FrameGeometry& geometry, const std::vector<PreciseShape>& shapes,
                 const Decomposition& decomposition, int width, int height, MotionSpan span = {});
  SpecularMotion(const SpecularMotion&) = delete;  // cameraNow_ refers to camera_
  SpecularMotion& operator=(const SpecularMotion&) = delete;

  // Decomposition::isSpecular, kept per component.
  bool isSpecular(int component) const { return specular_[static_cast<size_t>(component)] != 0; }
  // Frame pixel (x, y).
  SpecularTrack track(int x, int y, int component) const;

 private:
  const FrameGeometry& geometry_;
  FrameGeometry nextGeometry_, previousGeometry_;  // for the paths' visibility there
  const LpeAutomaton& automaton_;
  const std::vector<PreciseShape>& shapes_;
  PinholeCamera camera_;
  double now_, next_, previous_;  // seconds
  PinholeCamera::Placed cameraNow_;
  bool sceneMoves_;
  std::vector<uint8_t> specular_;
};

}  // namespace pathfarm
