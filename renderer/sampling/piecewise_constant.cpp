#include "renderer/sampling/piecewise_constant.h"

#include <algorithm>
#include <utility>

namespace pathfarm {

PiecewiseConstant1D::PiecewiseConstant1D(std::vector<float> values) : values_(std::move(values)) {
  const size_t n = values_.size();
  cdf_.resize(n + 1);
  // Running sums in double: a map's rows hold thousands of values of very different size.
  double total = 0;
  for (size_t i = 0; i < n; ++i) {
    total += values_[i];
    cdf_[i + 1] = static_cast<float>(total);
  }
  integral_ = static_cast<float>(total / static_cast<double>(n));
  for (size_t i = 1; i <= n; ++i) {
    cdf_[i] = total > 0 ? static_cast<float>(static_cast<double>(cdf_[i]) / total)
                        : static_cast<float>(static_cast<double>(i) / static_cast<double>(n));
  }
  cdf_[n] = 1;
}

PiecewiseConstant1D::Sample PiecewiseConstant1D::sample(float u) const {
  // The interval whose [cdf[i], cdf[i+1]) holds u; upper_bound skips empty intervals.
  const auto above = std::upper_bound(cdf_.begin(), cdf_.end(), u);
  const int last = size() - 1;
  const int i = std::clamp(static_cast<int>(above - cdf_.begin()) - 1, 0, last);
  const float low = cdf_[static_cast<size_t>(i)], width = cdf_[static_cast<size_t>(i) + 1] - low;
  const float within = width > 0 ? std::clamp((u - low) / width, 0.0f, 0x1.fffffep-1f) : 0.5f;
  const float x = std::min((static_cast<float>(i) + within) / static_cast<float>(size()), 0x1.fffffep-1f);
  return {x, pdf(i), i};
}

namespace {

std::vector<PiecewiseConstant1D> rowsOf(const std::vector<float>& values, int width, int height) {
  std::vector<PiecewiseConstant1D> rows;
  for (int y = 0; y < height; ++y) {
    const auto row = values.begin() + static_cast<std::ptrdiff_t>(y) * width;
    rows.emplace_back(std::vector<float>(row, row + width));
  }
  return rows;
}

std::vector<float> integralsOf(const std::vector<PiecewiseConstant1D>& rows) {
  std::vector<float> integrals;
  for (const PiecewiseConstant1D& row : rows) integrals.push_back(row.integral());
  return integrals;
}

}  // namespace

PiecewiseConstant2D::PiecewiseConstant2D(const std::vector<float>& values, int width, int height)
    : conditional_(rowsOf(values, width, height)), marginal_(integralsOf(conditional_)) {}

PiecewiseConstant2D::Sample PiecewiseConstant2D::sample(Vec2f u) const {
  const PiecewiseConstant1D::Sample row = marginal_.sample(u.y);
  const PiecewiseConstant1D::Sample column = conditional_[static_cast<size_t>(row.interval)].sample(u.x);
  return {{column.x, row.x}, column.pdf * row.pdf, column.interval, row.interval};
}

float PiecewiseConstant2D::pdf(int column, int row) const {
  return conditional_[static_cast<size_t>(row)].pdf(column) * marginal_.pdf(row);
}

}  // namespace pathfarm
