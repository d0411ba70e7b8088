#include "postproc/poisson/poisson_system.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <stdexcept>

namespace pathfarm {
namespace {

// Runs body(g) for every global index g in [0, n) in parallel; each g is written once, so
// the result does not depend on the partition.
template <class Body>
void forEach(size_t n, Body body) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t g = r.begin(); g != r.end(); ++g) body(g);
  });
}

}  // namespace

PoissonSystem::PoissonSystem(const std::vector<const GradientFrame*>& frames, size_t channel, float alpha)
    : width_(frames.at(0)->width), height_(frames.at(0)->height), frames_(frames.size()),
      pixels_(frames.at(0)->pixelCount()) {
  const size_t n = size(), w = static_cast<size_t>(width_);
  next_.assign(n, -1);
  previous_.assign(n, -1);
  for (auto& target : targets_) target.resize(n);
  for (auto& weight : base_) weight.assign(n, 0.0f);
  for (size_t f = 0; f < frames_; ++f) {
    const GradientFrame& frame = *frames[f];
    if (frame.width != width_ || frame.height != height_)
      throw std::invalid_argument("the frames of a Poisson window differ in size");
    const size_t offset = f * pixels_;
    std::copy(frame.primal[channel].begin(), frame.primal[channel].end(), targets_[Data].begin() + offset);
    std::copy(frame.gradientX[channel].begin(), frame.gradientX[channel].end(), targets_[SpatialX].begin() + offset);
    std::copy(frame.gradientY[channel].begin(), frame.gradientY[channel].end(), targets_[SpatialY].begin() + offset);
    for (size_t p = 0; p < pixels_; ++p) {
      const size_t g = offset + p, x = p % w, y = p / w;
      base_[Data][g] = alpha * alpha;
      base_[SpatialX][g] = x + 1 < w ? 1.0f : 0.0f;
      base_[SpatialY][g] = y + 1 < static_cast<size_t>(height_) ? 1.0f : 0.0f;
      // A non-finite sample constrains nothing.
      for (size_t k : {Data, SpatialX, SpatialY}) {
        if (!std::isfinite(targets_[k][g])) {
          targets_[k][g] = 0;
          base_[k][g] = 0;
        }
      }
      targets_[Temporal][g] = 0;
      if (f + 1 < frames_ && frame.hasTemporal() && frame.temporalTarget[p] >= 0) {
        const size_t target = (f + 1) * pixels_ + static_cast<size_t>(frame.temporalTarget[p]);
        next_[g] = static_cast<int32_t>(target);
        previous_[target] = static_cast<int32_t>(g);
        targets_[Temporal][g] = frame.temporal[channel][p];
        base_[Temporal][g] = 1.0f;
      }
    }
  }
  // A mixed row needs both temporal rows it differences, rigidly apart in both frames.
  for (auto& shift : mixedShift_) shift.assign(n, 0.0f);
  forEach(n, [&](size_t g) {
    const size_t f = g / pixels_, p = g % pixels_;
    if (base_[Temporal][g] == 0) return;
    const auto& targets = targets_[Temporal];
    const auto add = [&](Block block, size_t step, const GradientFrame::Color& mixed) {
      const size_t other = g + step;
      if (base_[Temporal][other] == 0 || next_[other] != next_[g] + static_cast<int32_t>(step)) return;
      const float shift = targets[other] - targets[g] - mixed[channel][p];
      if (!std::isfinite(shift)) return;
      base_[block][g] = 1.0f;
      mixedShift_[block == MixedX ? 0 : 1][g] = shift;
    };
    if (p % w + 1 < w) add(MixedX, 1, frames[f]->mixedX);
    if (p / w + 1 < static_cast<size_t>(height_)) add(MixedY, w, frames[f]->mixedY);
  });
  weights_ = base_;
}

void PoissonSystem::setWeightFactors(const std::array<std::vector<float>, kBlocks>& factors) {
  for (size_t k = 0; k < kBlocks; ++k)
    forEach(size(), [&](size_t g) { weights_[k][g] = base_[k][g] * factors[k][g]; });
}

void PoissonSystem::temporalResiduals(const std::vector<float>& x, bool withTargets, std::vector<float>& r) const {
  r.resize(size());
  forEach(size(), [&](size_t g) {
    r[g] = next_[g] < 0 ? 0.0f
                        : x[static_cast<size_t>(next_[g])] - x[g] - (withTargets ? targets_[Temporal][g] : 0.0f);
  });
}

