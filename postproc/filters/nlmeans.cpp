#include "postproc/filters/nlmeans.h"

#include "postproc/filters/nlmeans_prepared.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

namespace pathfarm {
namespace {

using nlmeans_detail::kExpClamp;
using nlmeans_detail::Prepared;

constexpr float kEpsilon = 1e-10f;
constexpr int kBandRows = 32;       // rows per parallel task: fixed, so results do not depend on threads

// e^-x for x in [0, kExpClamp] (callers clamp: a loop doing only that vectorizes, while a
// clamp inside would not): x log2(e) = n + f with n an integer and |f| <= 1/2, 2^f by its
// Taylor polynomial in f ln 2 (|f ln 2| <= 0.347, degree 6: relative error below 3e-7), 2^n
// by the exponent bits; 0 from x ~ 87 on, where 2^n would leave float's normal range (so
// no denormal ever reaches the sums). Plain arithmetic and an integer select, so loops
// over it vectorize and give the same bits everywhere.

inline float expNegative(float x) {
  const float t = x * -1.44269504088896341f;
  const int n = static_cast<int>(t - 0.5f);  // t <= 0: rounds to the nearest integer
  const float u = (t - static_cast<float>(n)) * 0.693147180559945309f;
  const float p =
      1.0f +
      u * (1.0f + u * (0.5f + u * (1.0f / 6.0f + u * (1.0f / 24.0f + u * (1.0f / 120.0f + u * (1.0f / 720.0f))))));
  const int biased = n + 127;
  const uint32_t bits = static_cast<uint32_t>(biased > 1 ? biased : 0) << 23;  // 0 bits: +0.0
  return p * std::bit_cast<float>(bits);
}

// out[0] = 0 and out[i + 1] = in[0] + ... + in[i] for i < n. Four stretches are summed as
// independent chains (their additions overlap in the pipeline) and then joined, which
// is several times faster than one chain; the order is fixed, so are the bits.
template <class T>
void prefixSums(const T* in, double* out, int n) {
  out[0] = 0.0;
  if (n < 16) {
    for (int i = 0; i < n; ++i) out[i + 1] = out[i] + static_cast<double>(in[i]);
    return;
  }
  const int len = (n + 3) / 4, last = n - 3 * len;  // three stretches of len, the last shorter
  const T* in1 = in + len;
  const T* in2 = in + 2 * len;
  const T* in3 = in + 3 * len;
  double* out1 = out + len;
  double* out2 = out + 2 * len;
  double* out3 = out + 3 * len;
  double a = 0.0, b = 0.0, c = 0.0, d = 0.0;
  int i = 0;
  for (; i < last; ++i) {
    a += static_cast<double>(in[i]);
    b += static_cast<double>(in1[i]);
    c += static_cast<double>(in2[i]);
    d += static_cast<double>(in3[i]);
    out[i + 1] = a;
    out1[i + 1] = b;
    out2[i + 1] = c;
    out3[i + 1] = d;
  }
  for (; i < len; ++i) {
    a += static_cast<double>(in[i]);
    b += static_cast<double>(in1[i]);
    c += static_cast<double>(in2[i]);
    out[i + 1] = a;
    out1[i + 1] = b;
    out2[i + 1] = c;
  }
  for (int s = 1; s < 4; ++s) {
    const int begin = s * len, end = std::min(n, begin + len);
    const double base = out[begin];
    for (int j = begin + 1; j <= end; ++j) out[j] += base;
  }
}

// Per row of frame 0, the columns [first, last + 1) that hold its valid pixels ({0, 0}: none).
using RowSpans = std::vector<std::pair<int, int>>;

RowSpans validSpans(const Prepared& prepared) {
  const int w = prepared.width;
  RowSpans spans(static_cast<size_t>(prepared.height), {0, 0});
  const float* valid = prepared.frames[0].valid;
  for (int y = 0; y < prepared.height; ++y) {
    const float* row = valid + static_cast<size_t>(y) * static_cast<size_t>(w);
    int first = 0;
    while (first < w && !(row[first] > 0.0f)) ++first;
    int last = w;
    while (last > first && !(row[last - 1] > 0.0f)) --last;
    if (first < last) spans[static_cast<size_t>(y)] = {first, last};
  }
  return spans;
}

// The weights of one band of rows [y0, y1) of frame 0 towards one frame and one offset.
class BandFilter {
 public:
  // `spans` (may be null: every pixel is wanted): the wanted columns of each row.
  BandFilter(const Prepared& prepared, const NlMeansSettings& s, int y0, int y1, bool keepFeatureDistances,
             const RowSpans* spans = nullptr)
      : in_(prepared), s_(s), y0_(y0), y1_(y1), keep_(keepFeatureDistances), spans_(spans) {
    const size_t w = static_cast<size_t>(in_.width);
    const size_t rows = static_cast<size_t>(y1 - y0 + 2 * s.patch);
    distance_.resize(rows * w);
    mask_.resize(rows * w);
    columnDistance_.resize(w);
    columnMask_.resize(w);
    prefixDistance_.resize(w + 1);
    prefixMask_.resize(w + 1);
    patch_.resize(w);
    largest_.resize(w);
    sum_.resize(w);
    equal_.resize(w);
    pixelDistance_.resize(w);
    weight_.resize(w);
    if (keep_) featureDistance_.assign(in_.kinds.size(), std::vector<float>(w));
  }

