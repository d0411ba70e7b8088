#pragma once
// The representative path of a specular component (Zimmer et al. 2015, Section 4.1): the
// pixel-centre camera ray followed through its chain of specular reflections and
// refractions x1 ... x(n-1) to the first non-specular vertex xn. A chain is found once
// with Embree; after that it is re-traced in double precision against its own objects
// only, at any time, which is the projection step of the manifold walk.
#include <optional>
#include <vector>

#include "renderer/accel/frame_geometry.h"
#include "renderer/accel/precise_shape.h"
#include "renderer/decomposition/lpe_automaton.h"
#include "renderer/scene/pinhole_camera.h"

namespace pathfarm {

// The bound: at most 8 vertices after the eye, the last one non-specular.
inline constexpr int kMaxChainVertices = 8;

struct ChainLink {
  int object = -1;
  bool refracts = false;  // refraction, else mirror reflection
  double ior = 1;         // the object's interior index for a refraction (the outside is 1)
};

// Which objects a chain meets and how, then the object its non-specular end lies on.
struct SpecularChain {
  std::vector<ChainLink> links;
  int endpoint = -1;
};

// Follows the ray through the vertices whose specular lobes keep `component` alive in
// the automaton, to the first vertex where the component reads D (as the path
// decomposer records features). Nothing when the component's first non-specular vertex
// is the one the camera sees directly, when the ray escapes, or when no chain of at most
// kMaxChainVertices vertices reaches such a vertex. `time` is the shutter fraction.
std::optional<SpecularChain> findSpecularChain(const FrameGeometry& geometry, const LpeAutomaton& automaton,
                                               int component, Ray ray, float time);

struct ChainVertex {
  SurfaceDifferentials surface;
  bool front = true;  // the path arrives on the side the normal points to
};

// One path of a chain at one time: the camera's film position, the pinhole, then the
// specular vertices and last the non-specular endpoint.
struct ChainPath {
  double seconds = 0;
  Vec2d film;
  Vec3d eye, eyeVelocity;
  std::vector<ChainVertex> vertices;

  const ChainVertex& endpoint() const { return vertices.back(); }
  int specularCount() const { return static_cast<int>(vertices.size()) - 1; }
};

class ChainTracer {
 public:
  ChainTracer(const std::vector<PreciseShape>& shapes, const PinholeCamera& camera, SpecularChain chain)
      : shapes_(shapes), camera_(camera), chain_(std::move(chain)) {}

  // The path through `film` at `seconds`, or nothing when the ray misses one of the
  // chain's objects or cannot refract (total internal reflection).
  std::optional<ChainPath> trace(Vec2d film, double seconds) const;
  // Where the endpoint's object carries the object-space point `shapePosition` at `seconds`.
  Vec3d endpointTarget(Vec3d shapePosition, double seconds) const;
  const SpecularChain& chain() const { return chain_; }
  const PinholeCamera& camera() const { return camera_; }

 private:
  const std::vector<PreciseShape>& shapes_;
  const PinholeCamera& camera_;
  SpecularChain chain_;
};

// Whether nothing lies between consecutive vertices of `path` in `geometry` (Embree, at
// shutter fraction `time`): re-tracing sees the chain's own objects only, so a path
// walked to another frame is checked against the whole scene there.
bool isUnoccluded(const ChainPath& path, const FrameGeometry& geometry, float time);

// Whether two paths of a chain arrive on the same side of every surface: otherwise the
// chain has changed type (say from entering the glass to leaving it) between them.
bool sameSides(const ChainPath& a, const ChainPath& b);

}  // namespace pathfarm
