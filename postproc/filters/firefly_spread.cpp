#include "postproc/filters/firefly_spread.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace pathfarm {
namespace {

constexpr int kJudgeRadius = 2;               // the 5x5 window a firefly is judged on
constexpr float kSameSurfaceCosine = 0.906f;  // cos 25 degrees

void requireShape(const Planes& planes, const Planes& color, size_t channels, const char* what) {
  if (planes.width != color.width || planes.height != color.height || planes.channels.size() != channels)
    throw std::invalid_argument(std::string("splitFireflies: the ") + what + " does not match the color's size or channels");
}

struct Firefly {
  int x, y;
  float scale;  // of its color to the clamped luminance
  float level;  // its neighbours' mean luminance, the brightest left out
  int radius;   // of its spread
};

// The weights of a spread of radius r: a Gaussian of sigma r / 2, cut to the square.
float spreadWeight(int dx, int dy, int r) {
  const float sigma = 0.5f * static_cast<float>(r);
  return std::exp(-static_cast<float>(dx * dx + dy * dy) / (2.0f * sigma * sigma));
}

// The smallest radius whose spread of `excess` peaks at no more than `glow` times `level`
// (its weights sum to at least excess / (glow level)), up to maxRadius.
int spreadRadius(float excess, float level, const FireflySettings& s) {
  const int most = std::max(1, s.maxRadius);
  if (level <= 0.0f || s.glow <= 0.0f) return most;
  const double mass = excess / (s.glow * level);
  for (int r = 1; r < most; ++r) {
    double line = 0;
    for (int d = -r; d <= r; ++d) line += spreadWeight(d, 0, r);
    if (line * line >= mass) return r;
  }
  return most;
}

class Judge {
 public:
  Judge(const Planes& color, const Planes& variance, const std::vector<float>& valid)
      : width_(color.width), height_(color.height), luminance_(color.pixelCount()), error_(color.pixelCount()),
        usable_(color.pixelCount()) {
    const float channels = static_cast<float>(color.channels.size());
    for (size_t p = 0; p < luminance_.size(); ++p) {
      bool finite = valid.empty() || valid[p] != 0.0f;
      float sum = 0, meanVariance = 0;
      for (size_t c = 0; c < color.channels.size(); ++c) {
        finite = finite && std::isfinite(color.channels[c][p]) && std::isfinite(variance.channels[c][p]);
        sum += color.channels[c][p];
        meanVariance += std::max(0.0f, variance.channels[c][p]);
      }
      usable_[p] = finite ? 1 : 0;
      luminance_[p] = finite ? sum / channels : 0.0f;
      error_[p] = finite ? std::sqrt(meanVariance / channels) : 0.0f;
    }
  }

  bool usable(size_t p) const { return usable_[p] != 0; }

  float luminance(size_t p) const { return luminance_[p]; }

  // The firefly at (x, y), if it is one.
  bool judge(int x, int y, const FireflySettings& s, Firefly& out) const {
    const size_t p = index(x, y);
    const float value = luminance_[p];
    if (!usable_[p] || value <= 0.0f || error_[p] < s.minRelativeError * value) return false;
    Window levels{}, errors{};
    size_t count = 0;
    for (int v = std::max(0, y - kJudgeRadius); v <= std::min(height_ - 1, y + kJudgeRadius); ++v)
      for (int u = std::max(0, x - kJudgeRadius); u <= std::min(width_ - 1, x + kJudgeRadius); ++u) {
        const size_t q = index(u, v);
        if (q == p || !usable_[q]) continue;
        levels[count] = luminance_[q];
        errors[count++] = error_[q];
      }
    if (count < static_cast<size_t>(std::max(2, s.minNeighbours))) return false;
    const float level = std::max(0.0f, meanWithoutBrightest(levels, count));
    const float limit = s.factor * level;
    if (value <= limit || value - level <= s.outlierErrors * median(errors, count)) return false;
    out = {x, y, limit / value, level, spreadRadius(value - limit, level, s)};
    return true;
  }

 private:
  using Window = std::array<float, (2 * kJudgeRadius + 1) * (2 * kJudgeRadius + 1)>;

  // The mean of all but the largest value: another firefly nearby does not lift it, but
  // a crowd of them (a caustic that few samples found) does, and keeps its light.
  static float meanWithoutBrightest(const Window& values, size_t count) {
    double sum = 0;
    float brightest = values[0];
    for (size_t i = 0; i < count; ++i) {
      sum += values[i];
      brightest = std::max(brightest, values[i]);
    }
    return static_cast<float>((sum - brightest) / static_cast<double>(count - 1));
  }

  static float median(Window& values, size_t count) {
    std::nth_element(values.begin(), values.begin() + count / 2, values.begin() + count);
    return values[count / 2];
  }
  size_t index(int x, int y) const { return static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x); }

  int width_, height_;
  std::vector<float> luminance_, error_;  // mean over the channels; standard error
  std::vector<uint8_t> usable_;
};

bool sameSurface(const FireflySurface& surface, size_t a, size_t b) {
  if (surface.objectId != nullptr && surface.objectId->channels[0][a] != surface.objectId->channels[0][b]) return false;
  if (surface.normal == nullptr) return true;
  float dot = 0, la = 0, lb = 0;
  for (const auto& plane : surface.normal->channels) {
    dot += plane[a] * plane[b];
    la += plane[a] * plane[a];
    lb += plane[b] * plane[b];
  }
  return la > 0.0f && lb > 0.0f && dot >= kSameSurfaceCosine * std::sqrt(la * lb);
}

