#pragma once
// The input of joint NL-means checked and made ready to filter (nlmeans.cpp's own part):
// sizes and settings validated, broken values cleaned out and their pixels marked invalid,
// missing feature variances and validity filled in, and each continuous feature's
// normalization at frame 0's pixels.
#include <algorithm>
#include <bit>
#include <cmath>
#include <deque>
#include <stdexcept>
#include <string>
#include <vector>

#include "image/size_text.h"
#include "postproc/filters/nlmeans.h"

namespace pathfarm::nlmeans_detail {

inline constexpr float kMaxColor = 1e15f;  // larger magnitudes count as broken pixels
inline constexpr float kMaxVariance = 1e30f;
// The largest exponent a weight e^-x is computed for (nlmeans.cpp, expNegative): beyond it
// the weight is 0.
inline constexpr float kExpClamp = 88.0f;
// The widest image whose patch distances are exact sums (Prepared::distanceSnap): 2^16.
inline constexpr int kWidthBits = 16;

inline void validate(const NlMeansInput& input, const NlMeansSettings& s) {
  if (s.radius < 0 || s.patch < 0)
    throw std::invalid_argument("NL-means: the search radius and patch size must not be negative");
  if (!(s.kf > 0.0f) || !std::isfinite(s.kf) || !(s.kc >= 0.0f) || !std::isfinite(s.kc) || !(s.tau >= 0.0f) ||
      !std::isfinite(s.alpha))
    throw std::invalid_argument("NL-means: k_f must be positive, k_c and tau not negative, alpha finite");
  if (input.frames.empty()) throw std::invalid_argument("NL-means: no frame to filter");
  const NlMeansFrame& first = input.frames[0];
  const int w = first.color.width, h = first.color.height;
  const size_t colorChannels = first.color.channels.size();
  if (w <= 0 || h <= 0 || colorChannels == 0) throw std::invalid_argument("NL-means: frame 0 has no color to filter");
  if (w > (1 << kWidthBits))
    throw std::invalid_argument("NL-means: frames wider than " + std::to_string(1 << kWidthBits) +
                                " pixels are not filtered (their patch sums would round)");
  const size_t pixels = first.color.pixelCount();
  const auto check = [&](const Planes& planes, size_t channels, const std::string& what) {
    if (planes.width != w || planes.height != h)
      throw std::invalid_argument("NL-means: " + what + " is " + sizeText(planes.width, planes.height) +
                                  ", the color of frame 0 is " + sizeText(w, h));
    if (planes.channels.size() != channels)
      throw std::invalid_argument("NL-means: " + what + " has " + std::to_string(planes.channels.size()) +
                                  " channels, expected " + std::to_string(channels));
    for (const auto& plane : planes.channels)
      if (plane.size() != pixels)
        throw std::invalid_argument("NL-means: a plane of " + what + " does not hold " + sizeText(w, h) + " pixels");
  };
  const size_t features = input.featureKinds.size();
  for (size_t g = 0; g < features && g < first.features.size(); ++g)
    if (first.features[g].channels.empty())
      throw std::invalid_argument("NL-means: feature " + std::to_string(g) + " of frame 0 has no channel");
  for (size_t t = 0; t < input.frames.size(); ++t) {
    const NlMeansFrame& frame = input.frames[t];
    const std::string label = "frame " + std::to_string(t);
    check(frame.color, colorChannels, label + "'s color");
    check(frame.variance, colorChannels, label + "'s variance");
    if (frame.features.size() != features)
      throw std::invalid_argument("NL-means: " + label + " has " + std::to_string(frame.features.size()) +
                                  " features, expected " + std::to_string(features));
    for (size_t g = 0; g < features; ++g)
      check(frame.features[g], first.features[g].channels.size(), label + "'s feature " + std::to_string(g));
    if (!frame.featureVariance.empty()) {
      if (frame.featureVariance.size() != features)
        throw std::invalid_argument("NL-means: " + label + " has feature variances for " +
                                    std::to_string(frame.featureVariance.size()) + " of " + std::to_string(features) +
                                    " features");
      for (size_t g = 0; g < features; ++g)
        if (!frame.featureVariance[g].channels.empty())
          check(frame.featureVariance[g], first.features[g].channels.size(),
                label + "'s variance of feature " + std::to_string(g));
    }
    if (!frame.valid.empty() && frame.valid.size() != pixels)
      throw std::invalid_argument("NL-means: " + label + "'s validity does not hold " + sizeText(w, h) + " pixels");
  }
}

// The input as flat pointers, with broken values replaced (in copies) and flagged invalid.
class Prepared {
 public:
  struct Frame {
    std::vector<const float*> color, variance;
    std::vector<std::vector<const float*>> feature;
    std::vector<std::vector<const float*>> featureVariance;  // per feature: empty, or a plane per channel
    const float* valid = nullptr;
    bool active = false;  // some pixel contributes
  };

