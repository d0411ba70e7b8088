#include "renderer/integrators/gradient_estimates.h"

#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

#include "renderer/integrators/gradient_path_tracer.h"

namespace pathfarm {
namespace {

const char* const kChannels[3] = {"R", "G", "B"};
const std::string kWhose = "the gradient estimates";

std::string directional(const char* moment, size_t k) { return moment + std::to_string(k); }

// Adds moment `name`: per pixel the mean and variance of the mean of `moment(sums)` over
// `count(sums)` samples.
template <typename Moment, typename Count>
void addMoment(FrameImage& image, const std::string& name, const std::vector<GradientPixelSums>& sums, Moment moment,
               Count count) {
  for (size_t c = 0; c < 3; ++c) {
    std::vector<float>& mean = image.addChannel(name + "." + kChannels[c]);
    std::vector<float>& variance = image.addChannel(name + ".variance." + kChannels[c]);
    for (size_t p = 0; p < sums.size(); ++p) {
      const SampleMoments& m = moment(sums[p]);
      mean[p] = static_cast<float>(m.mean(c, count(sums[p])));
      variance[p] = static_cast<float>(m.varianceOfMean(c, count(sums[p])));
    }
  }
}

// A moment's mean and variance planes in estimates of the whole frame.
struct MomentPlanes {
  std::array<const float*, 3> mean{}, variance{};

  MomentPlanes() = default;
  MomentPlanes(const FrameImage& estimates, const std::string& name) {
    for (size_t c = 0; c < 3; ++c) {
      mean[c] = channelOf(estimates, name + "." + kChannels[c], kWhose).data();
      variance[c] = channelOf(estimates, name + ".variance." + kChannels[c], kWhose).data();
    }
  }
};

// The frame's layers from its estimates: each pair (p, p + d) is estimated from both
// pixels' samples, so this is where neighbours meet.
class FrameLayers {
 public:
  explicit FrameLayers(const FrameImage& estimates)
      : width_(estimates.width()),
        height_(estimates.height()),
        temporal_(estimates.hasChannel("temporal.R")),
        own_(estimates, "own"),
        direct_(estimates, "direct") {
    for (size_t k = 0; k < 4; ++k) {
      offset_[k] = MomentPlanes(estimates, directional("offset", k));
      difference_[k] = MomentPlanes(estimates, directional("difference", k));
    }
    if (!temporal_) return;
    temporalDifference_ = MomentPlanes(estimates, "temporal");
    for (size_t k = 0; k < 4; ++k) mixed_[k] = MomentPlanes(estimates, directional("mixed", k));
    mixedSamples_ = channelOf(estimates, "mixed_samples.Y", kWhose).data();
    targetX_ = channelOf(estimates, "temporal.target.X", kWhose).data();
    targetY_ = channelOf(estimates, "temporal.target.Y", kWhose).data();
  }

  bool temporal() const { return temporal_; }
  size_t pixels() const { return static_cast<size_t>(width_) * static_cast<size_t>(height_); }

  size_t neighbour(size_t p, size_t k) const {
    const int x = static_cast<int>(p % static_cast<size_t>(width_)) + kShiftDirections[k][0];
    const int y = static_cast<int>(p / static_cast<size_t>(width_)) + kShiftDirections[k][1];
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return SIZE_MAX;
    return static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x);
  }
  // The primal estimate: for each of the 4 pairs the pixel is in, its own samples' part
  // plus the neighbour's offsets' part, averaged over the pairs.
  double primal(size_t p, size_t c, double* variance) const {
    double value = own_.mean[c][p], v = own_.variance[c][p];
    for (size_t k = 0; k < 4; ++k) {
      const size_t n = neighbour(p, k);
      if (n == SIZE_MAX) continue;
      value += 0.25 * offset_[k ^ 1].mean[c][n];
      v += 0.0625 * offset_[k ^ 1].variance[c][n];
    }
    if (variance) *variance = v;
    return value;
  }
  // I(p + d) - I(p) for d = +x (k = 0) or +y (k = 2): p's forward differences minus the
  // neighbour's backward ones (which estimate I(p) - I(p + d)).
  double gradient(size_t p, size_t k, size_t c, double* variance) const {
    const size_t n = neighbour(p, k);
    if (n == SIZE_MAX) {
      if (variance) *variance = 0;
      return 0;
    }
    const MomentPlanes &forward = difference_[k], &backward = difference_[k ^ 1];
    if (variance) *variance = static_cast<double>(forward.variance[c][p]) + backward.variance[c][n];
    return static_cast<double>(forward.mean[c][p]) - backward.mean[c][n];
  }
  // What adaptive sampling follows: the spatial differences' variance relative to the
  // squared primal value (relMSE's denominator).
  std::vector<float> relativeVariance() const {
    std::vector<float> out(pixels());
    for (size_t p = 0; p < out.size(); ++p) {
      double total = 0;
      for (size_t c = 0; c < 3; ++c) {
        double vx = 0, vy = 0;
        gradient(p, 0, c, &vx);
        gradient(p, 2, c, &vy);
        const double value = primal(p, c, nullptr);
        total += (vx + vy) / (value * value + 0.01);
      }
      out[p] = static_cast<float>(total);
    }
    return out;
  }

