#include "postproc/metrics/error_terms.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pathfarm {
namespace {

constexpr int kTile = 16;
constexpr int kTileBlock = 4;

// The mean of the 8 neighbours of pixel (x, y) inside the frame.
double neighbourMean(const std::vector<float>& values, int width, int height, int x, int y) {
  double sum = 0;
  int count = 0;
  for (int ny = std::max(0, y - 1); ny <= std::min(height - 1, y + 1); ++ny)
    for (int nx = std::max(0, x - 1); nx <= std::min(width - 1, x + 1); ++nx) {
      if (nx == x && ny == y) continue;
      sum += values[static_cast<size_t>(ny) * width + nx];
      ++count;
    }
  return count > 0 ? sum / count : values[static_cast<size_t>(y) * width + x];
}

struct Rect {
  int x0, y0, x1, y1;
};

// Per block of `block` pixels within `area`, the sum over channels c = 0..2 and the kept
// pixels p = (x, y) of term(c, p, x, y); channels outermost within a block, so that the
// sums come out in one fixed order.
template <class Term>
BlockedTerms blockedSums(Rect area, int width, int block, const std::vector<uint8_t>* kept, Term term) {
  BlockedTerms terms;
  for (int by = area.y0; by < area.y1; by += block)
    for (int bx = area.x0; bx < area.x1; bx += block) {
      double sum = 0, count = 0;
      for (int c = 0; c < 3; ++c)
        for (int y = by; y < std::min(area.y1, by + block); ++y)
          for (int x = bx; x < std::min(area.x1, bx + block); ++x) {
            const size_t p = static_cast<size_t>(y) * width + x;
            if (kept && !(*kept)[p]) continue;
            const double value = term(c, p, x, y);
            if (!std::isfinite(value)) continue;
            sum += value;
            count += 1;
          }
      if (count > 0) {
        terms.sums.push_back(sum);
        terms.counts.push_back(count);
      }
    }
  return terms;
}

struct BeautyChannel {
  const std::vector<float>& value;
  const std::vector<float>& variance;
};

std::vector<BeautyChannel> withVariance(const FrameImage& reference) {
  std::vector<BeautyChannel> channels;
  for (const char* channel : {"R", "G", "B"}) {
    const std::string varianceName = std::string("variance.") + channel;
    if (!reference.hasChannel(varianceName))
      throw std::invalid_argument("no \"" + varianceName + "\" channel to estimate the noise from");
    channels.push_back({reference.channel(channel), reference.channel(varianceName)});
  }
  return channels;
}

BlockedTerms errorTermsIn(Rect area, const FrameImage* image, const FrameImage& reference,
                          const std::vector<uint8_t>* kept, int block) {
  if (image) requireSameSize(*image, reference);
  const int w = reference.width(), h = reference.height();
  const std::vector<BeautyChannel> ref = withVariance(reference);
  std::vector<const std::vector<float>*> values;
  for (const char* channel : {"R", "G", "B"}) values.push_back(image ? &image->channel(channel) : nullptr);
  return blockedSums(area, w, block, kept, [&](int c, size_t p, int x, int y) {
    const double d = neighbourMean(ref[c].value, w, h, x, y);
    const double noise = ref[c].variance[p];
    if (!image) return noise / (d * d + 0.01);
    const double difference = double{(*values[c])[p]} - ref[c].value[p];
    return (difference * difference - noise) / (d * d + 0.01);
  });
}

}  // namespace

double BlockedTerms::mean() const {
  double sum = 0, count = 0;
  for (size_t b = 0; b < sums.size(); ++b) {
    sum += sums[b];
    count += counts[b];
  }
  return count > 0 ? sum / count : 0;
}

void BlockedTerms::append(const BlockedTerms& other) {
  sums.insert(sums.end(), other.sums.begin(), other.sums.end());
  counts.insert(counts.end(), other.counts.begin(), other.counts.end());
}

BlockedTerms averageOf(const std::vector<BlockedTerms>& measurements) {
  if (measurements.empty()) throw std::invalid_argument("an average of no measurement");
  BlockedTerms average = measurements.front();
  for (size_t m = 1; m < measurements.size(); ++m) {
    if (measurements[m].sums.size() != average.sums.size())
      throw std::invalid_argument("an average of terms over different blocks");
    for (size_t b = 0; b < average.sums.size(); ++b) {
      average.sums[b] += measurements[m].sums[b];
      average.counts[b] += measurements[m].counts[b];
    }
  }
  const auto n = static_cast<double>(measurements.size());
  for (size_t b = 0; b < average.sums.size(); ++b) {
    average.sums[b] /= n;
    average.counts[b] /= n;
  }
  return average;
}

BlockedTerms errorTerms(const FrameImage* image, const FrameImage& reference, const std::vector<uint8_t>* kept,
                        int block) {
  return errorTermsIn({0, 0, reference.width(), reference.height()}, image, reference, kept, block);
}

BlockedTerms temporalTerms(const FrameImage& before, const FrameImage& after, const FrameImage& referenceBefore,
                           const FrameImage& referenceAfter) {
  requireSameSize(before, after);
  requireSameSize(before, referenceBefore);
  requireSameSize(before, referenceAfter);
  const int w = before.width(), h = before.height();
  const std::vector<BeautyChannel> r0 = withVariance(referenceBefore), r1 = withVariance(referenceAfter);
  // The reference's change per channel, whose neighbours give the denominators.
  std::vector<std::vector<float>> change(3);
  for (int c = 0; c < 3; ++c) {
    change[c].resize(r0[c].value.size());
    for (size_t p = 0; p < change[c].size(); ++p) change[c][p] = r1[c].value[p] - r0[c].value[p];
  }
  const char* names[] = {"R", "G", "B"};
  return blockedSums({0, 0, w, h}, w, kErrorBlock, nullptr, [&](int c, size_t p, int x, int y) {
    const double d = neighbourMean(change[c], w, h, x, y);
    const double imageChange = double{after.channel(names[c])[p]} - before.channel(names[c])[p];
    const double difference = imageChange - change[c][p];
    const double noise = double{r0[c].variance[p]} + r1[c].variance[p];
    return (difference * difference - noise) / (d * d + 0.01);
  });
}

std::vector<BlockedTerms> tileTerms(const FrameImage& image, const FrameImage& reference,
                                    const std::vector<uint8_t>* kept) {
  std::vector<BlockedTerms> tiles;
  for (int y0 = 0; y0 < reference.height(); y0 += kTile)
    for (int x0 = 0; x0 < reference.width(); x0 += kTile) {
      const Rect tile{x0, y0, std::min(reference.width(), x0 + kTile), std::min(reference.height(), y0 + kTile)};
      BlockedTerms terms = errorTermsIn(tile, &image, reference, kept, kTileBlock);
      if (terms.sums.size() >= kMinTileBlocks) tiles.push_back(std::move(terms));
    }
  return tiles;
}

}  // namespace pathfarm