void PoissonSystem::gather(const std::vector<float>& x, bool withTargets, std::vector<float>& out) const {
  const size_t n = size(), w = static_cast<size_t>(width_);
  const float s = withTargets ? 1.0f : 0.0f;
  temporalResiduals(x, withTargets, r3_);
  const std::vector<float>& r3 = r3_;
  // z: the temporal rows' weighted residuals plus what the mixed rows add to them.
  std::vector<float>& z = z_;
  z.resize(n);
  forEach(n, [&](size_t g) {
    const size_t p = g % pixels_;
    const auto& wx = weights_[MixedX];
    const auto& wy = weights_[MixedY];
    float v = weights_[Temporal][g] * r3[g];
    const auto mixedX = [&](size_t i) { return wx[i] * (r3[i + 1] - r3[i] + s * mixedShift_[0][i]); };
    const auto mixedY = [&](size_t i) { return wy[i] * (r3[i + w] - r3[i] + s * mixedShift_[1][i]); };
    if (wx[g] > 0) v -= mixedX(g);
    if (p % w > 0 && wx[g - 1] > 0) v += mixedX(g - 1);
    if (wy[g] > 0) v -= mixedY(g);
    if (p / w > 0 && wy[g - w] > 0) v += mixedY(g - w);
    z[g] = v;
  });
  out.resize(n);
  forEach(n, [&](size_t g) {
    const size_t p = g % pixels_;
    const auto& w1 = weights_[SpatialX];
    const auto& w2 = weights_[SpatialY];
    const auto spatialX = [&](size_t i) { return w1[i] * (x[i + 1] - x[i] - s * targets_[SpatialX][i]); };
    const auto spatialY = [&](size_t i) { return w2[i] * (x[i + w] - x[i] - s * targets_[SpatialY][i]); };
    float v = weights_[Data][g] * (x[g] - s * targets_[Data][g]) - z[g];
    if (w1[g] > 0) v -= spatialX(g);
    if (p % w > 0 && w1[g - 1] > 0) v += spatialX(g - 1);
    if (w2[g] > 0) v -= spatialY(g);
    if (p / w > 0 && w2[g - w] > 0) v += spatialY(g - w);
    if (previous_[g] >= 0) v += z[static_cast<size_t>(previous_[g])];
    out[g] = v;
  });
}

void PoissonSystem::applyNormal(const std::vector<float>& x, std::vector<float>& out) const { gather(x, false, out); }

std::vector<float> PoissonSystem::rightHandSide() const {
  std::vector<float> out;
  gather(std::vector<float>(size(), 0.0f), true, out);
  for (float& v : out) v = -v;
  return out;
}

std::vector<float> PoissonSystem::diagonal() const {
  const size_t w = static_cast<size_t>(width_);
  std::vector<float> d(size());
  forEach(size(), [&](size_t g) {
    const size_t p = g % pixels_;
    const bool left = p % w > 0, up = p / w > 0;
    float v = weights_[Data][g] + weights_[SpatialX][g] + weights_[SpatialY][g] + weights_[Temporal][g] +
              weights_[MixedX][g] + weights_[MixedY][g];
    if (left) v += weights_[SpatialX][g - 1] + weights_[MixedX][g - 1];
    if (up) v += weights_[SpatialY][g - w] + weights_[MixedY][g - w];
    if (const int32_t q = previous_[g]; q >= 0) {
      // This pixel is m(q): the other end of q's temporal row and of the mixed rows through q.
      const size_t source = static_cast<size_t>(q), sp = source % pixels_;
      v += weights_[Temporal][source] + weights_[MixedX][source] + weights_[MixedY][source];
      if (sp % w > 0) v += weights_[MixedX][source - 1];
      if (sp / w > 0) v += weights_[MixedY][source - w];
    }
    d[g] = v;
  });
  return d;
}

std::array<std::vector<float>, PoissonSystem::kBlocks> PoissonSystem::residuals(const std::vector<float>& x) const {
  const size_t n = size(), w = static_cast<size_t>(width_);
  std::array<std::vector<float>, kBlocks> r;
  for (auto& block : r) block.assign(n, 0.0f);
  temporalResiduals(x, true, r[Temporal]);
  forEach(n, [&](size_t g) {
    r[Data][g] = x[g] - targets_[Data][g];
    if (base_[SpatialX][g] > 0) r[SpatialX][g] = x[g + 1] - x[g] - targets_[SpatialX][g];
    if (base_[SpatialY][g] > 0) r[SpatialY][g] = x[g + w] - x[g] - targets_[SpatialY][g];
    if (base_[MixedX][g] > 0) r[MixedX][g] = r[Temporal][g + 1] - r[Temporal][g] + mixedShift_[0][g];
    if (base_[MixedY][g] > 0) r[MixedY][g] = r[Temporal][g + w] - r[Temporal][g] + mixedShift_[1][g];
  });
  return r;
}

}  // namespace pathfarm