  // The beauty (primal plus direct emission), the primal estimate, the spatial
  // differences and the direct emission, each with its variance.
  void writeSpatial(FrameImage& image) const {
    for (size_t c = 0; c < 3; ++c) {
      const std::string ch = kChannels[c];
      auto& beauty = image.addChannel(ch);
      auto& beautyVariance = image.addChannel("variance." + ch);
      auto& primal = image.addChannel("primal." + ch);
      auto& primalVariance = image.addChannel("primal.variance." + ch);
      auto& gx = image.addChannel("gradient_x." + ch);
      auto& gxVariance = image.addChannel("gradient_x.variance." + ch);
      auto& gy = image.addChannel("gradient_y." + ch);
      auto& gyVariance = image.addChannel("gradient_y.variance." + ch);
      auto& direct = image.addChannel("direct_emission." + ch);
      for (size_t p = 0; p < pixels(); ++p) {
        double v = 0;
        primal[p] = static_cast<float>(this->primal(p, c, &v));
        primalVariance[p] = static_cast<float>(v);
        gx[p] = static_cast<float>(gradient(p, 0, c, &v));
        gxVariance[p] = static_cast<float>(v);
        gy[p] = static_cast<float>(gradient(p, 2, c, &v));
        gyVariance[p] = static_cast<float>(v);
        direct[p] = direct_.mean[c][p];
        beauty[p] = primal[p] + direct[p];
        beautyVariance[p] = primalVariance[p] + direct_.variance[c][p];
      }
    }
  }

  void writeTemporalDifferences(FrameImage& image) const {
    for (size_t c = 0; c < 3; ++c) {
      const std::string ch = kChannels[c];
      auto& temporal = image.addChannel("temporal." + ch);
      auto& variance = image.addChannel("temporal.variance." + ch);
      for (size_t p = 0; p < pixels(); ++p) {
        temporal[p] = temporalDifference_.mean[c][p];
        variance[p] = temporalDifference_.variance[c][p];
      }
    }
  }

  // Mixed differences where the motion is rigid across the pair: like the spatial
  // differences, p's forward part minus its neighbour's backward part. A pair whose
  // pixel has no sample with mixed offsets (too few samples for mixedEvery) gets NaN:
  // the reconstruction drops it.
  void writeMixedDifferences(FrameImage& image) const {
    for (size_t k : {size_t{0}, size_t{2}}) {
      const std::string layer = k == 0 ? "mixed_x." : "mixed_y.";
      for (size_t c = 0; c < 3; ++c) {
        auto& mixed = image.addChannel(layer + kChannels[c]);
        auto& variance = image.addChannel(layer + "variance." + kChannels[c]);
        for (size_t p = 0; p < pixels(); ++p) {
          if (!rigid(p, k)) continue;
          const size_t n = neighbour(p, k);
          if (mixedSamples_[p] == 0 || mixedSamples_[n] == 0) {
            mixed[p] = variance[p] = std::numeric_limits<float>::quiet_NaN();
            continue;
          }
          mixed[p] = static_cast<float>(static_cast<double>(mixed_[k].mean[c][p]) - mixed_[k ^ 1].mean[c][n]);
          variance[p] = static_cast<float>(static_cast<double>(mixed_[k].variance[c][p]) + mixed_[k ^ 1].variance[c][n]);
        }
      }
    }
  }

  // Where each pixel's temporal offset went in frame f + 1.
  void writeTemporalTargets(FrameImage& image) const {
    auto& tx = image.addChannel("temporal.target.X");
    auto& ty = image.addChannel("temporal.target.Y");
    auto& valid = image.addChannel("temporal.valid.Y");
    for (size_t p = 0; p < pixels(); ++p) {
      tx[p] = targetX_[p];
      ty[p] = targetY_[p];
      valid[p] = targetX_[p] >= 0 ? 1.0f : 0.0f;
    }
  }

 private:
  // The pixel p's temporal offset goes through, as an index of the frame, or -1.
  int64_t target(size_t p) const {
    if (targetX_[p] < 0) return -1;
    return static_cast<int64_t>(targetY_[p]) * width_ + static_cast<int64_t>(targetX_[p]);
  }
  // Whether p and its neighbour in direction k move rigidly: their offsets' pixels are
  // neighbours in the same direction (not across the next frame's right edge).
  bool rigid(size_t p, size_t k) const {
    const size_t n = neighbour(p, k);
    const int step = kShiftDirections[k][0] + kShiftDirections[k][1] * width_;
    return n != SIZE_MAX && target(p) >= 0 && target(n) == target(p) + step &&
           (k != 0 || targetX_[p] + 1 < static_cast<float>(width_));
  }