  const float* weight() const { return weight_.data(); }
  const float* patchDistance() const { return patch_.data(); }
  const float* featureDistance(size_t g) const { return featureDistance_[g].data(); }

  // Calls onRow(y, x0, x1) for each row y of the band whose pixels p have partners
  // q = p + (dx, dy) inside the image, for x in [x0, x1), once the row's weights are ready.
  template <class RowFn>
  void run(int t, int dx, int dy, RowFn&& onRow) {
    const std::optional<Reach> reached = reachOf(dx, dy);
    if (!reached) return;
    const Reach& reach = *reached;
    const Prepared::Frame& pt = in_.frames[static_cast<size_t>(t)];
    const bool center = t == 0 && dx == 0 && dy == 0;
    computePixelDistances(pt, dx, dy, reach);

    // Column sums over the patch rows, slid down the band, and row sums of those: exact, as
    // the distances lie on a grid (Prepared::distanceSnap), so a pixel's patch distance is
    // the same bits wherever the band or the image starts (a window of rows, a cropped box).
    const int f = s_.patch;
    std::fill(columnDistance_.begin(), columnDistance_.end(), 0.0);
    std::fill(columnMask_.begin(), columnMask_.end(), 0.0f);
    for (int y = std::max(reach.ry0, reach.oy0 - f); y < std::min(reach.ry1, reach.oy0 + f + 1); ++y)
      slideRows(reach, y, -1);

    for (int y = reach.oy0; y < reach.oy1; ++y) {
      if (y > reach.oy0) {
        slideRows(reach, y + f < reach.ry1 ? y + f : -1, y - f - 1 >= reach.ry0 ? y - f - 1 : -1);
      }
      // The columns of this row whose weights are wanted.
      int wx0 = reach.xa, wx1 = reach.xb;
      if (spans_ != nullptr) {
        wx0 = std::max(reach.xa, (*spans_)[static_cast<size_t>(y)].first);
        wx1 = std::min(reach.xb, (*spans_)[static_cast<size_t>(y)].second);
        if (wx0 >= wx1) continue;
      }
      computePatchDistances(reach);
      const size_t rowP = static_cast<size_t>(y) * static_cast<size_t>(in_.width);
      const ptrdiff_t rowQ = static_cast<ptrdiff_t>(y + dy) * in_.width + dx;
      computeFeatureDistances(pt, rowP, rowQ, wx0, wx1);
      computeWeights(pt, center, rowP, rowQ, wx0, wx1);
      onRow(y, wx0, wx1);
    }
  }

 private:
  // What one offset reaches: the columns [xa, xb) and the band's rows [oy0, oy1) whose
  // partners lie inside the image, and the rows [ry0, ry1) their patches read.
  struct Reach {
    int xa, xb, oy0, oy1, ry0, ry1;
  };

