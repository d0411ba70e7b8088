#include "renderer/decomposition/manifold_walk.h"

#include "renderer/math/dense_lu.h"

namespace pathfarm {
namespace {

// Bounds that keep every walk finite: time steps per walk, manifold steps per time step,
// the smallest step length (a fraction of the whole walk) and the smallest damping.
// A walk that succeeds rarely comes near them. A path that ceases to exist before the
// target time fails only once they are reached, so they set what failures cost, and
// failures took four fifths of the iterations with bounds of 24, 1/1024 and 1/256. With
// 12, 1/32 and 1/8, at most one pixel of each compared suite frame changed whether it is
// tracked (docs/performance.md, "Failed walks cut short").
constexpr int kMaxOuter = 40;
constexpr int kMaxInner = 12;
constexpr double kMinTimeFraction = 1.0 / 32;
constexpr double kMinDamping = 1.0 / 8;

// The constraint at one specular vertex and what its derivatives need (Jakob 2013,
// Section 4.3.1, with the unnormalized generalized half vector, which stays regular for
// an index of refraction near 1).
class VertexConstraint {
 public:
  VertexConstraint(Vec3d previous, const ChainVertex& vertex, Vec3d next, const ChainLink& link) {
    const Vec3d& x = vertex.surface.position;
    n_ = vertex.surface.normal;
    toPrevious_ = previous - x;
    toNext_ = next - x;
    distancePrevious_ = length(toPrevious_);
    distanceNext_ = length(toNext_);
    toPrevious_ = toPrevious_ / distancePrevious_;
    toNext_ = toNext_ / distanceNext_;
    // Indices on each side: 1 outside (where the normal points), ior inside.
    if (link.refracts) {
      etaPrevious_ = dot(toPrevious_, n_) > 0 ? 1 : link.ior;
      etaNext_ = dot(toNext_, n_) > 0 ? 1 : link.ior;
    }
    const Tangents frame = tangentsOf(n_);
    s_ = frame.s;
    t_ = frame.t;
    normalPart_ = dot(halfVector(), n_);
  }

  Vec3d halfVector() const { return toPrevious_ * etaPrevious_ + toNext_ * etaNext_; }

  // The change of (h.s, h.t) when the previous vertex, this one and the next move by the
  // given amounts and the normal turns by dn. The frame's own turning adds -(h.n)(s.dn)
  // and -(h.n)(t.dn); its twist about n is omitted, which is exact where h is along n,
  // i.e. on the manifold.
  Vec2d change(Vec3d dPrevious, Vec3d dVertex, Vec3d dNext, Vec3d dn) const {
    const Vec3d dh = rejectFrom(dPrevious - dVertex, toPrevious_) * (etaPrevious_ / distancePrevious_) +
                     rejectFrom(dNext - dVertex, toNext_) * (etaNext_ / distanceNext_);
    return {dot(dh, s_) - normalPart_ * dot(s_, dn), dot(dh, t_) - normalPart_ * dot(t_, dn)};
  }

