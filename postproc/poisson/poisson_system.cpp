#include "postproc/poisson/poisson_system.h"

#include "postproc/poisson/bfloat16.h"
#include "postproc/poisson/channel_lanes.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace pathfarm {
namespace {

// Runs body(g) for every row g in [0, n) in parallel; each g is written once, so the
// result does not depend on the partition.
template <class Body>
void forEach(size_t n, Body body) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 2048), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t g = r.begin(); g != r.end(); ++g) body(g);
  });
}

// Lines per chunk of the operator's passes; the chunks also fix the order of its dot
// product's sum.
constexpr size_t kLinesPerChunk = 32;

bool finite3(const float* v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

}  // namespace

PoissonSystem::PoissonSystem(const std::vector<const GradientFrame*>& frames, float alpha)
    : width_(frames.at(0)->width),
      height_(frames.at(0)->height),
      frames_(frames.size()),
      pixels_(frames.at(0)->pixelCount()),
      rows_(frames_ * pixels_),
      alpha_(alpha),
      alphaSquared_(alpha * alpha) {
  const size_t n = rows_, w = static_cast<size_t>(width_), h = static_cast<size_t>(height_);
  next_.assign(n, -1);
  previous_.assign(n, -1);
  for (auto& target : targets_) target.assign(3 * n, 0.0f);
  presence_.assign(n, 0);
  const auto mark = [&](Block block, size_t g) { presence_[g] |= static_cast<uint8_t>(1u << block); };
  for (auto& shift : mixedShift_) shift.assign(3 * n, 0.0f);
  for (const GradientFrame* frame : frames)
    if (frame->width != width_ || frame->height != height_)
      throw std::invalid_argument("the frames of a Poisson window differ in size");
  forEach(n, [&](size_t g) {
    const size_t f = g / pixels_, p = g % pixels_, x = p % w, y = p / w;
    const GradientFrame& frame = *frames[f];
    const std::array<const GradientFrame::Color*, 3> layers{&frame.primal, &frame.gradientX, &frame.gradientY};
    const bool inside[3] = {true, x + 1 < w, y + 1 < h};
    for (size_t k = 0; k < 3; ++k) {
      float* target = &targets_[k][3 * g];
      for (size_t c = 0; c < 3; ++c) target[c] = (*layers[k])[c][p];
      if (inside[k] && finite3(target))
        mark(static_cast<Block>(k), g);
      else
        target[0] = target[1] = target[2] = 0;
    }
  });
  // The maps, and their inverse: written sequentially, each target has one source.
  for (size_t g = 0; g < n; ++g) {
    const size_t f = g / pixels_, p = g % pixels_;
    const GradientFrame& frame = *frames[f];
    if (f + 1 >= frames_ || !frame.hasTemporal() || frame.temporalTarget[p] < 0) continue;
    float* target = &targets_[Temporal][3 * g];
    for (size_t c = 0; c < 3; ++c) target[c] = frame.temporal[c][p];
    if (!finite3(target)) {
      target[0] = target[1] = target[2] = 0;
      continue;
    }
    const size_t next = (f + 1) * pixels_ + static_cast<size_t>(frame.temporalTarget[p]);
    next_[g] = static_cast<int32_t>(next);
    previous_[next] = static_cast<int32_t>(g);
    mark(Temporal, g);
  }
  // A mixed row needs both temporal rows it differences, rigidly apart in both frames.
  forEach(n, [&](size_t g) {
    const size_t f = g / pixels_, p = g % pixels_;
    if (!present(Temporal, g)) return;
    const auto add = [&](Block block, size_t step, const GradientFrame::Color& mixed) {
      const size_t other = g + step;
      if (!present(Temporal, other) || next_[other] != next_[g] + static_cast<int32_t>(step)) return;
      float* shift = &mixedShift_[block == MixedX ? 0 : 1][3 * g];
      for (size_t c = 0; c < 3; ++c)
        shift[c] = targets_[Temporal][3 * other + c] - targets_[Temporal][3 * g + c] - mixed[c][p];
      if (finite3(shift))
        mark(block, g);
      else
        shift[0] = shift[1] = shift[2] = 0;
    };
    if (p % w + 1 < w) add(MixedX, 1, frames[f]->mixedX);
    if (p / w + 1 < h) add(MixedY, w, frames[f]->mixedY);
  });
  weighByVariance(frames);
  for (size_t k = 0; k < kBlocks; ++k) {
    factors_[k].resize(3 * n);
    forEach(n, [&](size_t g) {
      for (size_t c = 0; c < 3; ++c) factors_[k][3 * g + c] = confidence_[k][g];
    });
  }
}

