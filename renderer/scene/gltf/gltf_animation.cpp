#include "renderer/scene/gltf/gltf_animation.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace pathfarm {
namespace {

// Spacing of the keys that approximate motion which is not linear between the file's
// keys: four per frame at 24 frames per second.
constexpr double kDenseStep = 1.0 / 96;
// A STEP key holds its value until this long before the next key.
constexpr double kStepLead = 1e-5;
// Key times beyond this (about 28 hours) and nodes needing more samples than this are
// taken as hostile input, not as a shot.
constexpr double kMaxKeyTime = 1e5;
constexpr size_t kMaxSamplesPerNode = size_t{1} << 20;

Mat3d rotationMatrix(const Quaternion& q) {
  const double w = q.w, x = q.x, y = q.y, z = q.z;
  return Mat3d::fromColumns({1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)},
                            {2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)},
                            {2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)});
}

Affine3d fromTrs(const Trs& trs) {
  const Mat3d scale = Mat3d::fromColumns({trs.scale.x, 0, 0}, {0, trs.scale.y, 0}, {0, 0, trs.scale.z});
  return {rotationMatrix(trs.rotation) * scale, Vec3d(trs.translation)};
}

Vec3d column(const Mat3d& m, int j) { return {m.m[0][j], m.m[1][j], m.m[2][j]}; }

// The placement as translation, rotation and scale, or an explanation of why it is not one.
struct Decomposition {
  Trs trs;
  const char* problem = nullptr;
};

Decomposition decomposeAffine(const Affine3d& a) {
  Decomposition d;
  Vec3d axes[3];
  double scales[3];
  for (int j = 0; j < 3; ++j) {
    axes[j] = column(a.linear, j);
    scales[j] = length(axes[j]);
    if (!(scales[j] > 1e-12) || !std::isfinite(scales[j])) {
      d.problem = "a zero or non-finite scale";
      return d;
    }
    axes[j] = axes[j] / scales[j];
  }
  if (a.linear.determinant() < 0) {  // a mirror: put the reflection into the x scale
    scales[0] = -scales[0];
    axes[0] = -axes[0];
  }
  if (std::abs(dot(axes[0], axes[1])) > 1e-4 || std::abs(dot(axes[0], axes[2])) > 1e-4 ||
      std::abs(dot(axes[1], axes[2])) > 1e-4) {
    d.problem = "shear (a parent's non-uniform scale applied to a rotated child)";
    return d;
  }
  d.trs.translation = a.translation.toFloat();
  d.trs.rotation = Quaternion::fromBasis(axes[0].toFloat(), axes[1].toFloat(), axes[2].toFloat());
  d.trs.scale = Vec3d{scales[0], scales[1], scales[2]}.toFloat();
  return d;
}

}  // namespace

GltfNodeAnimation::GltfNodeAnimation(const GltfDocument& document) : document_(document) {
  const tinygltf::Model& model = document.model();
  const size_t n = model.nodes.size();
  parents_.assign(n, -1);
  rest_.resize(n);
  channels_.resize(n);
  weights_.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const tinygltf::Node& node = model.nodes[i];
    const std::string pointer = gltfPointer("nodes", static_cast<int>(i));
    for (const int child : node.children) {
      if (child < 0 || static_cast<size_t>(child) >= n)
        document.fail(pointer + "/children", "node " + std::to_string(child) + " does not exist");
      if (parents_[static_cast<size_t>(child)] != -1 || static_cast<size_t>(child) == i)
        document.fail(pointer + "/children", "node " + std::to_string(child) + " has more than one parent");
      parents_[static_cast<size_t>(child)] = static_cast<int>(i);
    }
    if (node.matrix.size() == 16) {
      const auto& m = node.matrix;  // column-major
      Affine3d a;
      a.linear = Mat3d::fromColumns({m[0], m[1], m[2]}, {m[4], m[5], m[6]}, {m[8], m[9], m[10]});
      a.translation = {m[12], m[13], m[14]};
      const Decomposition d = decomposeAffine(a);
      if (d.problem) document.fail(pointer + "/matrix", std::string("the matrix has ") + d.problem);
      rest_[i] = d.trs;
    } else {
      Trs& trs = rest_[i];
      if (node.translation.size() == 3) trs.translation = Vec3d{node.translation[0], node.translation[1], node.translation[2]}.toFloat();
      if (node.scale.size() == 3) trs.scale = Vec3d{node.scale[0], node.scale[1], node.scale[2]}.toFloat();
      if (node.rotation.size() == 4) {
        const Quaternion q{static_cast<float>(node.rotation[3]), static_cast<float>(node.rotation[0]),
                           static_cast<float>(node.rotation[1]), static_cast<float>(node.rotation[2])};
        if (!(dot(q, q) > 1e-12f) || !std::isfinite(dot(q, q)))
          document.fail(pointer + "/rotation", "the rotation quaternion has zero length");
        trs.rotation = q.normalized();
      }
    }
  }
  // A cycle leaves some node whose chain of parents never reaches a root.
  for (size_t i = 0; i < n; ++i) {
    size_t steps = 0;
    for (int p = parents_[i]; p != -1; p = parents_[static_cast<size_t>(p)]) {
      if (++steps > n) document.fail(gltfPointer("nodes", static_cast<int>(i)), "the node hierarchy has a cycle");
    }
  }
  readAnimations();
}

