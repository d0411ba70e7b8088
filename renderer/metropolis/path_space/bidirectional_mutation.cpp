#include "renderer/metropolis/path_space/bidirectional_mutation.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "renderer/bidirectional/subpath.h"
#include "renderer/bidirectional/vertex_scattering.h"
#include "renderer/metropolis/path_space/path_walk.h"
#include "renderer/metropolis/path_space/vertex_motion.h"

namespace pathfarm {
namespace {

double deletedEdgesWeight(int d) { return std::ldexp(1.0, -(d - 1)); }

double deletionNormalization(int k) {
  double sum = 0;
  for (int d = 1; d <= k + 1; ++d) sum += deletedEdgesWeight(d);
  return sum;
}

struct Deletion {
  int l = 0, m = 0;
};

Deletion sampleDeletion(int k, SampleStream& random) {
  double u = random.next1D() * deletionNormalization(k);
  int d = 1;
  while (d < k + 1 && u >= deletedEdgesWeight(d)) u -= deletedEdgesWeight(d++);
  const int places = k + 2 - d;
  const int l = std::min(static_cast<int>(random.next1D() * static_cast<float>(places)), places - 1);
  return {l, l + d};
}

// The probability of adding n vertices where `deleted` were deleted, leaving `kept`.
double additionProbability(int n, int kept, int deleted, bool lightEndDeleted, int maxVertices) {
  const double weights[3] = {0.25, 0.5, 0.25};
  double total = 0, chosen = 0;
  for (int j = 0; j < 3; ++j) {
    const int added = deleted - 1 + j;
    const bool allowed = added >= 0 && (!lightEndDeleted || added >= 1) && kept + added <= maxVertices &&
                         kept + added >= 2 && !(added == 0 && deleted == 0);
    if (!allowed) continue;
    total += weights[j];
    if (added == n) chosen = weights[j];
  }
  return total > 0 ? chosen / total : 0;
}

int sampleAddition(int kept, int deleted, bool lightEndDeleted, int maxVertices, float u) {
  for (int n = std::max(0, deleted - 1); n <= deleted + 1; ++n) {
    const double p = additionProbability(n, kept, deleted, lightEndDeleted, maxVertices);
    if (u < p) return n;
    u -= static_cast<float>(p);
  }
  return -1;
}

// The density of y's vertices l+1 .. mNew-1 sampled as t by a walk from y_l and the rest
// by a walk from y_mNew (or from a new light end, when mNew is past the end).
double splitDensity(const BdptScene& bdpt, float time, const std::vector<PathVertex>& y, int l, int mNew, int t) {
  const int k = static_cast<int>(y.size()) - 1;
  const int c = l + t, q = l + t + 1;  // the connection edge, if q is a vertex
  if (q <= k && (y[vertexIndex(c)].delta || y[vertexIndex(q)].delta)) return 0;
  double p = 1;
  for (int i = l + 1; i <= c; ++i) p *= walkDensity(bdpt, time, i >= 2 ? &y[vertexIndex(i - 2)] : nullptr, y[vertexIndex(i - 1)], y[vertexIndex(i)]);
  for (int i = q; i < mNew; ++i)
    p *= i == k ? lightStartDensity(bdpt, time, y[vertexIndex(k)])
                : walkDensity(bdpt, time, i + 2 <= k ? &y[vertexIndex(i + 2)] : nullptr, y[vertexIndex(i + 1)], y[vertexIndex(i)]);
  return p;
}

// Extends `walk` by `count` vertices; false when a walk fails or escapes before the end.
bool extend(const BdptScene& bdpt, float time, std::vector<PathVertex>& walk, int count, bool mayEscapeLast,
            SampleStream& random) {
  for (int j = 0; j < count; ++j) {
    const PathVertex* before = walk.size() >= 2 ? &walk[walk.size() - 2] : nullptr;
    const auto next = walkFrom(bdpt, time, before, walk.back(), random);
    if (!next || (next->type == VertexType::Environment && !(mayEscapeLast && j == count - 1))) return false;
    walk.push_back(*next);
  }
  return true;
}

}  // namespace

bool renewsTime(int k, int l, int m) { return l == 0 && m == k + 1; }

double deletionProbability(int k, int l, int m) {
  const int d = m - l;
  if (l < 0 || m > k + 1 || d < 1) return 0;
  return deletedEdgesWeight(d) / deletionNormalization(k) / (k + 2 - d);
}

double bidirectionalDensity(const WindowScene& scene, const PathSpaceState& x, const PathSpaceState& y, int l, int m) {
  const int k = x.path.length(), kNew = y.path.length();
  const int deleted = m - l - 1, added = kNew - k + deleted, mNew = l + added + 1;
  const BdptScene bdpt = scene.frame(y.contribution.frame);
  const double pn = additionProbability(added, k + 1 - deleted, deleted, m == k + 1, maxCameraVertices(bdpt));
  double sum = 0;
  for (int t = 0; t <= added; ++t) sum += splitDensity(bdpt, y.path.time, y.path.vertices, l, mNew, t);
  const double time = renewsTime(k, l, m) ? 1 / scene.time.openLength() : 1;
  return deletionProbability(k, l, m) * pn * sum / (added + 1) * time;
}

PathMutation bidirectionalMutation(const WindowScene& scene, const PathSpaceState& current, SampleStream& random) {
  PathMutation result;
  if (!(current.density > 0)) return result;
  const std::vector<PathVertex>& x = current.path.vertices;
  const int k = current.path.length();
  const Deletion del = sampleDeletion(k, random);
  double tau = current.tau;
  std::vector<PathVertex> cameraSide(x.begin(), x.begin() + del.l + 1);
  if (renewsTime(k, del.l, del.m)) {
    tau = scene.time.fromPrimary(random.next1D());
    cameraSide[0] = placedAt(scene, x[0], *scene.time.instant(current.tau), *scene.time.instant(tau));
  }
  const WindowInstant instant = *scene.time.instant(tau);
  const BdptScene bdpt = scene.frame(instant.frame);
  const float time = instant.shutterFraction;
  const int deleted = del.m - del.l - 1, kept = k + 1 - deleted;
  const bool lightEndDeleted = del.m == k + 1;
  const int added = sampleAddition(kept, deleted, lightEndDeleted, maxCameraVertices(bdpt), random.next1D());
  if (added < 0) return result;
  const int t = std::min(static_cast<int>(random.next1D() * static_cast<float>(added + 1)), added), s = added - t;
  const bool connected = !(lightEndDeleted && s == 0);
  // Keeping x_k as x_l (l = k, m = k + 1) turns the old light end into a scattering
  // vertex: neither an environment direction nor a punctual light can be one.
  const bool endKept = cameraSide.back().type == VertexType::Environment || cameraSide.back().isPunctual();
  if (endKept && (connected || t > 0)) return result;

  if (!extend(bdpt, time, cameraSide, t, !connected, random)) return result;
  std::vector<PathVertex> lightSide;  // from the light end inwards
  if (!lightEndDeleted) {
    lightSide.assign(x.rbegin(), x.rbegin() + (k + 1 - del.m));
  } else if (s > 0) {
    const auto end = sampleLightEnd(bdpt, time, random);
    if (!end) return result;
    lightSide.push_back(*end);
  }
  if (!extend(bdpt, time, lightSide, lightEndDeleted ? s - 1 : s, false, random)) return result;
  if (connected) {
    cameraSide.back().delta = false;
    lightSide.back().delta = false;
  } else if (cameraSide.back().type == VertexType::Surface) {
    cameraSide.back().type = VertexType::Light;  // the camera walk found the light end
  }
  cameraSide.insert(cameraSide.end(), lightSide.rbegin(), lightSide.rend());
  result.proposed = stateAt(scene, CompletePath{std::move(cameraSide), 0}, tau);
  if (!(result.proposed.density > 0)) return result;
  result.forward = bidirectionalDensity(scene, current, result.proposed, del.l, del.m);
  result.reverse = bidirectionalDensity(scene, result.proposed, current, del.l, del.l + added + 1);
  return result;
}

}  // namespace pathfarm
