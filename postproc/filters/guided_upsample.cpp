#include "postproc/filters/guided_upsample.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#include <utility>

#include "image/size_text.h"

namespace pathfarm {
namespace {

// Output rows per strip, placed by frame rows. Fixed (never derived from the thread count
// or a band's rows), so the running sums start at the same rows whatever the parallelism
// or the band and results are bit-identical.
constexpr int kStripRows = 64;
// Pixels solved together (structure of arrays).
constexpr int kBatch = 8;

// Whether only some rows are wanted (GuidedUpsampleSettings::onlyFirst, onlyEnd).
bool isBand(const GuidedUpsampleSettings& settings) { return settings.onlyEnd != settings.onlyFirst; }

void checkPlanes(const Planes& planes, const std::string& what) {
  if (planes.width < 0 || planes.height < 0)
    throw std::invalid_argument("guidedUpsample: the " + what + " has a negative size");
  if (planes.channels.empty()) throw std::invalid_argument("guidedUpsample: the " + what + " has no channel");
  for (size_t c = 0; c < planes.channels.size(); ++c)
    if (planes.channels[c].size() != planes.pixelCount())
      throw std::invalid_argument("guidedUpsample: channel " + std::to_string(c) + " of the " + what + " holds " +
                                  std::to_string(planes.channels[c].size()) + " values, not " +
                                  sizeText(planes.width, planes.height));
}

// Per worker: the vertical running sums and the ring of coefficient rows.
struct Workspace {
  std::vector<double> columnStats;  // width x K: vertical window sums of the statistics
  std::vector<double> rowStats;     // K: horizontal running sum
  std::vector<double> ring;         // ringRows x width x C: coefficients of recent rows
  std::vector<double> columnCoef;   // width x C: vertical window sums of the coefficients
  std::vector<double> rowCoef;      // C
  std::vector<double> guide, input;  // one pixel's values
  // A batch of kBatch pixels' windows, lane innermost (see Upsampler::solve).
  std::vector<double> batchStats, batchInverseCount, batchMean, batchL, batchX, batchPivot, batchCoef;
};

class Upsampler {
 public:
  Upsampler(const Planes& low, const Planes& guide, const GuidedUpsampleSettings& settings,
            GuidedUpsampleResult& result)
      : low_(low), guide_(guide), result_(result), width_(guide.width), height_(guide.height),
        factor_(settings.factor), R_(settings.radius * settings.factor), epsilon_(settings.epsilon),
        n_(static_cast<int>(guide.channels.size())), m_(static_cast<int>(low.channels.size())) {
    // Statistics per pixel: I (n), p (m), the upper triangle of I I^T (n(n+1)/2), I p^T (n m).
    offsetP_ = n_;
    offsetII_ = n_ + m_;
    offsetIP_ = offsetII_ + n_ * (n_ + 1) / 2;
    K_ = offsetIP_ + n_ * m_;
    // Coefficients per pixel: a (n m, a[c * m + j]), then b (m).
    C_ = n_ * m_ + m_;
    ringRows_ = 2 * R_ + 2;
    onlyFirst_ = isBand(settings) ? settings.onlyFirst - settings.firstRow : 0;
    onlyEnd_ = isBand(settings) ? settings.onlyEnd - settings.firstRow : height_;
    lowColumn_.resize(static_cast<size_t>(width_));
    for (int x = 0; x < width_; ++x) lowColumn_[static_cast<size_t>(x)] = x / factor_;
  }

  Workspace workspace() const {
    Workspace w;
    w.columnStats.resize(static_cast<size_t>(width_) * K_);
    w.rowStats.resize(static_cast<size_t>(K_));
    w.ring.resize(static_cast<size_t>(ringRows_) * width_ * C_);
    w.columnCoef.resize(static_cast<size_t>(width_) * C_);
    w.rowCoef.resize(static_cast<size_t>(C_));
    w.guide.resize(static_cast<size_t>(n_));
    w.input.resize(static_cast<size_t>(m_));
    w.batchStats.resize(static_cast<size_t>(K_) * kBatch);
    w.batchInverseCount.resize(kBatch);
    w.batchMean.resize(static_cast<size_t>(K_) * kBatch);
    w.batchL.resize(static_cast<size_t>(n_) * n_ * kBatch);
    w.batchX.resize(static_cast<size_t>(n_) * m_ * kBatch);
    w.batchPivot.resize(static_cast<size_t>(n_) * kBatch);
    w.batchCoef.resize(static_cast<size_t>(C_) * kBatch);
    return w;
  }