 private:
  Vec3d n_, s_, t_, toPrevious_, toNext_;
  double distancePrevious_, distanceNext_, etaPrevious_ = 1, etaNext_ = 1, normalPart_;
};

// Least squares for the endpoint's surface coordinates: dpdu du + dpdv dv = r.
std::optional<Vec2d> surfaceStep(const SurfaceDifferentials& s, Vec3d r) {
  const double aa = dot(s.dpdu, s.dpdu), ab = dot(s.dpdu, s.dpdv), bb = dot(s.dpdv, s.dpdv);
  const double det = aa * bb - ab * ab;
  if (!(det > 1e-12 * aa * bb)) return std::nullopt;
  const double ra = dot(s.dpdu, r), rb = dot(s.dpdv, r);
  return Vec2d{(bb * ra - ab * rb) / det, (aa * rb - ab * ra) / det};
}

// One manifold step from `path` towards `target` at `seconds`: the endpoint's
// coordinates move to reach the target (scaled by `damping`), time moves to `seconds`,
// the first vertex follows the tangent, and re-tracing from the camera through its new
// position projects the path back onto the manifold.
std::optional<ChainPath> manifoldStep(const ChainTracer& tracer, const ChainPath& path, Vec3d target, double seconds,
                                      double damping) {
  const auto tangent = manifoldTangent(path, tracer.chain());
  if (!tangent) return std::nullopt;
  const double dt = seconds - path.seconds;
  const SurfaceDifferentials& end = path.endpoint().surface;
  const auto endStep = surfaceStep(end, target - (end.position + end.velocity * dt));
  if (!endStep) return std::nullopt;
  const double d[3] = {endStep->x * damping, endStep->y * damping, dt};
  double du = 0, dv = 0;
  for (int i = 0; i < 3; ++i) {
    du += tangent->du[i] * d[i];
    dv += tangent->dv[i] * d[i];
  }
  const SurfaceDifferentials& first = path.vertices.front().surface;
  const Vec3d moved = first.position + first.dpdu * du + first.dpdv * dv + first.velocity * dt;
  const auto film = tracer.camera().at(seconds).project(moved);
  if (!film || !std::isfinite(film->x) || !std::isfinite(film->y)) return std::nullopt;
  auto traced = tracer.trace(*film, seconds);
  if (!traced || !sameSides(*traced, path)) return std::nullopt;
  return traced;
}

double tolerance(Vec3d target) { return kWalkTolerance * (1 + maxAbs(target)); }

double distance(const ChainPath& path, Vec3d target) { return length(path.endpoint().surface.position - target); }

// The inner walk: from `from` to a path at `seconds` whose endpoint reaches `target`.
// The first step extrapolates in time; the following ones, at fixed time, halve their
// length when they fail to get closer and grow back when they succeed.
std::optional<ChainPath> converge(const ChainTracer& tracer, const ChainPath& from, Vec3d target, double seconds,
                                  WalkCounts& counts) {
  ++counts.inner;
  std::optional<ChainPath> current = manifoldStep(tracer, from, target, seconds, 1);
  if (!current) return std::nullopt;
  double error = distance(*current, target);
  double damping = 1;
  for (int step = 0; error > tolerance(target); ++step) {
    if (step >= kMaxInner) return std::nullopt;
    ++counts.inner;
    auto next = manifoldStep(tracer, *current, target, seconds, damping);
    const double nextError = next ? distance(*next, target) : error;
    if (next && nextError < error) {
      current = std::move(next);
      error = nextError;
      damping = std::min(1.0, 2 * damping);
    } else if ((damping *= 0.5) < kMinDamping) {
      return std::nullopt;
    }
  }
  return current;
}

}  // namespace

std::optional<FirstVertexTangent> manifoldTangent(const ChainPath& path, const SpecularChain& chain) {
  const int m = path.specularCount();
  const int n = 2 * m;
  // Jc over the specular vertices' (u, v); B: its derivatives along un, vn and t.
  std::vector<double> jacobian(static_cast<size_t>(n * n), 0.0), rhs(static_cast<size_t>(n * 3), 0.0);
  const auto at = [&](int i) -> const SurfaceDifferentials& { return path.vertices[static_cast<size_t>(i)].surface; };
  const auto put = [](std::vector<double>& matrix, int columns, int row, int column, Vec2d value) {
    matrix[static_cast<size_t>(row * columns + column)] = value.x;
    matrix[static_cast<size_t>((row + 1) * columns + column)] = value.y;
  };
  const Vec3d zero;
  for (int i = 0; i < m; ++i) {
    const SurfaceDifferentials& x = at(i);
    const Vec3d previous = i == 0 ? path.eye : at(i - 1).position;
    const Vec3d previousVelocity = i == 0 ? path.eyeVelocity : at(i - 1).velocity;
    const SurfaceDifferentials& next = at(i + 1);
    const VertexConstraint c(previous, path.vertices[static_cast<size_t>(i)], next.position,
                             chain.links[static_cast<size_t>(i)]);
    const int row = 2 * i;
    if (i > 0) {
      put(jacobian, n, row, 2 * i - 2, c.change(at(i - 1).dpdu, zero, zero, zero));
      put(jacobian, n, row, 2 * i - 1, c.change(at(i - 1).dpdv, zero, zero, zero));
    }
    put(jacobian, n, row, 2 * i, c.change(zero, x.dpdu, zero, x.dndu));
    put(jacobian, n, row, 2 * i + 1, c.change(zero, x.dpdv, zero, x.dndv));
    if (i + 1 < m) {
      put(jacobian, n, row, 2 * i + 2, c.change(zero, zero, next.dpdu, zero));
      put(jacobian, n, row, 2 * i + 3, c.change(zero, zero, next.dpdv, zero));
    } else {
      put(rhs, 3, row, 0, c.change(zero, zero, next.dpdu, zero));
      put(rhs, 3, row, 1, c.change(zero, zero, next.dpdv, zero));
    }
    put(rhs, 3, row, 2, c.change(previousVelocity, x.velocity, next.velocity, x.dndt));
  }
  for (double& v : rhs) v = -v;
  if (!solveDense(jacobian, n, rhs, 3)) return std::nullopt;
  return FirstVertexTangent{{rhs[0], rhs[1], rhs[2]}, {rhs[3], rhs[4], rhs[5]}};
}

std::optional<ChainPath> walkInTime(const ChainTracer& tracer, const ChainPath& start, double targetSeconds,
                                    WalkCounts& counts) {
  const Vec3d anchor = start.endpoint().surface.shapePosition;
  // Where nothing on the path moves, the same film position still lands on the point:
  // the motion is then exactly zero.
  ++counts.inner;
  if (auto same = tracer.trace(start.film, targetSeconds); same && sameSides(*same, start)) {
    const Vec3d target = tracer.endpointTarget(anchor, targetSeconds);
    if (distance(*same, target) <= tolerance(target)) return same;
  }
  const double whole = targetSeconds - start.seconds;
  ChainPath path = start;
  double step = whole;
  while (path.seconds != targetSeconds) {
    if (++counts.outer > kMaxOuter || std::abs(step) < kMinTimeFraction * std::abs(whole)) return std::nullopt;
    // Land exactly on the target time rather than next to it through rounding.
    const double seconds =
        std::abs(targetSeconds - path.seconds) <= std::abs(step) ? targetSeconds : path.seconds + step;
    if (auto moved = converge(tracer, path, tracer.endpointTarget(anchor, seconds), seconds, counts)) {
      path = std::move(*moved);
      step *= 2;
    } else {
      step *= 0.5;
    }
  }
  return path;
}

}  // namespace pathfarm
