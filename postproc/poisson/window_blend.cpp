#include "postproc/poisson/window_blend.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

namespace pathfarm {

std::vector<PoissonWindow> planWindows(size_t frames, size_t window, size_t overlap) {
  if (window == 0 || overlap >= window) throw std::invalid_argument("a window needs 0 <= overlap < window frames");
  if (frames == 0) return {};
  if (frames <= window) return {{0, frames}};
  std::vector<PoissonWindow> windows;
  for (size_t first = 0;; first = std::min(first + window - overlap, frames - window)) {
    windows.push_back({first, window});
    if (first + window >= frames) break;
  }
  return windows;
}

float hannWeight(size_t index, size_t count) {
  const double s = std::sin(3.14159265358979323846 * (static_cast<double>(index) + 0.5) / static_cast<double>(count));
  return static_cast<float>(s * s);
}

void WindowBlend::add(const GradientFrame::Color& solved, size_t index, size_t count) {
  const float h = hannWeight(index, count);
  for (size_t c = 0; c < 3; ++c) {
    sum[c].resize(solved[c].size(), 0.0f);
    for (size_t p = 0; p < solved[c].size(); ++p) sum[c][p] += h * solved[c][p];
  }
  weight += h;
}

GradientFrame::Color WindowBlend::finish(const GradientFrame::Color& directEmission) && {
  GradientFrame::Color color = std::move(sum);
  for (size_t c = 0; c < 3; ++c)
    for (size_t p = 0; p < color[c].size(); ++p) color[c][p] = color[c][p] / weight + directEmission[c][p];
  return color;
}

void reconstructSequence(size_t frames, const FrameLoader& load, const FrameSink& sink, size_t window, size_t overlap,
                         const PoissonSettings& settings, PoissonStats* stats) {
  const std::vector<PoissonWindow> windows = planWindows(frames, window, overlap);
  std::map<size_t, GradientFrame> loaded;
  std::map<size_t, WindowBlend> blends;
  PoissonStats total;
  for (size_t w = 0; w < windows.size(); ++w) {
    const PoissonWindow& current = windows[w];
    std::erase_if(loaded, [&](const auto& entry) { return entry.first < current.first; });
    std::vector<const GradientFrame*> inputs;
    for (size_t f = current.first; f < current.first + current.count; ++f) {
      if (!loaded.count(f)) loaded.emplace(f, load(f));
      inputs.push_back(&loaded.at(f));
    }
    PoissonStats windowStats;
    const std::vector<GradientFrame::Color> solved = reconstructWindow(inputs, settings, &windowStats);
    total.iterations += windowStats.iterations;
    total.relativeResidual = std::max(total.relativeResidual, windowStats.relativeResidual);
    for (size_t i = 0; i < current.count; ++i) blends[current.first + i].add(solved[i], i, current.count);
    const size_t finishedBelow = w + 1 < windows.size() ? windows[w + 1].first : frames;
    for (auto it = blends.begin(); it != blends.end() && it->first < finishedBelow; it = blends.erase(it))
      sink(it->first, std::move(it->second).finish(loaded.at(it->first).directEmission));
  }
  if (stats) *stats = total;
}

}  // namespace pathfarm