  // None when no pixel of the band has a partner at offset (dx, dy), or none is wanted.
  std::optional<Reach> reachOf(int dx, int dy) const {
    const int w = in_.width, h = in_.height, f = s_.patch;
    Reach reach;
    reach.xa = std::max(0, -dx);
    reach.xb = std::min(w, w - dx);
    reach.oy0 = std::max(y0_, -dy);
    reach.oy1 = std::min(y1_, h - dy);
    if (reach.xa >= reach.xb || reach.oy0 >= reach.oy1) return std::nullopt;
    if (spans_ != nullptr) {
      // Distances are needed only within a patch of the wanted columns.
      int lo = w, hi = 0;
      for (int y = reach.oy0; y < reach.oy1; ++y) {
        const auto [first, last] = (*spans_)[static_cast<size_t>(y)];
        if (first >= last) continue;
        lo = std::min(lo, first);
        hi = std::max(hi, last);
      }
      reach.xa = std::max(reach.xa, lo - f);
      reach.xb = std::min(reach.xb, hi + f);
      if (reach.xa >= reach.xb) return std::nullopt;
    }
    reach.ry0 = std::max(0, reach.oy0 - f);
    reach.ry1 = std::min(h, reach.oy1 + f);
    return reach;
  }

  // Per-pixel distances d(x, x + offset) towards frame `pt` on the rows the band's patches
  // reach, and where both pixels are valid. Only the columns [xa, xb) are read later.
  void computePixelDistances(const Prepared::Frame& pt, int dx, int dy, const Reach& reach) {
    const int w = in_.width, h = in_.height;
    const size_t W = static_cast<size_t>(w);
    const Prepared::Frame& p0 = in_.frames[0];
    const float kc2 = s_.kc * s_.kc, alpha = s_.alpha, inverseChannels = 1.0f / static_cast<float>(in_.channels);
    const float low = -in_.distanceLow, high = in_.distanceHigh;
    for (int y = reach.ry0; y < reach.ry1; ++y) {
      double* snapped = distance_.data() + static_cast<size_t>(y - reach.ry0) * W;
      float* m = mask_.data() + static_cast<size_t>(y - reach.ry0) * W;
      if (y + dy < 0 || y + dy >= h) {
        std::fill(snapped + reach.xa, snapped + reach.xb, 0.0);
        std::fill(m + reach.xa, m + reach.xb, 0.0f);
        continue;
      }
      float* d = pixelDistance_.data();
      std::fill(d + reach.xa, d + reach.xb, 0.0f);
      const size_t rowP = static_cast<size_t>(y) * W;
      const ptrdiff_t rowQ = static_cast<ptrdiff_t>(y + dy) * w + dx;
      for (int c = 0; c < in_.channels; ++c) {
        const float* up = p0.color[static_cast<size_t>(c)] + rowP;
        const float* vp = p0.variance[static_cast<size_t>(c)] + rowP;
        const float* uq = pt.color[static_cast<size_t>(c)] + rowQ;
        const float* vq = pt.variance[static_cast<size_t>(c)] + rowQ;
        for (int x = reach.xa; x < reach.xb; ++x) {
          const float diff = up[x] - uq[x];
          const float a = vp[x], b = vq[x];
          d[x] += (diff * diff - alpha * (a + std::min(a, b))) / (kEpsilon + kc2 * (a + b));
        }
      }
      const float* validP = p0.valid + rowP;
      const float* validQ = pt.valid + rowQ;
      const double snap = in_.distanceSnap;
      for (int x = reach.xa; x < reach.xb; ++x) {
        const float both = validP[x] * validQ[x];
        const float clamped = std::min(std::max(d[x] * inverseChannels, low), high) * both;
        snapped[x] = (static_cast<double>(clamped) + snap) - snap;
        m[x] = both;
      }
    }
  }