  int width_, height_;
  bool temporal_;
  MomentPlanes own_, direct_, temporalDifference_;
  std::array<MomentPlanes, 4> offset_, difference_, mixed_;
  const float *mixedSamples_ = nullptr, *targetX_ = nullptr, *targetY_ = nullptr;
};

// The windows pasted into one image of the frame, each pixel covered exactly once.
FrameImage joined(const std::vector<PlacedEstimates>& windows, int width, int height) {
  FrameImage frame(width, height);
  std::vector<uint8_t> covered(frame.pixelCount(), 0);
  for (const PlacedEstimates& window : windows) {
    const FrameImage& estimates = *window.estimates;
    if (estimates.channelNames() != windows.front().estimates->channelNames())
      throw std::invalid_argument("gradient estimates of one frame hold different channels");
    frame.paste(estimates, window.x0, window.y0);
    for (int y = window.y0; y < window.y0 + estimates.height(); ++y)
      for (int x = window.x0; x < window.x0 + estimates.width(); ++x)
        if (covered[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)]++ != 0)
          throw std::invalid_argument("gradient estimates overlap at pixel (" + std::to_string(x) + ", " +
                                      std::to_string(y) + ")");
  }
  for (size_t p = 0; p < covered.size(); ++p)
    if (!covered[p])
      throw std::invalid_argument("no gradient estimates cover pixel (" + std::to_string(p % static_cast<size_t>(width)) +
                                  ", " + std::to_string(p / static_cast<size_t>(width)) + ")");
  return frame;
}

uint64_t nonFiniteSamplesOf(const FrameImage& estimates) {
  const auto found = estimates.attributes().find("pathfarm.nonfinite_samples");
  if (found == estimates.attributes().end()) return 0;
  try {
    return std::stoull(found->second);
  } catch (const std::exception&) {
    throw std::invalid_argument("gradient estimates with a malformed pathfarm.nonfinite_samples attribute");
  }
}

}  // namespace

FrameImage gradientEstimates(const std::vector<GradientPixelSums>& sums, int width, int height,
                             const std::vector<int32_t>& targets, int frameWidth) {
  FrameImage image(width, height);
  auto& drawn = image.addChannel("drawn.Y");
  for (size_t p = 0; p < sums.size(); ++p) drawn[p] = static_cast<float>(sums[p].drawn);
  const auto all = [](const GradientPixelSums& s) { return s.samples; };
  addMoment(image, "own", sums, [](const GradientPixelSums& s) -> const SampleMoments& { return s.own; }, all);
  addMoment(image, "direct", sums, [](const GradientPixelSums& s) -> const SampleMoments& { return s.direct; }, all);
  for (size_t k = 0; k < 4; ++k) {
    addMoment(image, directional("offset", k), sums,
              [k](const GradientPixelSums& s) -> const SampleMoments& { return s.offset[k]; }, all);
    addMoment(image, directional("difference", k), sums,
              [k](const GradientPixelSums& s) -> const SampleMoments& { return s.difference[k]; }, all);
  }
  if (targets.empty()) return image;

  auto& mixedSamples = image.addChannel("mixed_samples.Y");
  auto& targetX = image.addChannel("temporal.target.X");
  auto& targetY = image.addChannel("temporal.target.Y");
  for (size_t p = 0; p < sums.size(); ++p) {
    mixedSamples[p] = static_cast<float>(sums[p].mixedSamples);
    targetX[p] = targets[p] >= 0 ? static_cast<float>(targets[p] % frameWidth) : -1.0f;
    targetY[p] = targets[p] >= 0 ? static_cast<float>(targets[p] / frameWidth) : -1.0f;
  }
  addMoment(image, "temporal", sums, [](const GradientPixelSums& s) -> const SampleMoments& { return s.temporal; },
            all);
  for (size_t k = 0; k < 4; ++k)
    addMoment(image, directional("mixed", k), sums,
              [k](const GradientPixelSums& s) -> const SampleMoments& { return s.mixed[k]; },
              [](const GradientPixelSums& s) { return s.mixedSamples; });
  return image;
}

FrameImage gradientFrameFromEstimates(const std::vector<PlacedEstimates>& windows, int width, int height) {
  if (windows.empty()) throw std::invalid_argument("a gradient frame needs estimates");
  const bool whole = windows.size() == 1 && windows[0].x0 == 0 && windows[0].y0 == 0 &&
                     windows[0].estimates->width() == width && windows[0].estimates->height() == height;
  FrameImage pasted;
  if (!whole) pasted = joined(windows, width, height);
  const FrameImage& estimates = whole ? *windows[0].estimates : pasted;
  const FrameLayers layers(estimates);

  FrameImage image(width, height);
  layers.writeSpatial(image);
  if (layers.temporal()) {
    layers.writeTemporalDifferences(image);
    layers.writeMixedDifferences(image);
    layers.writeTemporalTargets(image);
  }
  image.addChannel("sample_count.Y") = channelOf(estimates, "drawn.Y", kWhose);

  image.attributes() = windows.front().estimates->attributes();
  uint64_t nonFinite = 0;
  for (const PlacedEstimates& window : windows) nonFinite += nonFiniteSamplesOf(*window.estimates);
  image.attributes()["pathfarm.nonfinite_samples"] = std::to_string(nonFinite);
  return image;
}

std::vector<float> gradientRelativeVariance(const FrameImage& estimates) {
  return FrameLayers(estimates).relativeVariance();
}

}  // namespace pathfarm