void PoissonSystem::weighByVariance(const std::vector<const GradientFrame*>& frames) {
  static_assert(GradientFrame::kLayers == kBlocks, "a block per layer, in the same order");
  // The variance of block k's row g, or -1 where its frame has no variance layer; a value
  // that is no variance (NaN, negative) comes out as infinity: the row is not trusted.
  const auto varianceOf = [&](size_t k, size_t g) -> float {
    const std::vector<float>& layer = frames[g / pixels_]->variance[k];
    if (layer.empty()) return -1;
    const float v = layer[g % pixels_];
    return v >= 0 ? v : std::numeric_limits<float>::infinity();
  };
  for (size_t k = 0; k < kBlocks; ++k) {
    // The typical variance: the median of the block's finite non-zero ones. Not the mean,
    // which a few outliers would raise enough to trust them in a small window; zeros (black
    // or exactly static regions) say nothing of the noise of the others.
    std::vector<float> variances;
    for (size_t g = 0; g < rows_; ++g) {
      const float v = present(static_cast<Block>(k), g) ? varianceOf(k, g) : 0;
      if (v > 0 && std::isfinite(v)) variances.push_back(v);
    }
    const auto middle = variances.begin() + static_cast<std::ptrdiff_t>(variances.size() / 2);
    std::nth_element(variances.begin(), middle, variances.end());
    const double typical = variances.empty() ? 0 : *middle;
    confidence_[k].resize(rows_);
    forEach(rows_, [&](size_t g) {
      float confidence = 0;
      if (present(static_cast<Block>(k), g)) {
        const float v = varianceOf(k, g);
        confidence = v < 0 || typical <= 0 ? 1.0f : static_cast<float>(1 / (1 + v / (kOutlierVarianceRatio * typical)));
      }
      confidence_[k][g] = toBfloat16(confidence);
    });
  }
}

float PoissonSystem::temporalResidual(const std::vector<float>& x, size_t g, size_t c) const {
  const int32_t next = next_[g];
  return next < 0 ? 0.0f : x[3 * static_cast<size_t>(next) + c] - x[3 * g + c] - targets_[Temporal][3 * g + c];
}

// The operator is computed image line by image line: the rows of a line (one value per
// unknown of the line, 0 for absent rows) go to short line buffers, and each unknown
// then adds the rows it takes part in. Every loop over a line runs over its values
// without branches, which the compiler vectorizes; the rows at the end of a line and on
// the last line of a frame are absent and never computed, so no buffer reaches past the
// window.
template <bool kWithTargets>
class PoissonSystem::LinePass {
 public:
  LinePass(const PoissonSystem& system, const std::vector<float>& x, std::vector<float>& out,
           const Reweighting* reweighting)
      : system_(system),
        x_(x),
        out_(out),
        reweighting_(reweighting),
        w_(static_cast<size_t>(system.width_)),
        h_(static_cast<size_t>(system.height_)),
        lineSize_(3 * w_),
        lines_(system.frames_ * h_) {}

