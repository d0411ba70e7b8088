#include "renderer/metropolis/path_space/temporal_perturbation.h"

#include <algorithm>
#include <optional>

#include "renderer/metropolis/path_space/vertex_motion.h"

namespace pathfarm {
namespace {

ChainDirection opposite(ChainDirection way) {
  return way == ChainDirection::FromCamera ? ChainDirection::FromLight : ChainDirection::FromCamera;
}

// A vertex list moved to another time one way, with what the move did to each vertex.
struct MovedPath {
  std::vector<PathVertex> vertices;
  std::vector<bool> moved, regenerated;
  std::vector<SpecularChain> retraced;
};

std::optional<MovedPath> moveTo(const WindowScene& scene, const std::vector<PathVertex>& x, WindowInstant from,
                                WindowInstant to, ChainDirection way) {
  MovedPath m;
  for (const PathVertex& v : x) {
    m.moved.push_back(movesWithTime(scene, v));
    m.vertices.push_back(m.moved.back() ? placedAt(scene, v, from, to) : v);
  }
  m.regenerated.assign(x.size(), false);
  const BdptScene bdpt = scene.frame(to.frame);
  std::vector<SpecularChain> chains = specularChainsOf(x);
  const bool fromCamera = way == ChainDirection::FromCamera;
  if (!fromCamera) std::reverse(chains.begin(), chains.end());
  for (const SpecularChain& c : chains) {
    const int anchor = fromCamera ? c.a : c.b;
    bool changed = m.regenerated[vertexIndex(anchor)];
    for (int i = c.a; i <= c.b; ++i) changed = changed || m.moved[vertexIndex(i)];
    if (!changed) continue;
    if (!retraceChain(bdpt, to.shutterFraction, x, c, way, m.vertices)) return std::nullopt;
    const int step = fromCamera ? 1 : -1;
    for (int i = anchor + 2 * step; i != (fromCamera ? c.b : c.a) + step; i += step) m.regenerated[vertexIndex(i)] = true;
    m.retraced.push_back(c);
  }
  return m;
}

// T without p_time and q: the regeneration densities and the Jacobians of the moved
// vertices, for the vertex list x that the move `m` made (or that its reverse restores).
double moveDensity(const WindowScene& scene, const std::vector<PathVertex>& x, const MovedPath& m, WindowInstant at,
                   ChainDirection way) {
  const Scene& shot = scene.geometry.frame(at.frame).shot().scene();
  double density = 1;
  for (const SpecularChain& c : m.retraced) density *= regenerationDensity(shot, x, c, way);
  for (size_t i = 0; i < x.size(); ++i)
    if (m.moved[i] && !m.regenerated[i]) density /= areaScale(scene, x[i], at);
  return density;
}

// The probability of the way used: 1/2 when the other way would also have succeeded.
double wayProbability(bool retraced, bool bothSucceed) { return retraced && bothSucceed ? 0.5 : 1.0; }

}  // namespace

TemporalMove temporalMove(const WindowScene& scene, const TemporalProposal& proposal, const PathSpaceState& current,
                          double tauNext, ChainDirection first) {
  TemporalMove move;
  move.mutation.proposed.tau = tauNext;
  const std::optional<WindowInstant> from = scene.time.instant(current.tau), to = scene.time.instant(tauNext);
  const double pForward = proposal.density(current.tau, tauNext);
  if (!from || !to || !(pForward > 0) || !(current.density > 0)) return move;  // closed shutter: f(Y) = 0
  const std::vector<PathVertex>& x = current.path.vertices;
  const auto tried = moveTo(scene, x, *from, *to, first);
  const auto other = moveTo(scene, x, *from, *to, opposite(first));
  if (!tried && !other) return move;
  const MovedPath& used = tried ? *tried : *other;
  move.way = tried ? first : opposite(first);
  move.retraced = !used.retraced.empty();
  move.mutation.proposed = stateAt(scene, CompletePath{used.vertices, 0}, tauNext);
  if (!(move.mutation.proposed.density > 0)) return move;

  const std::vector<PathVertex>& y = move.mutation.proposed.path.vertices;
  const auto back = moveTo(scene, y, *to, *from, move.way);
  if (!back) return move;  // not reversible (rounding at a grazing edge): T(Y -> X) = 0
  const bool backOtherSucceeds = moveTo(scene, y, *to, *from, opposite(move.way)).has_value();
  move.mutation.forward = pForward * wayProbability(move.retraced, tried && other) * moveDensity(scene, y, used, *to, move.way);
  move.mutation.reverse = proposal.density(tauNext, current.tau) * wayProbability(!back->retraced.empty(), backOtherSucceeds) *
                 moveDensity(scene, x, *back, *from, move.way);
  return move;
}

TemporalMove perturbInTime(const WindowScene& scene, const PathSpaceState& current, MutationContext& context) {
  const double tauNext = context.temporal.sample(current.tau, context.random.next1D());
  const ChainDirection first = context.random.next1D() < 0.5 ? ChainDirection::FromCamera : ChainDirection::FromLight;
  return temporalMove(scene, context.temporal, current, tauNext, first);
}

}  // namespace pathfarm
