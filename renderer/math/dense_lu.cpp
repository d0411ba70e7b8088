#include "renderer/math/dense_lu.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace pathfarm {

bool solveDense(std::vector<double>& a, int n, std::vector<double>& b, int columns) {
  const auto A = [&](int r, int c) -> double& { return a[static_cast<size_t>(r * n + c)]; };
  const auto B = [&](int r, int c) -> double& { return b[static_cast<size_t>(r * columns + c)]; };
  double largest = 0;
  for (double v : a) {
    if (!std::isfinite(v)) return false;
    largest = std::max(largest, std::abs(v));
  }
  const double tiny = 1e-12 * largest;
  for (int k = 0; k < n; ++k) {
    int pivot = k;
    for (int r = k + 1; r < n; ++r)
      if (std::abs(A(r, k)) > std::abs(A(pivot, k))) pivot = r;
    if (!(std::abs(A(pivot, k)) > tiny)) return false;
    if (pivot != k) {
      for (int c = 0; c < n; ++c) std::swap(A(k, c), A(pivot, c));
      for (int c = 0; c < columns; ++c) std::swap(B(k, c), B(pivot, c));
    }
    for (int r = k + 1; r < n; ++r) {
      const double f = A(r, k) / A(k, k);
      if (f == 0) continue;
      for (int c = k; c < n; ++c) A(r, c) -= f * A(k, c);
      for (int c = 0; c < columns; ++c) B(r, c) -= f * B(k, c);
    }
  }
  for (int k = n - 1; k >= 0; --k) {
    for (int c = 0; c < columns; ++c) {
      double v = B(k, c);
      for (int j = k + 1; j < n; ++j) v -= A(k, j) * B(j, c);
      B(k, c) = v / A(k, k);
      if (!std::isfinite(B(k, c))) return false;
    }
  }
  return true;
}

}  // namespace pathfarm
