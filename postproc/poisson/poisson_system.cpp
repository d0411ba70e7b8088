#include "postproc/poisson/poisson_system.h"

#include <tbb/parallel_for.h>

#include <cmath>
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

// Runs body(g, x, y) for every pixel g of the window with its image coordinates, image
// lines in parallel: no divisions per pixel.
template <class Body>
void forEachPixel(size_t lines, size_t width, size_t height, Body body) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, lines, 4), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t line = r.begin(); line != r.end(); ++line) {
      const size_t y = line % height;
      for (size_t x = 0, g = line * width; x < width; ++x, ++g) body(g, x, y);
    }
  });
}

bool finite3(const float* v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

}  // namespace

PoissonSystem::PoissonSystem(const std::vector<const GradientFrame*>& frames, float alpha)
    : width_(frames.at(0)->width),
      height_(frames.at(0)->height),
      frames_(frames.size()),
      pixels_(frames.at(0)->pixelCount()),
      rows_(frames_ * pixels_),
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
}

void PoissonSystem::setWeightFactors(std::array<std::vector<float>, kBlocks> factors) { factors_ = std::move(factors); }

template <bool kWithTargets>
void PoissonSystem::temporalResiduals(const std::vector<float>& x, std::vector<float>& r) const {
  r.resize(size());
  forEach(rows_, [&](size_t g) {
    const int32_t next = next_[g];
    for (size_t c = 0; c < 3; ++c) {
      float v = next < 0 ? 0.0f : x[3 * static_cast<size_t>(next) + c] - x[3 * g + c];
      if constexpr (kWithTargets) v -= targets_[Temporal][3 * g + c];
      r[3 * g + c] = v;
    }
  });
}

template <bool kWithTargets>
void PoissonSystem::gather(const std::vector<float>& x, std::vector<float>& out) const {
  const size_t w = static_cast<size_t>(width_);
  // The targets' part of a row, read only when asked for.
  const auto target = [&](const std::vector<float>& targets, size_t i) {
    if constexpr (kWithTargets) return targets[i];
    return 0.0f;
  };
  temporalResiduals<kWithTargets>(x, r3_);
  const std::vector<float>& r3 = r3_;
  // z: the temporal rows' weighted residuals plus what the mixed rows add to them.
  std::vector<float>& z = z_;
  z.resize(size());
  const size_t lines = frames_ * static_cast<size_t>(height_), h = static_cast<size_t>(height_);
  forEachPixel(lines, w, h, [&](size_t g, size_t column, size_t line) {
    const bool left = column > 0, up = line > 0;
    for (size_t c = 0; c < 3; ++c) {
      const auto mixedX = [&](size_t i) {
        return weight(MixedX, i, c) * (r3[3 * (i + 1) + c] - r3[3 * i + c] + target(mixedShift_[0], 3 * i + c));
      };
      const auto mixedY = [&](size_t i) {
        return weight(MixedY, i, c) * (r3[3 * (i + w) + c] - r3[3 * i + c] + target(mixedShift_[1], 3 * i + c));
      };
      float v = weight(Temporal, g, c) * r3[3 * g + c];
      if (present(MixedX, g)) v -= mixedX(g);
      if (left && present(MixedX, g - 1)) v += mixedX(g - 1);
      if (present(MixedY, g)) v -= mixedY(g);
      if (up && present(MixedY, g - w)) v += mixedY(g - w);
      z[3 * g + c] = v;
    }
  });
  out.resize(size());
  forEachPixel(lines, w, h, [&](size_t g, size_t column, size_t line) {
    const bool left = column > 0, up = line > 0;
    const int32_t previous = previous_[g];
    for (size_t c = 0; c < 3; ++c) {
      const auto spatialX = [&](size_t i) {
        return weight(SpatialX, i, c) * (x[3 * (i + 1) + c] - x[3 * i + c] - target(targets_[SpatialX], 3 * i + c));
      };
      const auto spatialY = [&](size_t i) {
        return weight(SpatialY, i, c) * (x[3 * (i + w) + c] - x[3 * i + c] - target(targets_[SpatialY], 3 * i + c));
      };
      float v = weight(Data, g, c) * (x[3 * g + c] - target(targets_[Data], 3 * g + c)) - z[3 * g + c];
      if (present(SpatialX, g)) v -= spatialX(g);
      if (left && present(SpatialX, g - 1)) v += spatialX(g - 1);
      if (present(SpatialY, g)) v -= spatialY(g);
      if (up && present(SpatialY, g - w)) v += spatialY(g - w);
      if (previous >= 0) v += z[3 * static_cast<size_t>(previous) + c];
      out[3 * g + c] = v;
    }
  });
}

void PoissonSystem::applyNormal(const std::vector<float>& x, std::vector<float>& out) const { gather<false>(x, out); }

std::vector<float> PoissonSystem::rightHandSide() const {
  std::vector<float> out;
  gather<true>(std::vector<float>(size(), 0.0f), out);
  for (float& v : out) v = -v;
  return out;
}

std::vector<float> PoissonSystem::diagonal() const {
  const size_t w = static_cast<size_t>(width_);
  std::vector<float> d(size());
  const size_t h = static_cast<size_t>(height_);
  forEachPixel(frames_ * h, w, h, [&](size_t g, size_t column, size_t line) {
    const bool left = column > 0, up = line > 0;
    const int32_t q = previous_[g];
    for (size_t c = 0; c < 3; ++c) {
      float v = 0;
      for (Block k : {Data, SpatialX, SpatialY, Temporal, MixedX, MixedY}) v += weight(k, g, c);
      if (left) v += weight(SpatialX, g - 1, c) + weight(MixedX, g - 1, c);
      if (up) v += weight(SpatialY, g - w, c) + weight(MixedY, g - w, c);
      if (q >= 0) {
        // This pixel is m(q): the other end of q's temporal row and of the mixed rows through q.
        const size_t source = static_cast<size_t>(q), sp = source % pixels_;
        v += weight(Temporal, source, c) + weight(MixedX, source, c) + weight(MixedY, source, c);
        if (sp % w > 0) v += weight(MixedX, source - 1, c);
        if (sp / w > 0) v += weight(MixedY, source - w, c);
      }
      d[3 * g + c] = v;
    }
  });
  return d;
}

std::array<std::vector<float>, PoissonSystem::kBlocks> PoissonSystem::residuals(const std::vector<float>& x) const {
  const size_t w = static_cast<size_t>(width_);
  std::array<std::vector<float>, kBlocks> r;
  for (auto& block : r) block.assign(size(), 0.0f);
  temporalResiduals<true>(x, r[Temporal]);
  forEach(rows_, [&](size_t g) {
    for (size_t c = 0; c < 3; ++c) {
      const size_t i = 3 * g + c;
      r[Data][i] = x[i] - targets_[Data][i];
      if (present(SpatialX, g)) r[SpatialX][i] = x[i + 3] - x[i] - targets_[SpatialX][i];
      if (present(SpatialY, g)) r[SpatialY][i] = x[i + 3 * w] - x[i] - targets_[SpatialY][i];
      if (present(MixedX, g)) r[MixedX][i] = r[Temporal][i + 3] - r[Temporal][i] + mixedShift_[0][i];
      if (present(MixedY, g)) r[MixedY][i] = r[Temporal][i + 3 * w] - r[Temporal][i] + mixedShift_[1][i];
    }
  });
  return r;
}

}  // namespace pathfarm