  // z over lines [begin, end) of one frame: the temporal rows' weighted residuals plus what
  // the mixed rows add to them. A mixed row differences neighbouring temporal rows,
  // mixed_x(i) = t(i + x) - t(i) + (its target shift), with t the temporal residuals.
  void temporalAndMixedRows(size_t begin, size_t end) const {
    // mixedX has 3 leading zeros: a value's left neighbour is always there.
    std::vector<float> t(lineSize_), tBelow(lineSize_), temporal(lineSize_), mixedX(3 + lineSize_, 0.0f),
        mixedY(lineSize_), mixedYAbove(lineSize_, 0.0f);
    temporalResiduals(begin, t.data());
    if (begin % h_ > 0) {
      temporalResiduals(begin - 1, tBelow.data());  // the line above, for now
      mixedYRows(begin - 1, tBelow.data(), t.data(), mixedYAbove.data(), false);
    }
    for (size_t line = begin; line < end; ++line) {
      const size_t first = line * lineSize_;
      if (line + 1 < lines_) temporalResiduals(line + 1, tBelow.data());
      weightedRows(Temporal, line, 0, false, temporal.data(), [&](size_t j) { return t[j]; });
      weightedRows(MixedX, line, 3, false, mixedX.data() + 3,
                   [&](size_t j) { return t[j + 3] - t[j] + target(system_.mixedShift_[0], first + j); });
      mixedYRows(line, t.data(), tBelow.data(), mixedY.data(), true);
      float* z = zOfLine(line);
      for (size_t j = 0; j < lineSize_; ++j)
        z[j] = temporal[j] - mixedX[j + 3] + mixedX[j] - mixedY[j] + mixedYAbove[j];
      std::swap(t, tBelow);
      std::swap(mixedY, mixedYAbove);
    }
  }

  // out over lines [begin, end) of one frame: the data and spatial rows, minus z, plus
  // the previous frame's z gathered through m^-1; returns <x, out> per channel.
  ChannelSums dataAndSpatialRows(size_t begin, size_t end) const {
    // spatialX has 3 leading zeros like mixedX above.
    std::vector<float> data(lineSize_), spatialX(3 + lineSize_, 0.0f), spatialY(lineSize_),
        spatialYAbove(lineSize_, 0.0f);
    if (begin % h_ > 0) spatialYRows(begin - 1, spatialYAbove.data(), false);
    // The previous frame's z, indexed by its window pixel (there is none for frame 0).
    const size_t frame = begin / h_, previousFirst = frame > 0 ? (frame - 1) * system_.pixels_ : 0;
    const float* zPrevious = &system_.z_[(frame + 1) % 2 * 3 * system_.pixels_];
    ChannelSums partial{};
    for (size_t line = begin; line < end; ++line) {
      const size_t first = line * lineSize_;
      weightedRows(Data, line, 0, false, data.data(),
                   [&](size_t j) { return x_[first + j] - target(system_.targets_[Data], first + j); });
      weightedRows(SpatialX, line, 3, false, spatialX.data() + 3, [&](size_t j) {
        return x_[first + j + 3] - x_[first + j] - target(system_.targets_[SpatialX], first + j);
      });
      spatialYRows(line, spatialY.data(), true);
      float* o = &out_[first];
      const float* z = zOfLine(line);
      for (size_t j = 0; j < lineSize_; ++j)
        o[j] = data[j] - spatialX[j + 3] + spatialX[j] - spatialY[j] + spatialYAbove[j] - z[j];
      // The line's pixels are the far end of the previous frame's temporal and mixed rows.
      for (size_t g = line * w_; g < (line + 1) * w_; ++g) {
        const int32_t previous = system_.previous_[g];
        for (size_t c = 0; c < 3; ++c) {
          if (previous >= 0) out_[3 * g + c] += zPrevious[3 * (static_cast<size_t>(previous) - previousFirst) + c];
          partial[c] += static_cast<double>(x_[3 * g + c]) * out_[3 * g + c];
        }
      }
      std::swap(spatialY, spatialYAbove);
    }
    return partial;
  }

 private:
  // The targets' part of a row, read only when asked for.
  static float target(const std::vector<float>& targets, size_t i) {
    if constexpr (kWithTargets) return targets[i];
    return 0.0f;
  }

