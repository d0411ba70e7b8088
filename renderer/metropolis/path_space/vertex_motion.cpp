#include "renderer/metropolis/path_space/vertex_motion.h"

#include <cmath>

#include "renderer/bidirectional/vertex_scattering.h"

namespace pathfarm {
namespace {

const PreparedShape* movingShapeOf(const WindowScene& scene, const PathVertex& x) {
  if (!x.isSurfaceLike() || x.hit.object < 0) return nullptr;
  const PreparedShape& shape = scene.geometry.frame(scene.time.window().first).shot().shape(x.hit.object);
  return shape.animated || shape.deforming ? &shape : nullptr;
}

Transform shapeToWorld(const WindowScene& scene, int object, WindowInstant at) {
  return scene.geometry.frame(at.frame).shapeToWorld(object, at.shutterFraction);
}

double seconds(const WindowScene& scene, WindowInstant at) {
  return scene.geometry.frame(at.frame).shot().scene().timeAt(at.frame, at.shutterFraction);
}

// A world normal back in shape space: normals map by the inverse transpose M^-T, so
// M^T takes them back (up to length).
Vec3f shapeNormal(const Transform& toWorld, Vec3f n) {
  const auto& m = toWorld.matrix();
  return normalize(Vec3f{m[0] * n.x + m[4] * n.y + m[8] * n.z, m[1] * n.x + m[5] * n.y + m[9] * n.z,
                         m[2] * n.x + m[6] * n.y + m[10] * n.z});
}

const PunctualLight& punctualLightOf(const WindowScene& scene, const PathVertex& x) {
  return scene.geometry.frame(scene.time.window().first).shot().scene().punctualLights[static_cast<size_t>(x.punctual)];
}

}  // namespace

bool movesWithTime(const WindowScene& scene, const PathVertex& x) {
  if (x.type == VertexType::Camera) return scene.camera.camera().isAnimated();
  if (x.isPunctual()) return punctualLightOf(scene, x).transform.isAnimated();
  return movingShapeOf(scene, x) != nullptr;
}

PathVertex placedAt(const WindowScene& scene, const PathVertex& x, WindowInstant from, WindowInstant to) {
  PathVertex moved = x;
  if (x.type == VertexType::Camera) {
    const Camera& camera = scene.camera.camera();
    const double s = seconds(scene, from), t = seconds(scene, to);
    moved.hit.position = camera.cameraToWorld(t).point(camera.cameraToWorld(s).inversePoint(x.position()));
    moved.hit.geometricNormal = scene.camera.viewDirection(t);
    return moved;
  }
  if (x.isPunctual()) {
    const PathVertex placed = punctualLightEnd(scene.frame(to.frame), to.shutterFraction, x.punctual);
    moved.hit = placed.hit;
    moved.direction = placed.direction;
    return moved;
  }
  const PreparedShape* shape = movingShapeOf(scene, x);
  if (!shape) return x;
  if (shape->deforming) {  // the same point of the same triangle on the mesh's pose then
    const SurfaceHit there =
        scene.geometry.frame(to.frame).deformedSurface(x.hit.object, x.hit.primitive, x.hit.barycentric, to.shutterFraction);
    moved.hit.position = there.position;
    moved.hit.shapePosition = there.shapePosition;
    moved.hit.geometricNormal = there.geometricNormal;
    moved.hit.shadingNormal = there.shadingNormal;
    return moved;
  }
  const Transform before = shapeToWorld(scene, x.hit.object, from);
  const Transform after = shapeToWorld(scene, x.hit.object, to);
  moved.hit.position = after.point(x.hit.shapePosition);
  moved.hit.geometricNormal = normalize(after.normal(shapeNormal(before, x.hit.geometricNormal)));
  moved.hit.shadingNormal = normalize(after.normal(shapeNormal(before, x.hit.shadingNormal)));
  return moved;
}

double areaScale(const WindowScene& scene, const PathVertex& x, WindowInstant at) {
  const PreparedShape* shape = movingShapeOf(scene, x);
  if (!shape) return 1;
  if (shape->deforming)
    return scene.geometry.frame(at.frame).deformedAreaScale(x.hit.object, x.hit.primitive, at.shutterFraction);
  const Transform toWorld = shapeToWorld(scene, x.hit.object, at);
  const auto& m = toWorld.matrix();
  const double det = static_cast<double>(m[0]) * (m[5] * m[10] - m[6] * m[9]) -
                     static_cast<double>(m[1]) * (m[4] * m[10] - m[6] * m[8]) +
                     static_cast<double>(m[2]) * (m[4] * m[9] - m[5] * m[8]);
  // An area element with unit shape normal n maps to |det M| |M^-T n| of world area.
  return std::abs(det) * length(toWorld.normal(shapeNormal(toWorld, x.hit.geometricNormal)));
}

}  // namespace pathfarm