  // Adds row `in`'s distances and masses to the column sums and takes off row `out`'s
  // (-1: none). The sums are exact (Prepared::distanceSnap), so one pass may do both.
  [[gnu::always_inline]] void slideRows(const Reach& reach, int in, int out) {
    const size_t W = static_cast<size_t>(in_.width);
    const auto row = [&](int y) { return static_cast<size_t>(y - reach.ry0) * W; };
    double* cd = columnDistance_.data();
    float* cm = columnMask_.data();
    if (in >= 0 && out >= 0) {
      const double *dIn = distance_.data() + row(in), *dOut = distance_.data() + row(out);
      const float *mIn = mask_.data() + row(in), *mOut = mask_.data() + row(out);
      for (int x = reach.xa; x < reach.xb; ++x) {
        cd[x] += dIn[x] - dOut[x];
        cm[x] += mIn[x] - mOut[x];
      }
    } else if (in >= 0) {
      const double* d = distance_.data() + row(in);
      const float* m = mask_.data() + row(in);
      for (int x = reach.xa; x < reach.xb; ++x) {
        cd[x] += d[x];
        cm[x] += m[x];
      }
    } else if (out >= 0) {
      const double* d = distance_.data() + row(out);
      const float* m = mask_.data() + row(out);
      for (int x = reach.xa; x < reach.xb; ++x) {
        cd[x] -= d[x];
        cm[x] -= m[x];
      }
    }
  }

  // The patch distances of the current row into patch_: the row box filter of the column
  // sums, through prefix sums over [xa, xb) (everything outside is zero).
  [[gnu::always_inline]] void computePatchDistances(const Reach& reach) {
    const int f = s_.patch, n = reach.xb - reach.xa;
    const double* pd = prefixDistance_.data();
    const double* pm = prefixMask_.data();
    prefixSums(columnDistance_.data() + reach.xa, prefixDistance_.data(), n);
    prefixSums(columnMask_.data() + reach.xa, prefixMask_.data(), n);
    float* patch = patch_.data() + reach.xa;  // indexed from xa
    // The masses are whole numbers, and where one is 0 so is the sum of distances.
    const auto boxAt = [&](int i, int lo, int hi) {
      patch[i] = static_cast<float>((pd[hi] - pd[lo]) / std::max(pm[hi] - pm[lo], 1.0));
    };
    const int interiorBegin = std::min(n, f), interiorEnd = std::max(interiorBegin, n - f - 1);
    for (int i = 0; i < interiorBegin; ++i) boxAt(i, std::max(0, i - f), std::min(n, i + f + 1));
    for (int i = interiorBegin; i < interiorEnd; ++i) {
      const double mass = std::max(pm[i + f + 1] - pm[i - f], 1.0);
      patch[i] = static_cast<float>((pd[i + f + 1] - pd[i - f]) / mass);
    }
    for (int i = interiorEnd; i < n; ++i) boxAt(i, std::max(0, i - f), std::min(n, i + f + 1));
  }

  // The feature distances of row rowP's columns [wx0, wx1) towards frame `pt`, into
  // largest_ (with the patch distance: the largest of them) and equal_ (0 where an
  // ExactMatch feature differs); kept per feature in featureDistance_ when asked.
  void computeFeatureDistances(const Prepared::Frame& pt, size_t rowP, ptrdiff_t rowQ, int wx0, int wx1) {
    const Prepared::Frame& p0 = in_.frames[0];
    const float* patch = patch_.data();
    float* largest = largest_.data();
    float* equal = equal_.data();
    for (int x = wx0; x < wx1; ++x) {
      largest[x] = std::max(0.0f, patch[x]);
      equal[x] = 1.0f;
    }
    for (size_t g = 0; g < in_.kinds.size(); ++g) {
      const size_t count = static_cast<size_t>(in_.featureChannels[g]);
      if (in_.kinds[g] == FeatureKind::ExactMatch) {
        float* eq = keep_ ? sum_.data() : equal;
        if (keep_) std::fill(sum_.begin() + wx0, sum_.begin() + wx1, 1.0f);
        for (size_t j = 0; j < count; ++j) {
          const float* a = p0.feature[g][j] + rowP;
          const float* b = pt.feature[g][j] + rowQ;
          for (int x = wx0; x < wx1; ++x) eq[x] = a[x] == b[x] ? eq[x] : 0.0f;
        }
        if (keep_) {
          float* out = featureDistance_[g].data();
          for (int x = wx0; x < wx1; ++x) {
            out[x] = eq[x] != 0.0f ? 0.0f : std::numeric_limits<float>::infinity();
            equal[x] *= eq[x];
          }
        }
        continue;
      }
      float* sum = sum_.data();
      std::fill(sum + wx0, sum + wx1, 0.0f);
      for (size_t j = 0; j < count; ++j) {
        const float* a = p0.feature[g][j] + rowP;
        const float* b = pt.feature[g][j] + rowQ;
        for (int x = wx0; x < wx1; ++x) {
          const float diff = a[x] - b[x];
          sum[x] += diff * diff;
        }
        if (!p0.featureVariance[g].empty()) {
          const float* va = p0.featureVariance[g][j] + rowP;
          const float* vb = pt.featureVariance[g][j] + rowQ;
          for (int x = wx0; x < wx1; ++x) sum[x] -= va[x] + std::min(va[x], vb[x]);
        }
      }
      const float* scale = in_.featureScale[g].data() + rowP;
      float* out = keep_ ? featureDistance_[g].data() : sum;
      for (int x = wx0; x < wx1; ++x) {
        const float distance = sum[x] * scale[x];
        out[x] = distance;
        largest[x] = std::max(largest[x], distance);
      }
    }
  }