  // Output rows [y0, y1).
  void strip(int y0, int y1, Workspace& w) const {
    std::fill(w.columnStats.begin(), w.columnStats.end(), 0.0);
    std::fill(w.columnCoef.begin(), w.columnCoef.end(), 0.0);
    int statsLo = 0, statsHi = -1;  // rows summed into columnStats
    bool statsEmpty = true;
    int coefLo = std::max(0, y0 - R_), coefHi = coefLo - 1;  // coefficient rows in columnCoef
    for (int y = y0; y < y1; ++y) {
      const int wantLo = std::max(0, y - R_), wantHi = std::min(height_ - 1, y + R_);
      while (coefHi < wantHi) {
        const int t = ++coefHi;
        const int tLo = std::max(0, t - R_), tHi = std::min(height_ - 1, t + R_);
        if (statsEmpty) {
          statsLo = tLo;
          statsHi = tLo - 1;
          statsEmpty = false;
        }
        while (statsHi < tHi) accumulateStats<true>(++statsHi, w);
        while (statsLo < tLo) accumulateStats<false>(statsLo++, w);
        double* coef = ringRow(t, w);
        coefficientsRow(tHi - tLo + 1, coef, w);
        accumulateCoefficients<true>(coef, w);
      }
      while (coefLo < wantLo) accumulateCoefficients<false>(ringRow(coefLo++, w), w);
      if (y >= onlyFirst_ && y < onlyEnd_) outputRow(y, wantHi - wantLo + 1, w);
    }
  }

 private:
  double* ringRow(int row, Workspace& w) const {
    return w.ring.data() + static_cast<size_t>(row % ringRows_) * width_ * C_;
  }

  // Adds (or removes) one full-resolution row's statistics to the vertical sums.
  template <bool Add>
  void accumulateStats(int y, Workspace& w) const {
    const size_t row = static_cast<size_t>(y) * width_;
    const size_t lowRow = static_cast<size_t>(y / factor_) * low_.width;
    double* I = w.guide.data();
    double* p = w.input.data();
    for (int x = 0; x < width_; ++x) {
      for (int c = 0; c < n_; ++c) I[c] = guide_.channels[static_cast<size_t>(c)][row + x];
      const size_t lowIndex = lowRow + lowColumn_[static_cast<size_t>(x)];
      for (int j = 0; j < m_; ++j) p[j] = low_.channels[static_cast<size_t>(j)][lowIndex];
      double* s = w.columnStats.data() + static_cast<size_t>(x) * K_;
      const auto put = [&s](double v) {
        if constexpr (Add) *s++ += v;
        else *s++ -= v;
      };
      for (int c = 0; c < n_; ++c) put(I[c]);
      for (int j = 0; j < m_; ++j) put(p[j]);
      for (int c = 0; c < n_; ++c)
        for (int d = c; d < n_; ++d) put(I[c] * I[d]);
      for (int c = 0; c < n_; ++c)
        for (int j = 0; j < m_; ++j) put(I[c] * p[j]);
    }
  }

  template <bool Add>
  void accumulateCoefficients(const double* coef, Workspace& w) const {
    const size_t count = static_cast<size_t>(width_) * C_;
    double* s = w.columnCoef.data();
    for (size_t i = 0; i < count; ++i) {
      if constexpr (Add) s[i] += coef[i];
      else s[i] -= coef[i];
    }
  }

  // Slides a horizontal window of radius R_ over `columns` (width x stride); calls
  // visit(x, sums, 1 / column count).
  template <typename Visit>
  void slideRow(const double* columns, int stride, double* sums, Visit&& visit) const {
    std::fill(sums, sums + stride, 0.0);
    for (int x = 0; x <= std::min(width_ - 1, R_); ++x)
      for (int k = 0; k < stride; ++k) sums[k] += columns[static_cast<size_t>(x) * stride + k];
    for (int x = 0; x < width_; ++x) {
      if (x > 0) {
        if (x + R_ < width_) {
          const double* in = columns + static_cast<size_t>(x + R_) * stride;
          for (int k = 0; k < stride; ++k) sums[k] += in[k];
        }
        if (x - R_ - 1 >= 0) {
          const double* out = columns + static_cast<size_t>(x - R_ - 1) * stride;
          for (int k = 0; k < stride; ++k) sums[k] -= out[k];
        }
      }
      const int count = std::min(width_ - 1, x + R_) - std::max(0, x - R_) + 1;
      visit(x, static_cast<const double*>(sums), count);
    }
  }

