#pragma once
// A mesh whose vertices move on their own, as a character's do: morph targets (offsets
// of positions, normals and tangents, blended by weights that may be animated) and
// linear blend skinning (each vertex carried by the weighted sum of its joints' current
// placements times their inverse bind matrices). Poses are in world space: a skinned
// mesh follows its joints alone (glTF 2.0, 3.7.3.3), an unskinned one its placement.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "renderer/math/animation.h"
#include "renderer/math/key_track.h"
#include "renderer/scene/mesh.h"

namespace pathfarm {

// Offsets per vertex of the rest mesh; an empty list leaves that attribute alone.
struct MorphTarget {
  std::vector<Vec3f> positions, normals, tangents;
};

struct JointInfluence {
  uint32_t joint = 0;
  float weight = 0;  // a vertex's weights sum to 1
};

struct Skin {
  std::vector<AnimatedTrs> joints;     // each joint's world placement over time
  std::vector<Transform> inverseBind;  // per joint: mesh space to the joint's space at bind time
  std::vector<uint32_t> firstInfluence;  // vertex v's influences: [first[v], first[v + 1])
  std::vector<JointInfluence> influences;
};

struct MorphWeights {
  std::vector<float> rest;  // when not animated (the node's or the mesh's default)
  std::optional<KeyTrack> animated;  // one component per target
};

class MeshDeformation {
 public:
  // Without `skin`, `placement` carries the morphed mesh into the world.
  MeshDeformation(std::shared_ptr<const TriangleMesh> rest, std::vector<MorphTarget> targets, MorphWeights weights,
                  std::optional<Skin> skin, AnimatedTrs placement);

  struct Pose {
    std::vector<Vec3f> positions, normals, tangents;  // normals and tangents where the mesh has them; unit
  };
  // Every vertex at `seconds`.
  Pose poseAt(double seconds) const;
  // One vertex's position at `seconds`, for following a surface point through time.
  Vec3f positionAt(uint32_t vertex, double seconds) const;
  // Whether the pose changes over time at all.
  bool isAnimated() const;
  const TriangleMesh& rest() const { return *rest_; }

 private:
  std::vector<float> weightsAt(double seconds) const;
  // Mesh space to world space for vertex v, given the joints' matrices at one time.
  std::array<float, 12> vertexMatrix(uint32_t vertex, const std::vector<Transform>& jointMatrices) const;
  Transform jointMatrix(size_t joint, double seconds) const;

  std::shared_ptr<const TriangleMesh> rest_;
  std::vector<MorphTarget> targets_;
  MorphWeights weights_;
  std::optional<Skin> skin_;
  AnimatedTrs placement_;
};

}  // namespace pathfarm