  // result[j] = weight * residual(j) for the values j of `line` of one row block; 0 for the
  // `lastColumns` values of the line's last pixel (rows towards x + 1) and over the whole
  // line when it is its frame's last and the rows reach y + 1. When reweighting, the
  // weights come from the residuals instead, and the chunk that owns the line writes them.
  template <class Residual>
  void weightedRows(Block block, size_t line, size_t lastColumns, bool towardsNextLine, float* result,
                    Residual residual, bool ownsLine = true) const {
    const size_t end = towardsNextLine && line % h_ == h_ - 1 ? 0 : lineSize_ - lastColumns;
    const float base = block == Data ? system_.alphaSquared_ : 1.0f;
    const size_t first = line * lineSize_;
    if (reweighting_) {
      // Branch-free, so that it vectorizes: absent rows have confidence 0, and a line
      // another chunk owns goes to scratch.
      thread_local std::vector<float> confidence;
      thread_local std::vector<uint16_t> scratch;
      confidence.resize(lineSize_);
      scratch.resize(lineSize_);
      for (size_t j = 0; j < lineSize_; j += 3)
        confidence[j] = confidence[j + 1] = confidence[j + 2] =
            fromBfloat16(system_.confidence_[block][(first + j) / 3]);
      uint16_t* factor = ownsLine ? &reweighting_->factors[block][first] : scratch.data();
      const float scale = block == Data ? system_.alpha_ : 1.0f;
      for (size_t j = 0; j < end; ++j) {
        const float r = residual(j);
        factor[j] = toBfloat16(confidence[j] / std::max(scale * std::abs(r), reweighting_->epsilon));
        result[j] = base * fromBfloat16(factor[j]) * r;
      }
    } else {
      const uint16_t* factor = &system_.factors_[block][first];
      for (size_t j = 0; j < end; ++j) result[j] = base * fromBfloat16(factor[j]) * residual(j);
    }
    std::fill(result + end, result + lineSize_, 0.0f);
  }

  // The mixed y rows of `line`, from the temporal residuals of it and of the line below.
  void mixedYRows(size_t line, const float* above, const float* below, float* result, bool ownsLine) const {
    weightedRows(
        MixedY, line, 0, true, result,
        [&](size_t j) { return below[j] - above[j] + target(system_.mixedShift_[1], line * lineSize_ + j); }, ownsLine);
  }

  void spatialYRows(size_t line, float* result, bool ownsLine) const {
    const size_t first = line * lineSize_;
    weightedRows(
        SpatialY, line, 0, true, result,
        [&](size_t j) {
          return x_[first + lineSize_ + j] - x_[first + j] - target(system_.targets_[SpatialY], first + j);
        },
        ownsLine);
  }

  // The temporal rows' A x - b over a line, 0 where absent (where their targets are 0).
  void temporalResiduals(size_t line, float* t) const {
    for (size_t g = line * w_, j = 0; g < (line + 1) * w_; ++g, j += 3) {
      const int32_t next = system_.next_[g];
      for (size_t c = 0; c < 3; ++c)
        t[j + c] = next < 0 ? 0.0f
                            : x_[3 * static_cast<size_t>(next) + c] - x_[3 * g + c] -
                                  target(system_.targets_[Temporal], 3 * g + c);
    }
  }

  float* zOfLine(size_t line) const {
    return &system_.z_[(line / h_ % 2) * 3 * system_.pixels_ + (line % h_) * lineSize_];
  }

  const PoissonSystem& system_;
  const std::vector<float>& x_;
  std::vector<float>& out_;
  const Reweighting* reweighting_;
  size_t w_, h_, lineSize_, lines_;
};

template <bool kWithTargets>
ChannelSums PoissonSystem::gather(const std::vector<float>& x, std::vector<float>& out,
                                  const Reweighting* reweighting) const {
  const size_t h = static_cast<size_t>(height_);
  // Frame f's gather reads its own z and, through m^-1, frame f - 1's: the window is
  // gathered frame by frame, each chunk of lines computing its z just before it is read
  // (still in cache), and z is kept for two frames, frame f's at slot f mod 2.
  z_.resize(2 * 3 * pixels_);
  out.resize(size());
  const LinePass<kWithTargets> pass(*this, x, out, reweighting);
  ChannelSums total{};
  for (size_t f = 0; f < frames_; ++f) {
    const ChannelSums sums = chunkedSum<3>(h, kLinesPerChunk, [&](size_t begin, size_t end) {
      pass.temporalAndMixedRows(f * h + begin, f * h + end);
      return pass.dataAndSpatialRows(f * h + begin, f * h + end);
    });
    for (size_t c = 0; c < 3; ++c) total[c] += sums[c];
  }
  return total;
}