  // The linear model of every window centred on row t (whose window spans `rows` rows),
  // solved kBatch pixels at a time.
  void coefficientsRow(int rows, double* coef, Workspace& w) const {
    double* batch = w.batchStats.data();
    double* inverseCount = w.batchInverseCount.data();
    int lanes = 0, first = 0;
    slideRow(w.columnStats.data(), K_, w.rowStats.data(), [&](int x, const double* sums, int columns) {
      if (lanes == 0) first = x;
      for (int k = 0; k < K_; ++k) batch[k * kBatch + lanes] = sums[k];
      inverseCount[lanes] = 1.0 / (static_cast<double>(columns) * rows);
      if (++lanes == kBatch || x == width_ - 1) {
        for (int lane = lanes; lane < kBatch; ++lane) {  // pad with the last pixel
          for (int k = 0; k < K_; ++k) batch[k * kBatch + lane] = batch[k * kBatch + lanes - 1];
          inverseCount[lane] = inverseCount[lanes - 1];
        }
        solve(w);
        const double* solved = w.batchCoef.data();
        for (int lane = 0; lane < lanes; ++lane)
          for (int k = 0; k < C_; ++k) coef[static_cast<size_t>(first + lane) * C_ + k] = solved[k * kBatch + lane];
        lanes = 0;
      }
    });
  }

  // Per pixel of the batch: a = (Sigma + eps U)^-1 cov(I, p), b = mean(p) - a^T mean(I),
  // from the window sums in w.batchStats. Arrays hold kBatch lanes per value (lane
  // innermost), so independent pixels fill the pipeline; every lane computes the same
  // operations in the same order, so the result does not depend on the batching.
  void solve(Workspace& w) const {
    constexpr int B = kBatch;
    const int n = n_, m = m_;
    const double* sums = w.batchStats.data();
    const double* inverseCount = w.batchInverseCount.data();
    double* mean = w.batchMean.data();  // K x B: the window means
    double* L = w.batchL.data();        // n x n x B, lower triangle
    double* x = w.batchX.data();        // n x m x B: cov(I, p), then a
    double* inversePivot = w.batchPivot.data();
    double* coef = w.batchCoef.data();  // C x B
    for (int k = 0; k < K_; ++k)
      for (int l = 0; l < B; ++l) mean[k * B + l] = sums[k * B + l] * inverseCount[l];
    const double* meanI = mean;
    const double* meanP = mean + offsetP_ * B;
    int k = offsetII_;
    for (int c = 0; c < n; ++c)
      for (int d = c; d < n; ++d, ++k) {
        double* target = L + (d * n + c) * B;
        for (int l = 0; l < B; ++l) target[l] = mean[k * B + l] - meanI[c * B + l] * meanI[d * B + l];
      }
    for (int c = 0; c < n; ++c)
      for (int l = 0; l < B; ++l) L[(c * n + c) * B + l] += epsilon_;
    for (int c = 0; c < n; ++c)
      for (int j = 0; j < m; ++j)
        for (int l = 0; l < B; ++l)
          x[(c * m + j) * B + l] = mean[(offsetIP_ + c * m + j) * B + l] - meanI[c * B + l] * meanP[j * B + l];

    // Cholesky, in place on the lower triangle. Sigma is positive semi-definite and
    // epsilon > 0, so every pivot is >= epsilon but for rounding; guard against that.
    double column[kBatch];
    for (int j = 0; j < n; ++j) {
      for (int l = 0; l < B; ++l) column[l] = L[(j * n + j) * B + l];
      for (int q = 0; q < j; ++q)
        for (int l = 0; l < B; ++l) column[l] -= L[(j * n + q) * B + l] * L[(j * n + q) * B + l];
      for (int l = 0; l < B; ++l) {
        const double diagonal = column[l] > 0.0 ? column[l] : epsilon_;
        const double pivot = std::sqrt(diagonal);
        L[(j * n + j) * B + l] = pivot;
        inversePivot[j * B + l] = 1.0 / pivot;
      }
      for (int i = j + 1; i < n; ++i) {
        for (int l = 0; l < B; ++l) column[l] = L[(i * n + j) * B + l];
        for (int q = 0; q < j; ++q)
          for (int l = 0; l < B; ++l) column[l] -= L[(i * n + q) * B + l] * L[(j * n + q) * B + l];
        for (int l = 0; l < B; ++l) L[(i * n + j) * B + l] = column[l] * inversePivot[j * B + l];
      }
    }
    for (int j = 0; j < m; ++j) {
      // Forward (L y = cov_j), then backward (L^T a_j = y), in place in x's column j.
      for (int i = 0; i < n; ++i) {
        for (int l = 0; l < B; ++l) column[l] = x[(i * m + j) * B + l];
        for (int q = 0; q < i; ++q)
          for (int l = 0; l < B; ++l) column[l] -= L[(i * n + q) * B + l] * x[(q * m + j) * B + l];
        for (int l = 0; l < B; ++l) x[(i * m + j) * B + l] = column[l] * inversePivot[i * B + l];
      }
      for (int i = n - 1; i >= 0; --i) {
        for (int l = 0; l < B; ++l) column[l] = x[(i * m + j) * B + l];
        for (int q = i + 1; q < n; ++q)
          for (int l = 0; l < B; ++l) column[l] -= L[(q * n + i) * B + l] * x[(q * m + j) * B + l];
        for (int l = 0; l < B; ++l) x[(i * m + j) * B + l] = column[l] * inversePivot[i * B + l];
      }
      for (int l = 0; l < B; ++l) column[l] = meanP[j * B + l];
      for (int c = 0; c < n; ++c)
        for (int l = 0; l < B; ++l) {
          coef[(c * m + j) * B + l] = x[(c * m + j) * B + l];
          column[l] -= x[(c * m + j) * B + l] * meanI[c * B + l];
        }
      for (int l = 0; l < B; ++l) coef[(n * m + j) * B + l] = column[l];
    }
  }

