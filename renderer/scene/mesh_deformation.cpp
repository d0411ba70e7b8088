#include "renderer/scene/mesh_deformation.h"

#include <cmath>

namespace pathfarm {
namespace {

using Matrix = std::array<float, 12>;  // 3x4, row-major

Vec3f applyPoint(const Matrix& m, Vec3f p) {
  return {m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3], m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
          m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]};
}

Vec3f applyVector(const Matrix& m, Vec3f v) {
  return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[4] * v.x + m[5] * v.y + m[6] * v.z,
          m[8] * v.x + m[9] * v.y + m[10] * v.z};
}

// Normals take the inverse transpose of the linear part; its direction is the cofactor
// matrix's, times the determinant's sign (a blend of joints need not be invertible
// cheaply, but its cofactors always exist).
Vec3f applyNormal(const Matrix& m, Vec3f n) {
  const float c00 = m[5] * m[10] - m[6] * m[9], c01 = m[6] * m[8] - m[4] * m[10], c02 = m[4] * m[9] - m[5] * m[8];
  const float c10 = m[2] * m[9] - m[1] * m[10], c11 = m[0] * m[10] - m[2] * m[8], c12 = m[1] * m[8] - m[0] * m[9];
  const float c20 = m[1] * m[6] - m[2] * m[5], c21 = m[2] * m[4] - m[0] * m[6], c22 = m[0] * m[5] - m[1] * m[4];
  const float det = m[0] * c00 + m[1] * c01 + m[2] * c02;
  const Vec3f cofactor{c00 * n.x + c01 * n.y + c02 * n.z, c10 * n.x + c11 * n.y + c12 * n.z,
                       c20 * n.x + c21 * n.y + c22 * n.z};
  return det < 0 ? -cofactor : cofactor;
}

Vec3f unit(Vec3f v, Vec3f fallback) {
  const float l = length(v);
  return l > 1e-20f && std::isfinite(l) ? v / l : fallback;
}

}  // namespace

MeshDeformation::MeshDeformation(std::shared_ptr<const TriangleMesh> rest, std::vector<MorphTarget> targets,
                                 MorphWeights weights, std::optional<Skin> skin, AnimatedTrs placement)
    : rest_(std::move(rest)),
      targets_(std::move(targets)),
      weights_(std::move(weights)),
      skin_(std::move(skin)),
      placement_(std::move(placement)) {}

std::vector<float> MeshDeformation::weightsAt(double seconds) const {
  if (!weights_.animated) return weights_.rest;
  std::vector<double> sampled(weights_.animated->width);
  weights_.animated->sample(seconds, sampled.data());
  return {sampled.begin(), sampled.end()};
}

Transform MeshDeformation::jointMatrix(size_t joint, double seconds) const {
  return skin_->joints[joint].transformAt(seconds) * skin_->inverseBind[joint];
}

Matrix MeshDeformation::vertexMatrix(uint32_t vertex, const std::vector<Transform>& jointMatrices) const {
  Matrix blend{};
  for (uint32_t i = skin_->firstInfluence[vertex]; i < skin_->firstInfluence[vertex + 1]; ++i) {
    const JointInfluence& influence = skin_->influences[i];
    const Matrix& m = jointMatrices[influence.joint].matrix();
    for (size_t k = 0; k < 12; ++k) blend[k] += influence.weight * m[k];
  }
  return blend;
}

MeshDeformation::Pose MeshDeformation::poseAt(double seconds) const {
  const TriangleMesh& mesh = *rest_;
  Pose pose{mesh.positions, mesh.normals, mesh.tangents};
  const std::vector<float> weights = weightsAt(seconds);
  for (size_t t = 0; t < targets_.size(); ++t) {
    const float w = weights[t];
    if (w == 0) continue;
    const MorphTarget& target = targets_[t];
    for (size_t v = 0; v < target.positions.size(); ++v) pose.positions[v] += target.positions[v] * w;
    if (!pose.normals.empty())
      for (size_t v = 0; v < target.normals.size(); ++v) pose.normals[v] += target.normals[v] * w;
    if (!pose.tangents.empty())
      for (size_t v = 0; v < target.tangents.size(); ++v) pose.tangents[v] += target.tangents[v] * w;
  }
  std::vector<Matrix> perVertex;
  if (skin_) {
    std::vector<Transform> joints;
    for (size_t j = 0; j < skin_->joints.size(); ++j) joints.push_back(jointMatrix(j, seconds));
    perVertex.reserve(mesh.positions.size());
    for (uint32_t v = 0; v < mesh.positions.size(); ++v) perVertex.push_back(vertexMatrix(v, joints));
  } else {
    perVertex.assign(mesh.positions.size(), placement_.transformAt(seconds).matrix());
  }
  for (size_t v = 0; v < pose.positions.size(); ++v) {
    const Matrix& m = perVertex[v];
    pose.positions[v] = applyPoint(m, pose.positions[v]);
    if (!pose.normals.empty()) pose.normals[v] = unit(applyNormal(m, pose.normals[v]), mesh.normals[v]);
    if (!pose.tangents.empty()) pose.tangents[v] = unit(applyVector(m, pose.tangents[v]), mesh.tangents[v]);
  }
  return pose;
}

Vec3f MeshDeformation::positionAt(uint32_t vertex, double seconds) const {
  Vec3f p = rest_->positions[vertex];
  if (!targets_.empty()) {
    const std::vector<float> weights = weightsAt(seconds);
    for (size_t t = 0; t < targets_.size(); ++t)
      if (!targets_[t].positions.empty()) p += targets_[t].positions[vertex] * weights[t];
  }
  if (!skin_) return placement_.transformAt(seconds).point(p);
  // Only the joints this vertex follows are placed.
  std::vector<Transform> joints(skin_->joints.size());
  for (uint32_t i = skin_->firstInfluence[vertex]; i < skin_->firstInfluence[vertex + 1]; ++i) {
    const uint32_t joint = skin_->influences[i].joint;
    joints[joint] = jointMatrix(joint, seconds);
  }
  return applyPoint(vertexMatrix(vertex, joints), p);
}

bool MeshDeformation::isAnimated() const {
  if (weights_.animated && weights_.animated->times.size() > 1) return true;
  if (!skin_) return placement_.isAnimated();
  for (const AnimatedTrs& joint : skin_->joints)
    if (joint.isAnimated()) return true;
  return false;
}

}  // namespace pathfarm
