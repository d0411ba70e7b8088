#include "renderer/accel/shutter_poses.h"

#include <algorithm>
#include <limits>

namespace pathfarm {
namespace {

// How far the middle pose's vertices lie from the midpoints of the outer poses'.
float chordDeviation(const MeshDeformation::Pose& first, const MeshDeformation::Pose& middle,
                     const MeshDeformation::Pose& last) {
  float deviation = 0;
  for (size_t v = 0; v < middle.positions.size(); ++v)
    deviation = std::max(deviation, length(middle.positions[v] - (first.positions[v] + last.positions[v]) * 0.5f));
  return deviation;
}

float extent(const MeshDeformation::Pose& pose) {
  Vec3f lower{std::numeric_limits<float>::max(), std::numeric_limits<float>::max(), std::numeric_limits<float>::max()};
  Vec3f upper = -lower;
  for (const Vec3f& p : pose.positions) {
    lower = {std::min(lower.x, p.x), std::min(lower.y, p.y), std::min(lower.z, p.z)};
    upper = {std::max(upper.x, p.x), std::max(upper.y, p.y), std::max(upper.z, p.z)};
  }
  return length(upper - lower);
}

}  // namespace

std::vector<MeshDeformation::Pose> shutterPoses(const MeshDeformation& deformation, double open, double close) {
  if (close <= open) return {deformation.poseAt(open)};
  const auto at = [&](size_t step, size_t steps) {
    return deformation.poseAt(open + (close - open) * static_cast<double>(step) / static_cast<double>(steps - 1));
  };
  MeshDeformation::Pose first = at(0, 3), middle = at(1, 3), last = at(2, 3);
  const float stray = chordDeviation(first, middle, last) / (kShutterPoseTolerance * extent(middle));
  // With n - 1 segments the stray is about 1 / (n - 1)^2 of one segment's.
  if (!(stray > 1)) return {std::move(first), std::move(last)};
  if (stray <= 4) return {std::move(first), std::move(middle), std::move(last)};
  const size_t steps = stray <= 16 ? 5 : 9;
  std::vector<MeshDeformation::Pose> poses;
  for (size_t s = 0; s < steps; ++s) {
    if (s == 0) poses.push_back(std::move(first));
    else if (2 * s == steps - 1) poses.push_back(std::move(middle));
    else if (s == steps - 1) poses.push_back(std::move(last));
    else poses.push_back(at(s, steps));
  }
  return poses;
}

}  // namespace pathfarm