void GltfNodeAnimation::readAnimations() {
  const tinygltf::Model& model = document_.model();
  for (size_t a = 0; a < model.animations.size(); ++a) {
    const tinygltf::Animation& animation = model.animations[a];
    const std::string base = gltfPointer("animations", static_cast<int>(a));
    for (size_t c = 0; c < animation.channels.size(); ++c) {
      const tinygltf::AnimationChannel& source = animation.channels[c];
      const std::string pointer = base + "/channels/" + std::to_string(c);
      if (source.target_node < 0) continue;  // no target: the channel animates nothing
      if (static_cast<size_t>(source.target_node) >= channels_.size())
        document_.fail(pointer + "/target/node", "node " + std::to_string(source.target_node) + " does not exist");
      if (source.target_path == "weights") {
        KeyTrack& weights = weights_[static_cast<size_t>(source.target_node)];
        if (!weights.times.empty())
          document_.fail(pointer, "a second channel animates the same node's morph target weights");
        weights = readTrack(animation, source.sampler, 0, pointer);
        duration_ = std::max(duration_, weights.times.back());
        continue;
      }
      Channel channel;
      channel.node = source.target_node;
      size_t width = 3;
      if (source.target_path == "translation") {
        channel.path = Path::Translation;
      } else if (source.target_path == "scale") {
        channel.path = Path::Scale;
      } else if (source.target_path == "rotation") {
        channel.path = Path::Rotation;
        width = 4;
      } else {
        document_.fail(pointer + "/target/path", "unknown target path \"" + source.target_path + "\"");
      }
      channel.track = readTrack(animation, source.sampler, width, pointer);
      duration_ = std::max(duration_, channel.track.times.back());
      channels_[static_cast<size_t>(channel.node)].push_back(std::move(channel));
    }
  }
}

KeyTrack GltfNodeAnimation::readTrack(const tinygltf::Animation& animation, int samplerIndex, size_t width,
                                      const std::string& channelPointer) {
  if (samplerIndex < 0 || static_cast<size_t>(samplerIndex) >= animation.samplers.size())
    document_.fail(channelPointer + "/sampler", "sampler " + std::to_string(samplerIndex) + " does not exist");
  const tinygltf::AnimationSampler& sampler = animation.samplers[static_cast<size_t>(samplerIndex)];
  const std::string pointer =
      channelPointer.substr(0, channelPointer.rfind("/channels/")) + "/samplers/" + std::to_string(samplerIndex);
  KeyTrack track;
  if (sampler.interpolation == "STEP") {
    track.interpolation = KeyInterpolation::Step;
  } else if (sampler.interpolation == "CUBICSPLINE") {
    track.interpolation = KeyInterpolation::CubicSpline;
  } else if (sampler.interpolation.empty() || sampler.interpolation == "LINEAR") {
    track.interpolation = KeyInterpolation::Linear;
  } else {
    document_.fail(pointer + "/interpolation", "unknown interpolation \"" + sampler.interpolation + "\"");
  }
  const std::vector<float> times = document_.readFloats(sampler.input, 1, pointer + "/input");
  if (times.empty()) document_.fail(pointer + "/input", "a sampler needs at least one key");
  for (size_t k = 0; k < times.size(); ++k) {
    if (times[k] < 0 || times[k] > kMaxKeyTime || (k > 0 && !(times[k] > times[k - 1])))
      document_.fail(pointer + "/input", "key times must lie in [0, " + std::to_string(kMaxKeyTime) +
                                             "] s and increase strictly");
    track.times.push_back(times[k]);
  }
  const size_t perKey = track.interpolation == KeyInterpolation::CubicSpline ? 3 : 1;
  // Weights are SCALAR outputs, one per target and key: their width follows from the count.
  track.values = document_.readFloats(sampler.output, width == 0 ? 1 : static_cast<int>(width), pointer + "/output");
  track.width = width == 0 ? track.values.size() / (track.times.size() * perKey) : width;
  if (track.width == 0 || track.values.size() != track.times.size() * perKey * track.width)
    document_.fail(pointer + "/output", "has " + std::to_string(track.values.size()) + " numbers for " +
                                            std::to_string(track.times.size()) + " keys of " +
                                            std::to_string(std::max<size_t>(track.width, 1)) + " components");
  return track;
}

const KeyTrack* GltfNodeAnimation::weightTrack(int node) const {
  const KeyTrack& track = weights_[static_cast<size_t>(node)];
  return track.times.empty() ? nullptr : &track;
}