  int width = 0, height = 0, channels = 0;
  std::vector<Frame> frames;
  std::vector<FeatureKind> kinds;
  std::vector<int> featureChannels;
  std::vector<std::vector<float>> featureScale;  // continuous features: 1 / (C_g kf^2 max(...)) at frame 0's pixels
  std::vector<uint8_t> invalidCenter;
  size_t invalidCenters = 0;
  float distanceLow = 0, distanceHigh = 0;  // per-pixel color distances are clamped to [-low, high]
  // Adding and subtracting this rounds a clamped distance to a grid on which a double sums
  // a row of patch columns exactly, in any order (nlmeans.cpp's box sums), for images up
  // to 2^16 pixels wide (validate refuses wider ones): 52 bits hold the bound, the patch's
  // rows and the width. (The build's -fno-fast-math keeps the compiler from folding it.)
  double distanceSnap = 0;

  Prepared(const NlMeansInput& input, const NlMeansSettings& s) {
    validate(input, s);
    const NlMeansFrame& first = input.frames[0];
    width = first.color.width;
    height = first.color.height;
    channels = static_cast<int>(first.color.channels.size());
    kinds = input.featureKinds;
    for (const Planes& feature : first.features) featureChannels.push_back(static_cast<int>(feature.channels.size()));
    const size_t pixels = first.color.pixelCount();

    for (size_t t = 0; t < input.frames.size(); ++t) {
      const NlMeansFrame& in = input.frames[t];
      Frame frame;
      std::vector<float>& valid = storage_.emplace_back(pixels, 1.0f);
      if (!in.valid.empty())
        for (size_t p = 0; p < pixels; ++p) valid[p] = (in.valid[p] != 0.0f && !std::isnan(in.valid[p])) ? 1.0f : 0.0f;
      for (const auto& plane : in.color.channels) frame.color.push_back(clean(plane, Value::Color, &valid));
      for (const auto& plane : in.variance.channels) frame.variance.push_back(clean(plane, Value::Variance, &valid));
      for (size_t g = 0; g < in.features.size(); ++g) {
        std::vector<const float*> planes;
        for (const auto& plane : in.features[g].channels) planes.push_back(clean(plane, Value::Feature, nullptr));
        frame.feature.push_back(std::move(planes));
        std::vector<const float*> variances;
        if (g < in.featureVariance.size())
          for (const auto& plane : in.featureVariance[g].channels)
            variances.push_back(clean(plane, Value::FeatureVariance, nullptr));
        frame.featureVariance.push_back(std::move(variances));
      }
      frame.valid = valid.data();
      frame.active = std::any_of(valid.begin(), valid.end(), [](float v) { return v != 0.0f; });
      if (t == 0) {
        invalidCenter.resize(pixels);
        for (size_t p = 0; p < pixels; ++p) {
          invalidCenter[p] = valid[p] == 0.0f;
          invalidCenters += invalidCenter[p];
        }
      }
      frames.push_back(std::move(frame));
    }
    // Where only one frame of a pair has feature variances, the other's count as zero.
    for (size_t g = 0; g < kinds.size(); ++g) {
      const bool any =
          std::any_of(frames.begin(), frames.end(), [&](const Frame& f) { return !f.featureVariance[g].empty(); });
      if (!any) continue;
      for (Frame& f : frames)
        if (f.featureVariance[g].empty())
          f.featureVariance[g].assign(static_cast<size_t>(featureChannels[g]), zeros(pixels));
    }
    computeFeatureScales(s);

    // A pixel's distance is at least -2 alpha / kc^2 (the cancellation term over the
    // denominator); clamping it above at `high` keeps any patch holding a clamped pixel
    // beyond the exp cutoff, so the clamp never changes a weight.
    const float patchPixels = static_cast<float>((2 * s.patch + 1) * (2 * s.patch + 1));
    distanceLow = s.kc > 0.0f ? std::min(1e6f, std::max(0.0f, 2.0f * s.alpha / (s.kc * s.kc))) : 1e6f;
    if (!(s.alpha > 0.0f)) distanceLow = 0.0f;
    distanceHigh = patchPixels * kExpClamp + (patchPixels - 1.0f) * distanceLow;
    const int boundExponent = std::ilogb(std::max(distanceHigh, distanceLow)) + 1;
    const int patchRowBits = std::bit_width(static_cast<unsigned>(2 * s.patch + 1));
    distanceSnap = std::ldexp(1.5, boundExponent + patchRowBits + kWidthBits);
  }

