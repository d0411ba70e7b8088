#include "renderer/metropolis/path_space/lens_perturbation.h"

#include "renderer/metropolis/path_space/path_walk.h"
#include "renderer/metropolis/path_space/perturbation_size.h"
#include "renderer/metropolis/path_space/specular_chain.h"

namespace pathfarm {
namespace {

PerturbationSize offsetSize(const WindowScene& scene) { return {0.1, 0.1 * scene.width()}; }

// The first non-delta vertex after the camera.
int firstNonDelta(const std::vector<PathVertex>& x) {
  int c = 1;
  while (x[static_cast<size_t>(c)].delta) ++c;
  return c;
}

// T without the offset density: the density of the regenerated vertices.
double regeneration(const WindowScene& scene, const BdptScene& bdpt, float time, const std::vector<PathVertex>& x) {
  const int c = firstNonDelta(x);
  double density = static_cast<double>(scene.width()) * scene.height() * walkDensity(bdpt, time, nullptr, x[0], x[1]);
  if (c >= 2) density *= regenerationDensity(bdpt.scene(), x, {0, c}, ChainDirection::FromCamera);
  return density;
}

}  // namespace

PathMutation lensPerturbation(const WindowScene& scene, const PathSpaceState& current, Vec2f offset) {
  PathMutation result;
  if (!(current.density > 0)) return result;
  const WindowInstant instant = *scene.time.instant(current.tau);
  const BdptScene bdpt = scene.frame(instant.frame);
  const float time = instant.shutterFraction;
  const std::vector<PathVertex>& x = current.path.vertices;
  // Veach's lens subpath is E S* D (D|L): the moved x_c must reconnect to a vertex that
  // can be connected. A delta x_c+1 keeps its Dirac directions, which the moved x_c would
  // break; f only tolerates that within the lobe test's tolerance, a band of paths no
  // other sampler makes, where a chain then sticks with a biased f.
  const int c = firstNonDelta(x);
  if (c < current.path.length() && x[static_cast<size_t>(c + 1)].delta) return result;
  const Vec2f film{current.contribution.film.x + offset.x, current.contribution.film.y + offset.y};
  const Vec3f direction = bdpt.camera.camera().generateRay(film, {0.5f, 0.5f}, bdpt.seconds(time)).direction;
  std::vector<PathVertex> y = x;
  const auto y1 = regenerate(bdpt, time, x[0], direction, x[1]);
  if (!y1) return result;
  y[1] = *y1;
  if (c >= 2 && !retraceChain(bdpt, time, x, {0, c}, ChainDirection::FromCamera, y)) return result;
  result.proposed = stateAt(scene, CompletePath{std::move(y), 0}, current.tau);
  if (!(result.proposed.density > 0)) return result;
  const double r = std::sqrt(static_cast<double>(offset.x) * offset.x + static_cast<double>(offset.y) * offset.y);
  const double offsetDensity = offsetSize(scene).density(r) / (2 * kPi * r);
  result.forward = offsetDensity * regeneration(scene, bdpt, time, result.proposed.path.vertices);
  result.reverse = offsetDensity * regeneration(scene, bdpt, time, x);
  return result;
}

PathMutation lensPerturbation(const WindowScene& scene, const PathSpaceState& current, SampleStream& random) {
  const double r = offsetSize(scene).sample(random.next1D());
  const double phi = 2 * kPi * random.next1D();
  return lensPerturbation(scene, current,
                          {static_cast<float>(r * std::cos(phi)), static_cast<float>(r * std::sin(phi))});
}

}  // namespace pathfarm