Affine3d GltfNodeAnimation::localAt(int node, double seconds) const {
  Trs trs = rest_[static_cast<size_t>(node)];
  for (const Channel& c : channels_[static_cast<size_t>(node)]) {
    std::array<double, 4> v{};
    const KeyTrack::Segment s = c.track.locate(seconds);
    if (c.path == Path::Rotation && c.track.interpolation == KeyInterpolation::Linear && !s.hold) {
      const auto quaternion = [&](size_t key) {
        return Quaternion{c.track.keyValue(key, 3), c.track.keyValue(key, 0), c.track.keyValue(key, 1),
                          c.track.keyValue(key, 2)};
      };
      const Quaternion q = slerp(quaternion(s.key), quaternion(s.key + 1), static_cast<float>(s.fraction));
      v = {q.x, q.y, q.z, q.w};
    } else {
      c.track.sample(seconds, v.data());
    }
    const Vec3f xyz = Vec3d{v[0], v[1], v[2]}.toFloat();
    if (c.path == Path::Translation) trs.translation = xyz;
    if (c.path == Path::Scale) trs.scale = xyz;
    if (c.path == Path::Rotation) {
      const Quaternion q{static_cast<float>(v[3]), xyz.x, xyz.y, xyz.z};
      if (dot(q, q) > 1e-12f) trs.rotation = q.normalized();
    }
  }
  return fromTrs(trs);
}

Affine3d GltfNodeAnimation::worldAt(int node, double seconds) const {
  Affine3d world = localAt(node, seconds);
  for (int p = parents_[static_cast<size_t>(node)]; p != -1; p = parents_[static_cast<size_t>(p)])
    world = localAt(p, seconds) * world;
  return world;
}

std::vector<double> GltfNodeAnimation::sampleTimes(int node) const {
  std::vector<double> times;
  int animatedNodes = 0;
  bool nonlinear = false;
  for (int n = node; n != -1; n = parents_[static_cast<size_t>(n)]) {
    const auto& channels = channels_[static_cast<size_t>(n)];
    if (!channels.empty()) ++animatedNodes;
    for (const Channel& c : channels) {
      const std::vector<double>& keys = c.track.times;
      times.insert(times.end(), keys.begin(), keys.end());
      if (c.track.interpolation == KeyInterpolation::CubicSpline) nonlinear = true;
      if (c.track.interpolation == KeyInterpolation::Step) {
        for (size_t k = 1; k < keys.size(); ++k) times.push_back(std::max(keys[k - 1], keys[k] - kStepLead));
      }
    }
  }
  if (times.empty()) return times;
  if (times.size() > kMaxSamplesPerNode)
    document_.fail(gltfPointer("nodes", node), "its animation has more than " + std::to_string(kMaxSamplesPerNode) +
                                                   " keys");
  std::sort(times.begin(), times.end());
  if (animatedNodes > 1 || nonlinear) {
    const double first = times.front(), last = times.back();
    const double span = std::ceil((last - first) / kDenseStep);
    if (span + static_cast<double>(times.size()) > static_cast<double>(kMaxSamplesPerNode))
      document_.fail(gltfPointer("nodes", node), "its animation would need more than " +
                                                     std::to_string(kMaxSamplesPerNode) + " samples");
    const auto steps = static_cast<size_t>(span);
    for (size_t i = 1; i < steps; ++i) times.push_back(first + static_cast<double>(i) * kDenseStep);
    std::sort(times.begin(), times.end());
  }
  // Keys must be strictly increasing; merge times closer than rounding can separate.
  std::vector<double> unique;
  for (const double t : times) {
    if (unique.empty() || t - unique.back() > 1e-7) unique.push_back(t);
  }
  return unique;
}

Trs GltfNodeAnimation::decompose(int node, const Affine3d& placement, bool withScale) const {
  const Decomposition d = decomposeAffine(placement);
  if (d.problem) {
    document_.fail(gltfPointer("nodes", node),
                   std::string("the node's world placement has ") + d.problem + ", which pathfarm cannot represent");
  }
  Trs trs = d.trs;
  if (!withScale) trs.scale = {1, 1, 1};
  return trs;
}

AnimatedTrs GltfNodeAnimation::worldTransform(int node, bool withScale) const {
  const std::vector<double> times = sampleTimes(node);
  if (times.empty()) return AnimatedTrs(decompose(node, worldAt(node, 0), withScale));
  AnimatedTrs animated(decompose(node, worldAt(node, times.front()), withScale));
  std::vector<Keyframe<Vec3f>> translation, scale;
  std::vector<Keyframe<Quaternion>> rotation;
  for (const double t : times) {
    const Trs trs = decompose(node, worldAt(node, t), withScale);
    translation.push_back({t, trs.translation});
    rotation.push_back({t, trs.rotation});
    scale.push_back({t, trs.scale});
  }
  animated.setTranslationKeys(std::move(translation));
  animated.setRotationKeys(std::move(rotation));
  animated.setScaleKeys(std::move(scale));
  return animated;
}

}  // namespace pathfarm