  // The weights of row rowP's columns [wx0, wx1) into weight_; the center pixel's is its validity.
  void computeWeights(const Prepared::Frame& pt, bool center, size_t rowP, ptrdiff_t rowQ, int wx0, int wx1) {
    float* weight = weight_.data();
    float* largest = largest_.data();
    const float* equal = equal_.data();
    const float* validQ = pt.valid + rowQ;
    if (center) {
      for (int x = wx0; x < wx1; ++x) weight[x] = in_.frames[0].valid[rowP + static_cast<size_t>(x)];
    } else {
      for (int x = wx0; x < wx1; ++x) largest[x] = std::min(kExpClamp, largest[x]);  // NaN: the clamp
      for (int x = wx0; x < wx1; ++x) weight[x] = expNegative(largest[x]) * equal[x] * validQ[x];
    }
  }

  const Prepared& in_;
  const NlMeansSettings& s_;
  int y0_, y1_;
  bool keep_;
  const RowSpans* spans_;
  std::vector<double> distance_;    // per-pixel distances on the band's rows, on the grid
  std::vector<float> mask_;
  std::vector<float> pixelDistance_;  // one row's, summed over the channels
  std::vector<double> columnDistance_;
  std::vector<float> columnMask_;
  std::vector<double> prefixDistance_, prefixMask_;
  std::vector<float> patch_, largest_, sum_, equal_, weight_;
  std::vector<std::vector<float>> featureDistance_;
};

int bandCount(int height) { return (height + kBandRows - 1) / kBandRows; }

// The filtered colors of one band of rows into `out`, and its pixels without a partner
// of any weight into `unfilled`. Both instruction sets below compile this same code.
[[gnu::always_inline]] inline void filterBand(const Prepared& prepared, const NlMeansSettings& settings,
                                              const RowSpans* spans, int band, Planes& out,
                                              std::vector<uint8_t>& unfilled) {
  const int w = prepared.width, h = prepared.height, r = settings.radius;
  const size_t W = static_cast<size_t>(w);
  const size_t channels = static_cast<size_t>(prepared.channels);
  const int y0 = band * kBandRows, y1 = std::min(h, y0 + kBandRows);
  const size_t cells = static_cast<size_t>(y1 - y0) * W;
  std::vector<float> weightSum(cells, 0.0f), colorSum(channels * cells, 0.0f);
  BandFilter filter(prepared, settings, y0, y1, false, spans);
  for (size_t t = 0; t < prepared.frames.size(); ++t) {
    const Prepared::Frame& frame = prepared.frames[t];
    if (!frame.active) continue;
    for (int dy = -r; dy <= r; ++dy) {
      for (int dx = -r; dx <= r; ++dx) {
        filter.run(static_cast<int>(t), dx, dy, [&](int y, int x0, int x1) {
          const float* weight = filter.weight();
          const size_t row = static_cast<size_t>(y - y0) * W;
          float* ws = weightSum.data() + row;
          for (int x = x0; x < x1; ++x) ws[x] += weight[x];
          const ptrdiff_t rowQ = static_cast<ptrdiff_t>(y + dy) * w + dx;
          for (size_t c = 0; c < channels; ++c) {
            float* cs = colorSum.data() + c * cells + row;
            const float* uq = frame.color[c] + rowQ;
            for (int x = x0; x < x1; ++x) cs[x] += weight[x] * uq[x];
          }
        });
      }
    }
  }
  for (size_t i = 0; i < cells; ++i) {
    const size_t p = static_cast<size_t>(y0) * W + i;
    const float ws = weightSum[i];
    if (!(ws > 0.0f)) unfilled[p] = 1;
    for (size_t c = 0; c < channels; ++c) out.channels[c][p] = ws > 0.0f ? colorSum[c * cells + i] / ws : 0.0f;
  }
}

// The band's filter with 256-bit vectors where the CPU has them: about 1.5x faster. AVX2
// without FMA does each float operation as the baseline build does (a fused multiply-add
// would round once where the baseline rounds twice), so a worker's bits do not depend on
// which of the two it ran. `flatten` compiles the whole filter, inlined, for AVX2.
[[gnu::target("avx2"), gnu::flatten]] void filterBandAvx2(const Prepared& prepared, const NlMeansSettings& settings,
                                                            const RowSpans* spans, int band, Planes& out,
                                                            std::vector<uint8_t>& unfilled) {
  filterBand(prepared, settings, spans, band, out, unfilled);
}

[[gnu::flatten]] void filterBandBaseline(const Prepared& prepared, const NlMeansSettings& settings,
                                         const RowSpans* spans, int band, Planes& out, std::vector<uint8_t>& unfilled) {
  filterBand(prepared, settings, spans, band, out, unfilled);
}

}  // namespace

Planes jointNlMeans(const NlMeansInput& input, const NlMeansSettings& settings, NlMeansStats* stats) {
  const Prepared prepared(input, settings);
  Planes out(prepared.width, prepared.height, prepared.channels);
  std::vector<uint8_t> unfilled(out.pixelCount(), 0);
  const RowSpans spans = settings.validCentersOnly ? validSpans(prepared) : RowSpans{};
  const RowSpans* wanted = settings.validCentersOnly ? &spans : nullptr;
  const auto filter = settings.wideVectors && __builtin_cpu_supports("avx2") ? filterBandAvx2 : filterBandBaseline;
  tbb::parallel_for(tbb::blocked_range<int>(0, bandCount(prepared.height), 1), [&](const tbb::blocked_range<int>& bands) {
    for (int band = bands.begin(); band != bands.end(); ++band) filter(prepared, settings, wanted, band, out, unfilled);
  });

  if (stats != nullptr) {
    stats->invalidCenters = prepared.invalidCenters;
    stats->invalidCenter = prepared.invalidCenter;
    stats->unfilledCenters = static_cast<size_t>(std::count(unfilled.begin(), unfilled.end(), uint8_t{1}));
  }
  return out;
}

NlMeansPairTerms jointNlMeansPairTerms(const NlMeansInput& input, const NlMeansSettings& settings, int frame, int dx,
                                       int dy) {
  const Prepared prepared(input, settings);
  if (frame < 0 || static_cast<size_t>(frame) >= prepared.frames.size())
    throw std::invalid_argument("NL-means: no frame " + std::to_string(frame) + " in the window");
  const int w = prepared.width, h = prepared.height;
  const size_t W = static_cast<size_t>(w), pixels = W * static_cast<size_t>(h);
  const float infinity = std::numeric_limits<float>::infinity();
  NlMeansPairTerms terms;
  terms.colorDistance.assign(pixels, infinity);
  terms.featureDistance.assign(prepared.kinds.size(), std::vector<float>(pixels, infinity));
  terms.weight.assign(pixels, 0.0f);
  for (int band = 0; band < bandCount(h); ++band) {
    const int y0 = band * kBandRows, y1 = std::min(h, y0 + kBandRows);
    BandFilter filter(prepared, settings, y0, y1, true);
    filter.run(frame, dx, dy, [&](int y, int x0, int x1) {
      const size_t row = static_cast<size_t>(y) * W;
      for (int x = x0; x < x1; ++x) {
        const size_t p = row + static_cast<size_t>(x);
        terms.colorDistance[p] = filter.patchDistance()[x];
        terms.weight[p] = filter.weight()[x];
        for (size_t g = 0; g < prepared.kinds.size(); ++g) terms.featureDistance[g][p] = filter.featureDistance(g)[x];
      }
    });
  }
  return terms;
}

}  // namespace pathfarm