ChannelSums PoissonSystem::applyNormal(const std::vector<float>& x, std::vector<float>& out) const {
  return gather<false>(x, out);
}

void PoissonSystem::gradient(const std::vector<float>& x, std::vector<float>& out) const { gather<true>(x, out); }

void PoissonSystem::reweightForL1(const std::vector<float>& x, float epsilon, std::vector<float>& gradient) {
  Reweighting reweighting{epsilon, {}};
  for (size_t k = 0; k < kBlocks; ++k) reweighting.factors[k] = factors_[k].data();
  gather<true>(x, gradient, &reweighting);
}

// Every coefficient is +-1, so an unknown's diagonal entry is the sum of the weights of
// the rows it takes part in: its own, the x rows of the pixel to its left, the y rows of
// the pixel above, and through m^-1 the temporal and mixed rows it is the far end of.
// Absent rows weigh 0, and the rows that would reach from a line's last pixel to the
// next line's first, or from a frame's last line to the next frame, are absent: the
// neighbours need no test but the window's start. Computed line by line, so the sums
// over the blocks vectorize.
void PoissonSystem::inverseDiagonal(std::vector<float>& out) const {
  const size_t w = static_cast<size_t>(width_), lineSize = 3 * w, lines = frames_ * static_cast<size_t>(height_);
  out.resize(size());
  tbb::parallel_for(size_t{0}, lines, [&](size_t line) {
    float* v = &out[line * lineSize];
    for (size_t j = 0, i = line * lineSize; j < lineSize; ++j, ++i) {
      float sum = 0;
      for (Block k : {Data, SpatialX, SpatialY, Temporal, MixedX, MixedY}) sum += weight(k, i);
      v[j] = sum;
    }
    for (size_t j = line > 0 ? 0 : 3; j < lineSize; ++j) {
      const size_t i = line * lineSize + j - 3;
      v[j] += weight(SpatialX, i) + weight(MixedX, i);
    }
    if (line > 0)
      for (size_t j = 0, i = (line - 1) * lineSize; j < lineSize; ++j, ++i)
        v[j] += weight(SpatialY, i) + weight(MixedY, i);
    for (size_t g = line * w, j = 0; j < lineSize; ++g, j += 3) {
      if (previous_[g] < 0) continue;
      // This pixel is m(q): the far end of q's temporal row and of the mixed rows through q.
      const size_t q = static_cast<size_t>(previous_[g]);
      for (size_t c = 0; c < 3; ++c) {
        const size_t i = 3 * q + c;
        v[j + c] += weight(Temporal, i) + weight(MixedX, i) + weight(MixedY, i);
        if (q >= 1) v[j + c] += weight(MixedX, i - 3);
        if (q >= w) v[j + c] += weight(MixedY, i - lineSize);
      }
    }
    for (size_t j = 0; j < lineSize; ++j) v[j] = v[j] > 0 ? 1 / v[j] : 0;
  });
}

std::array<std::vector<float>, PoissonSystem::kBlocks> PoissonSystem::residuals(const std::vector<float>& x) const {
  std::array<std::vector<float>, kBlocks> r;
  for (auto& block : r) block.assign(size(), 0.0f);
  const size_t w = static_cast<size_t>(width_);
  forEach(rows_, [&](size_t g) {
    for (size_t c = 0; c < 3; ++c) {
      const size_t i = 3 * g + c;
      if (present(Data, g)) r[Data][i] = x[i] - targets_[Data][i];
      if (present(SpatialX, g)) r[SpatialX][i] = x[i + 3] - x[i] - targets_[SpatialX][i];
      if (present(SpatialY, g)) r[SpatialY][i] = x[i + 3 * w] - x[i] - targets_[SpatialY][i];
      if (!present(Temporal, g)) continue;
      const float temporal = temporalResidual(x, g, c);
      r[Temporal][i] = temporal;
      if (present(MixedX, g)) r[MixedX][i] = temporalResidual(x, g + 1, c) - temporal + mixedShift_[0][i];
      if (present(MixedY, g)) r[MixedY][i] = temporalResidual(x, g + w, c) - temporal + mixedShift_[1][i];
    }
  });
  return r;
}

}  // namespace pathfarm
