#include "renderer/bidirectional/connection.h"

#include "renderer/bidirectional/vertex_scattering.h"
#include "renderer/integrators/path_vertex.h"

namespace pathfarm {
namespace {

// The vertices of strategy (s, t) joined into x0 ... xk, with the densities each
// subpath stored and those around the connection evaluated anew (Veach 1997, section
// 10.3.4): only the densities of the two connected vertices and their neighbours differ
// from what the subpaths recorded.
class JoinedPath {
 public:
  JoinedPath(const Subpath& camera, const Subpath& light, int s, int t, const PathVertex& cameraEnd,
             const PathVertex& lightEnd)
      : camera_(camera), light_(light), s_(s), t_(t), k_(s + t - 1), cameraEnd_(cameraEnd), lightEnd_(lightEnd) {}

  const PathVertex& operator[](int i) const {
    if (i == t_ - 1) return cameraEnd_;
    if (s_ > 0 && i == t_) return lightEnd_;
    return i < t_ ? camera_[static_cast<size_t>(i)] : light_[static_cast<size_t>(k_ - i)];
  }

  void densities(const BdptScene& bdpt, float time, PathDensities& d) const {
    d.resize(k_ + 1);
    for (int i = 0; i <= k_; ++i) {
      const PathVertex& x = (*this)[i];
      const bool fromCamera = i < t_;
      d.fromCamera[static_cast<size_t>(i)] = fromCamera ? x.pdfFwd : x.pdfRev;
      d.fromLight[static_cast<size_t>(i)] = fromCamera ? x.pdfRev : x.pdfFwd;
      d.delta[static_cast<size_t>(i)] = x.delta;
    }
    const PathVertex& pt = (*this)[t_ - 1];
    const PathVertex* beforePt = t_ >= 2 ? &(*this)[t_ - 2] : nullptr;
    if (s_ == 0) {
      d.environmentEnd = pt.type == VertexType::Environment;
      d.fromLight[static_cast<size_t>(k_)] = lightStartDensity(bdpt, time, pt);
      if (beforePt) d.fromLight[static_cast<size_t>(k_ - 1)] = vertexDensity(bdpt, time, nullptr, pt, *beforePt);
      return;
    }
    const PathVertex& qs = (*this)[t_];
    const PathVertex* beforeQs = s_ >= 2 ? &(*this)[t_ + 1] : nullptr;
    d.environmentEnd = light_[0].type == VertexType::Environment;
    d.fromCamera[static_cast<size_t>(t_)] = vertexDensity(bdpt, time, beforePt, pt, qs);
    if (beforeQs) d.fromCamera[static_cast<size_t>(t_ + 1)] = vertexDensity(bdpt, time, &pt, qs, *beforeQs);
    d.fromLight[static_cast<size_t>(t_ - 1)] = vertexDensity(bdpt, time, beforeQs, qs, pt);
    if (beforePt) d.fromLight[static_cast<size_t>(t_ - 2)] = vertexDensity(bdpt, time, &qs, pt, *beforePt);
  }

  void copyTo(Subpath& path) const {
    path.clear();
    for (int i = 0; i <= k_; ++i) path.push_back((*this)[i]);
    if (s_ == 0 && path.back().type == VertexType::Surface) path.back().type = VertexType::Light;
  }

 private:
  const Subpath& camera_;
  const Subpath& light_;
  int s_, t_, k_;
  const PathVertex& cameraEnd_;
  const PathVertex& lightEnd_;
};

// A connected vertex scatters through its non-delta lobes whatever its subpath sampled next.
PathVertex asConnected(const PathVertex& x) {
  PathVertex copy = x;
  copy.delta = false;
  return copy;
}

}  // namespace

bool isConnectible(const Scene& scene, const PathVertex& x) {
  if (x.type != VertexType::Surface) return true;
  // At the point's own parameters: a roughness texture may make a glossy lobe a delta one.
  const Material& material = ShadedVertex::materialOf(scene, x.hit);
  return Bsdf(material, surfaceAt(scene, material, x.hit.uv), scene.roughnessThreshold).hasNonDeltaLobe();
}

std::optional<StrategySample> connectStrategy(const BdptScene& bdpt, float time, const Subpath& camera,
                                              const Subpath& light, int s, int t, UniformSource& connection,
                                              Subpath* path, PathDensities* densities) {
  if (t < 1 || s < 0 || s + t < 2 || t > static_cast<int>(camera.size()) || s > static_cast<int>(light.size()))
    return std::nullopt;
  const Scene& scene = bdpt.scene();
  StrategySample result;
  PathVertex pt = asConnected(camera[static_cast<size_t>(t - 1)]);
  PathVertex qs = s > 0 ? asConnected(light[static_cast<size_t>(s - 1)]) : PathVertex{};
  bool visible = true;
  if (s == 0) {
    if (pt.type == VertexType::Camera) return std::nullopt;
    result.unweighted = pt.beta * emitted(scene, pt, directionBetween(pt, camera[static_cast<size_t>(t - 2)]));
    if (result.unweighted.isBlack()) return std::nullopt;
  } else {
    if (!isConnectible(scene, pt) || !isConnectible(scene, qs) || pt.type == VertexType::Environment)
      return std::nullopt;
    if (t == 1) {
      const Vec2f uLens = connection.next2D();
      if (qs.type == VertexType::Environment) return std::nullopt;
      // A point or spot light has no area: the camera does not see it, as in the path tracer.
      if (s == 1 && qs.isPunctual()) return std::nullopt;
      const auto c = bdpt.camera.connect(qs.position(), bdpt.seconds(time), uLens);
      if (!c) return std::nullopt;
      pt = PathVertex{};
      pt.type = VertexType::Camera;
      pt.hit.position = c->lensPoint;
      pt.hit.geometricNormal = bdpt.camera.viewDirection(bdpt.seconds(time));
      pt.beta = Rgb(1);
      pt.pdfFwd = bdpt.camera.lensDensity();
      result.lightTracing = true;
      result.raster = c->raster;
    }
    const Vec3f towardLight = directionBetween(pt, qs);
    const Rgb cameraSide = t == 1 ? Rgb(bdpt.camera.importance(pt.position(), towardLight, bdpt.seconds(time)) *
                                        dot(towardLight, pt.hit.geometricNormal) / bdpt.camera.lensDensity())
                                  : scattering(scene, pt, directionBetween(pt, camera[static_cast<size_t>(t - 2)]),
                                               towardLight);
    const Rgb lightSide = s == 1 ? emitted(scene, qs, -towardLight)
                                 : scattering(scene, qs, -towardLight,
                                              directionBetween(qs, light[static_cast<size_t>(s - 2)]));
    result.unweighted = pt.beta * cameraSide * edgeFactor(pt, qs) * lightSide * qs.beta;
    if (result.unweighted.isBlack()) return std::nullopt;
    if (qs.type == VertexType::Environment) {
      visible = bdpt.geometry.escapes(pt.hit, towardLight, time);
    } else if (t == 1) {
      visible = bdpt.geometry.connects(qs.hit, pt.position(), time);
    } else {
      visible = bdpt.geometry.connects(pt.hit, qs.position(), time);
    }
    if (!visible) return std::nullopt;
  }

  const JoinedPath joined(camera, light, s, t, pt, qs);
  PathDensities local;
  PathDensities& d = densities ? *densities : local;
  joined.densities(bdpt, time, d);
  result.misWeight = misWeight(d, t);
  result.contribution = result.unweighted * result.misWeight;
  if (path) joined.copyTo(*path);
  return result;
}

}  // namespace pathfarm