  // q = mean(a)^T I + mean(b) for row y, whose coefficient window spans `rows` rows.
  void outputRow(int y, int rows, Workspace& w) const {
    const size_t row = static_cast<size_t>(y) * width_;
    slideRow(w.columnCoef.data(), C_, w.rowCoef.data(), [&](int x, const double* sums, int columns) {
      const double inverseCount = 1.0 / (static_cast<double>(columns) * rows);
      const size_t i = row + static_cast<size_t>(x);
      bool negative = false;
      float deficit = 0.0f;
      for (int j = 0; j < m_; ++j) {
        double q = sums[n_ * m_ + j];
        for (int c = 0; c < n_; ++c) q += sums[c * m_ + j] * guide_.channels[static_cast<size_t>(c)][i];
        auto value = static_cast<float>(q * inverseCount);
        if (!(value >= 0.0f)) {  // negative or NaN
          deficit = std::max(deficit, std::isnan(value) ? std::numeric_limits<float>::infinity() : -value);
          value = 0.0f;
          negative = true;
        }
        result_.image.channels[static_cast<size_t>(j)][i] = value;
      }
      result_.rerender[i] = negative ? 1.0f : 0.0f;
      result_.deficit[i] = deficit;
    });
  }

  const Planes& low_;
  const Planes& guide_;
  GuidedUpsampleResult& result_;
  const int width_, height_, factor_, R_;
  const double epsilon_;
  const int n_, m_;
  int offsetP_ = 0, offsetII_ = 0, offsetIP_ = 0, K_ = 0, C_ = 0, ringRows_ = 0;
  int onlyFirst_ = 0, onlyEnd_ = 0;  // the rows written, in the planes' rows
  std::vector<int> lowColumn_;
};

}  // namespace

FrameRows guidedUpsampleReads(const FrameRows& wanted, int height, const GuidedUpsampleSettings& settings) {
  const int factor = std::max(settings.factor, 1);
  // A strip's coefficient windows reach R rows beyond it, and their statistics R more.
  const int reach = 2 * settings.radius * factor;
  const int first = std::max(0, wanted.first / kStripRows * kStripRows - reach);
  const int end = std::min(height, (wanted.end + kStripRows - 1) / kStripRows * kStripRows + reach);
  return {first / factor * factor, std::min(height, (end + factor - 1) / factor * factor)};
}

GuidedUpsampleResult guidedUpsample(const Planes& low, const Planes& guide, const GuidedUpsampleSettings& settings) {
  if (settings.factor < 1)
    throw std::invalid_argument("guidedUpsample: the factor must be at least 1, not " + std::to_string(settings.factor));
  if (settings.radius < 0)
    throw std::invalid_argument("guidedUpsample: the radius must not be negative, not " + std::to_string(settings.radius));
  if (!(settings.epsilon > 0.0f) || !std::isfinite(settings.epsilon))
    throw std::invalid_argument("guidedUpsample: epsilon must be positive and finite, not " +
                                std::to_string(settings.epsilon));
  checkPlanes(low, "low-resolution input");
  checkPlanes(guide, "guide");
  if (static_cast<long long>(low.width) * settings.factor != guide.width ||
      static_cast<long long>(low.height) * settings.factor != guide.height)
    throw std::invalid_argument("guidedUpsample: a " + sizeText(low.width, low.height) + " input upsampled by " +
                                std::to_string(settings.factor) + " needs a " +
                                sizeText(low.width * settings.factor, low.height * settings.factor) +
                                " guide, not " + sizeText(guide.width, guide.height));

  const bool band = isBand(settings);
  if (settings.firstRow < 0 || settings.firstRow % settings.factor != 0 ||
      (band && (settings.onlyFirst < settings.firstRow || settings.onlyEnd > settings.firstRow + guide.height ||
                settings.onlyFirst > settings.onlyEnd)))
    throw std::invalid_argument("guidedUpsample: rows " + std::to_string(settings.onlyFirst) + " to " +
                                std::to_string(settings.onlyEnd) + " are not within the planes' rows from " +
                                std::to_string(settings.firstRow) + " (a multiple of the factor)");

  GuidedUpsampleResult result;
  result.image = Planes(guide.width, guide.height, static_cast<int>(low.channels.size()));
  result.rerender.assign(guide.pixelCount(), 0.0f);
  result.deficit.assign(guide.pixelCount(), 0.0f);
  if (guide.pixelCount() == 0) return result;

  // The strips, by frame rows, that hold the rows to compute; in the planes' rows.
  const int from = band ? settings.onlyFirst : settings.firstRow;
  const int to = band ? settings.onlyEnd : settings.firstRow + guide.height;
  std::vector<std::pair<int, int>> stripRows;
  for (int s = from / kStripRows; s * kStripRows < to; ++s)
    stripRows.emplace_back(std::max(0, s * kStripRows - settings.firstRow),
                           std::min(guide.height, (s + 1) * kStripRows - settings.firstRow));
  const int strips = static_cast<int>(stripRows.size());
  if (strips == 0) return result;

  const Upsampler upsampler(low, guide, settings, result);
  int threads = settings.threads > 0 ? settings.threads : static_cast<int>(std::thread::hardware_concurrency());
  threads = std::clamp(threads, 1, strips);

  std::atomic<int> next{0};
  std::exception_ptr failure;
  std::mutex failureMutex;
  const auto work = [&] {
    try {
      Workspace workspace = upsampler.workspace();
      for (int s = next++; s < strips; s = next++)
        upsampler.strip(stripRows[static_cast<size_t>(s)].first, stripRows[static_cast<size_t>(s)].second, workspace);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(failureMutex);
      if (!failure) failure = std::current_exception();
      next = strips;
    }
  };
  std::vector<std::thread> workers;
  workers.reserve(static_cast<size_t>(threads - 1));
  for (int t = 1; t < threads; ++t) {
    try {
      workers.emplace_back(work);
    } catch (const std::system_error&) {
      break;  // fewer threads; the strips do not change, nor does the result
    }
  }
  work();
  for (std::thread& worker : workers) worker.join();
  if (failure) std::rethrow_exception(failure);

  for (const float flag : result.rerender) result.negativePixels += flag != 0.0f ? 1 : 0;
  return result;
}

}  // namespace pathfarm