 private:
  enum class Value { Color, Variance, Feature, FeatureVariance };

  static bool broken(float v, Value kind) {
    switch (kind) {
      case Value::Color:
      case Value::Feature:
        return !std::isfinite(v) || std::abs(v) > kMaxColor;
      case Value::Variance:
      case Value::FeatureVariance:
        return !std::isfinite(v) || v > kMaxVariance;
    }
    return false;
  }

  // `plane` itself when every value is usable, else a copy with broken values set to 0 (and
  // their pixels marked invalid) and negative variances set to 0.
  const float* clean(const std::vector<float>& plane, Value kind, std::vector<float>* valid) {
    const bool variance = kind == Value::Variance || kind == Value::FeatureVariance;
    const bool needsCopy =
        std::any_of(plane.begin(), plane.end(), [&](float v) { return broken(v, kind) || (variance && v < 0.0f); });
    if (!needsCopy) return plane.data();
    std::vector<float>& copy = storage_.emplace_back(plane);
    for (size_t p = 0; p < copy.size(); ++p) {
      if (broken(copy[p], kind)) {
        copy[p] = 0.0f;
        if (valid != nullptr && kind != Value::FeatureVariance) (*valid)[p] = 0.0f;
      } else if (variance && copy[p] < 0.0f) {
        copy[p] = 0.0f;
      }
    }
    return copy.data();
  }

  const float* zeros(size_t pixels) {
    if (zeros_ == nullptr) zeros_ = storage_.emplace_back(pixels, 0.0f).data();
    return zeros_;
  }

  // The normalization of each continuous feature's distance at frame 0's pixels.
  void computeFeatureScales(const NlMeansSettings& s) {
    featureScale.resize(kinds.size());
    const Frame& first = frames[0];
    const size_t w = static_cast<size_t>(width);
    for (size_t g = 0; g < kinds.size(); ++g) {
      if (kinds[g] != FeatureKind::Continuous) continue;
      const int count = featureChannels[g];
      std::vector<float>& scale = featureScale[g];
      scale.assign(w * static_cast<size_t>(height), 0.0f);
      std::vector<float> variance(scale.size(), 0.0f), gradient(scale.size(), 0.0f);
      for (int j = 0; j < count; ++j) {
        const float* f = first.feature[g][static_cast<size_t>(j)];
        if (!first.featureVariance[g].empty()) {
          const float* v = first.featureVariance[g][static_cast<size_t>(j)];
          for (size_t p = 0; p < scale.size(); ++p) variance[p] += v[p];
        }
        for (int y = 0; y < height; ++y) {
          const size_t up = static_cast<size_t>(std::max(0, y - 1)) * w,
                       down = static_cast<size_t>(std::min(height - 1, y + 1)) * w;
          const size_t row = static_cast<size_t>(y) * w;
          for (int x = 0; x < width; ++x) {
            const size_t left = static_cast<size_t>(std::max(0, x - 1)),
                         right = static_cast<size_t>(std::min(width - 1, x + 1));
            const float gx = 0.5f * (f[row + right] - f[row + left]);
            const float gy = 0.5f * (f[down + static_cast<size_t>(x)] - f[up + static_cast<size_t>(x)]);
            gradient[row + static_cast<size_t>(x)] += gx * gx + gy * gy;
          }
        }
      }
      const float inverseCount = 1.0f / static_cast<float>(count);
      const float kf2 = s.kf * s.kf;
      for (size_t p = 0; p < scale.size(); ++p) {
        const float normalization = std::max({s.tau, variance[p] * inverseCount, gradient[p] * inverseCount, 1e-30f});
        scale[p] = 1.0f / (static_cast<float>(count) * kf2 * normalization);
      }
    }
  }

  std::deque<std::vector<float>> storage_;  // cleaned copies and validity (stable addresses)
  const float* zeros_ = nullptr;
};

}  // namespace pathfarm::nlmeans_detail
