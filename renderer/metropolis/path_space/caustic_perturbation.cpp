#include "renderer/metropolis/path_space/caustic_perturbation.h"

#include <algorithm>
#include <cmath>

#include "renderer/bidirectional/vertex_scattering.h"
#include "renderer/math/frame.h"
#include "renderer/metropolis/path_space/perturbation_size.h"
#include "renderer/metropolis/path_space/specular_chain.h"

namespace pathfarm {
namespace {

const PerturbationSize kAngle{1e-4, 0.1};

// T without the angle's density: the density of the regenerated vertices.
double regeneration(const Scene& scene, const std::vector<PathVertex>& x, int j) {
  double density = toAreaDensity(x[vertexIndex(j)], x[vertexIndex(j - 1)], 1.0f);
  if (j >= 3) density *= regenerationDensity(scene, x, {1, j}, ChainDirection::FromLight);
  return density;
}

}  // namespace

int causticSource(const std::vector<PathVertex>& x) {
  const int k = static_cast<int>(x.size()) - 1;  // -1 for an empty path
  if (k < 2 || x[1].delta) return -1;
  int j = 2;
  while (j < k && x[vertexIndex(j)].delta) ++j;
  return x[vertexIndex(j)].type == VertexType::Environment ? -1 : j;
}

PathMutation causticPerturbation(const WindowScene& scene, const PathSpaceState& current, Vec3f direction) {
  PathMutation result;
  const std::vector<PathVertex>& x = current.path.vertices;
  const int j = causticSource(x);
  if (j < 0 || !(current.density > 0)) return result;
  const WindowInstant instant = *scene.time.instant(current.tau);
  const BdptScene bdpt = scene.frame(instant.frame);
  const float time = instant.shutterFraction;
  std::vector<PathVertex> y = x;
  const auto next = regenerate(bdpt, time, x[vertexIndex(j)], direction, x[vertexIndex(j - 1)]);
  if (!next) return result;
  y[vertexIndex(j - 1)] = *next;
  if (j >= 3 && !retraceChain(bdpt, time, x, {1, j}, ChainDirection::FromLight, y)) return result;
  result.proposed = stateAt(scene, CompletePath{std::move(y), 0}, current.tau);
  if (!(result.proposed.density > 0)) return result;
  // The chord between the unit directions: acos of their dot product loses small angles.
  const double angle = 2 * std::asin(std::min(1.0, 0.5 * length(direction - directionBetween(x[vertexIndex(j)], x[vertexIndex(j - 1)]))));
  const double angleDensity = kAngle.density(angle) / (2 * kPi * std::sin(angle));
  result.forward = angleDensity * regeneration(bdpt.scene(), result.proposed.path.vertices, j);
  result.reverse = angleDensity * regeneration(bdpt.scene(), x, j);
  return result;
}

PathMutation causticPerturbation(const WindowScene& scene, const PathSpaceState& current, SampleStream& random) {
  const std::vector<PathVertex>& x = current.path.vertices;
  const int j = causticSource(x);
  const float angle = static_cast<float>(kAngle.sample(random.next1D()));
  const float phi = 2 * kPi * random.next1D();
  if (j < 0) return {};
  const Frame around = Frame::fromNormal(directionBetween(x[vertexIndex(j)], x[vertexIndex(j - 1)]));
  const Vec3f local{std::sin(angle) * std::cos(phi), std::sin(angle) * std::sin(phi), std::cos(angle)};
  return causticPerturbation(scene, current, normalize(around.toWorld(local)));
}

}  // namespace pathfarm