// Per pixel, the mean luminance of the usable pixels of its 3x3 window on its surface that
// are no fireflies (a firefly without such a neighbour: its clamped luminance; 0 where
// nothing is usable): how much of a spread it takes.
std::vector<float> receiverLevels(const Judge& judge, const std::vector<Firefly>& fireflies,
                                  const FireflySurface& surface, int width, int height) {
  const auto index = [width](int x, int y) { return static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x); };
  std::vector<uint8_t> firefly(static_cast<size_t>(width) * static_cast<size_t>(height), 0);
  for (const Firefly& f : fireflies) firefly[index(f.x, f.y)] = 1;
  std::vector<float> levels(firefly.size(), 0.0f);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float sum = 0;
      int count = 0;
      for (int v = std::max(0, y - 1); v <= std::min(height - 1, y + 1); ++v)
        for (int u = std::max(0, x - 1); u <= std::min(width - 1, x + 1); ++u) {
          const size_t q = index(u, v);
          if (!judge.usable(q) || firefly[q] || !sameSurface(surface, index(x, y), q)) continue;
          sum += std::max(0.0f, judge.luminance(q));
          ++count;
        }
      levels[index(x, y)] = count > 0 ? sum / static_cast<float>(count) : 0.0f;
    }
  for (const Firefly& f : fireflies)
    if (levels[index(f.x, f.y)] == 0.0f) levels[index(f.x, f.y)] = judge.luminance(index(f.x, f.y)) * f.scale;
  return levels;
}

}  // namespace

int fireflyReach(const FireflySettings& settings) {
  // A firefly up to maxRadius away; its weights normalized over the pixels up to
  // maxRadius from it, each weighted by its 3x3 window, whose pixels' firefly judgement
  // reads their 5x5 windows.
  return 2 * std::max(1, settings.maxRadius) + 1 + kJudgeRadius;
}

FireflySplit splitFireflies(Planes& color, Planes& variance, const std::vector<float>& valid,
                            const FireflySurface& surface, const FireflySettings& settings) {
  const size_t channels = color.channels.size();
  if (channels == 0) throw std::invalid_argument("splitFireflies: the color has no channel");
  requireShape(variance, color, channels, "variance");
  if (!valid.empty() && valid.size() != color.pixelCount())
    throw std::invalid_argument("splitFireflies: the validity does not match the color's size");
  if (surface.normal != nullptr) requireShape(*surface.normal, color, 3, "normal");
  if (surface.objectId != nullptr) requireShape(*surface.objectId, color, 1, "object id");
  for (const auto& plane : color.channels)
    if (plane.size() != color.pixelCount()) throw std::invalid_argument("splitFireflies: a color plane has the wrong size");

  FireflySplit split;
  split.excess = Planes(color.width, color.height, static_cast<int>(channels));
  const Judge judge(color, variance, valid);
  std::vector<Firefly> fireflies;
  for (int y = 0; y < color.height; ++y)
    for (int x = 0; x < color.width; ++x)
      if (Firefly f; judge.judge(x, y, settings, f)) fireflies.push_back(f);
  if (fireflies.empty()) return split;

  const std::vector<float> receiverLevel = receiverLevels(judge, fireflies, surface, color.width, color.height);
  std::vector<float> share;
  for (const Firefly& f : fireflies) {
    const int r = f.radius, side = 2 * r + 1;
    share.assign(static_cast<size_t>(side * side), 0.0f);
    const size_t p = static_cast<size_t>(f.y) * static_cast<size_t>(color.width) + static_cast<size_t>(f.x);
    // Who receives, in proportion to its own light (a shadow beside the firefly takes
    // little), and the normalization over receivers and pixels without a sample, which
    // count at the firefly's level.
    float total = 0;
    for (int dy = -r; dy <= r; ++dy)
      for (int dx = -r; dx <= r; ++dx) {
        const int u = f.x + dx, v = f.y + dy;
        if (u < 0 || v < 0 || u >= color.width || v >= color.height) continue;
        const size_t k = static_cast<size_t>((dy + r) * side + dx + r);
        const float weight = spreadWeight(dx, dy, r);
        const size_t q = static_cast<size_t>(v) * static_cast<size_t>(color.width) + static_cast<size_t>(u);
        if (!judge.usable(q)) {
          total += weight * f.level;
        } else if (sameSurface(surface, p, q)) {
          share[k] = weight * receiverLevel[q];
          total += share[k];
        }
      }
    // The firefly itself is a receiver, so this holds unless its whole surround is black:
    // then nothing tells where its light belongs, and it stays.
    if (!(total > 0.0f)) continue;
    split.fireflies.push_back(p);
    for (size_t c = 0; c < channels; ++c) {
      const float excess = color.channels[c][p] * (1.0f - f.scale);
      color.channels[c][p] *= f.scale;
      variance.channels[c][p] *= f.scale * f.scale;
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          const float w = share[static_cast<size_t>((dy + r) * side + dx + r)];
          if (w == 0.0f) continue;
          const size_t q = static_cast<size_t>(f.y + dy) * static_cast<size_t>(color.width) + static_cast<size_t>(f.x + dx);
          split.excess.channels[c][q] += excess * w / total;
        }
    }
  }
  return split;
}

}  // namespace pathfarm
