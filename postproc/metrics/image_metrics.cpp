#include "postproc/metrics/image_metrics.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include "postproc/metrics/relmse.h"

namespace pathfarm {
namespace {

struct Sums {
  double rel = 0, squared = 0, smape = 0, imageSum = 0, referenceSum = 0;
  size_t compared = 0, skippedReference = 0, nonFinite = 0;

  // Adds one value; returns its relative squared error (0 for a value that was skipped).
  double add(double x, double r) {
    if (!std::isfinite(r)) {
      ++skippedReference;
      return 0;
    }
    if (!std::isfinite(x)) {
      ++nonFinite;
      return 0;
    }
    const double term = relativeSquaredError(x, r);
    rel += term;
    squared += (x - r) * (x - r);
    smape += 2 * std::abs(x - r) / (std::abs(x) + std::abs(r) + 0.01);
    imageSum += x;
    referenceSum += r;
    ++compared;
    return term;
  }

  ImageMetrics metrics() const {
    ImageMetrics m;
    const double n = compared > 0 ? static_cast<double>(compared) : 1;
    m.relMse = rel / n;
    m.mse = squared / n;
    m.psnr = m.mse > 0 ? 10 * std::log10(1 / m.mse) : INFINITY;
    m.smape = smape / n;
    m.brightness = referenceSum != 0 ? imageSum / referenceSum : (imageSum == 0 ? 1 : INFINITY);
    m.compared = compared;
    m.skippedReference = skippedReference;
    m.nonFinite = nonFinite;
    return m;
  }
};

Crop checkedCrop(const FrameImage& image, const std::optional<Crop>& crop) {
  const Crop c = crop.value_or(Crop{0, 0, image.width(), image.height()});
  if (c.x0 < 0 || c.y0 < 0 || c.x1 > image.width() || c.y1 > image.height() || c.x0 >= c.x1 || c.y0 >= c.y1)
    throw std::invalid_argument("the crop lies outside the " + std::to_string(image.width()) + "x" +
                                std::to_string(image.height()) + " frame or is empty");
  return c;
}

// Calls visit(p) for every pixel index p inside the crop.
template <class Visit>
void forEachPixel(const Crop& crop, int width, Visit visit) {
  for (int y = crop.y0; y < crop.y1; ++y)
    for (int x = crop.x0; x < crop.x1; ++x) visit(static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x));
}

constexpr int kArtifactTile = 16;

// Per pixel of the crop: the sum of its values' relative squared errors and how many
// values entered it.
struct PixelErrors {
  std::vector<double> error;
  std::vector<int> values;
};

void addArtifactMeasures(const PixelErrors& pixels, const Crop& crop, int width, ImageMetrics& m) {
  // Worst tile, on the frame's tile grid clipped to the crop.
  for (int ty = crop.y0 / kArtifactTile * kArtifactTile; ty < crop.y1; ty += kArtifactTile)
    for (int tx = crop.x0 / kArtifactTile * kArtifactTile; tx < crop.x1; tx += kArtifactTile) {
      double sum = 0;
      size_t count = 0;
      for (int y = std::max(ty, crop.y0); y < std::min(ty + kArtifactTile, crop.y1); ++y)
        for (int x = std::max(tx, crop.x0); x < std::min(tx + kArtifactTile, crop.x1); ++x) {
          const size_t p = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
          sum += pixels.error[p];
          count += static_cast<size_t>(pixels.values[p]);
        }
      if (count > 0) m.worstTileRelMse = std::max(m.worstTileRelMse, sum / static_cast<double>(count));
    }
  // Share of the error in the worst 1 % of the compared pixels.
  std::vector<double> errors;
  double total = 0;
  for (int y = crop.y0; y < crop.y1; ++y)
    for (int x = crop.x0; x < crop.x1; ++x) {
      const size_t p = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
      if (pixels.values[p] == 0) continue;
      errors.push_back(pixels.error[p]);
      total += pixels.error[p];
    }
  if (errors.empty()) return;
  const size_t worst = std::max<size_t>(1, errors.size() / 100);
  std::nth_element(errors.begin(), errors.begin() + static_cast<std::ptrdiff_t>(worst - 1), errors.end(),
                   std::greater<>());
  double inWorst = 0;
  for (size_t i = 0; i < worst; ++i) inWorst += errors[i];
  m.worstPercentShare = total > 0 ? inWorst / total : 0;
}

}  // namespace

std::vector<std::string> layerChannels(const FrameImage& frame, const std::string& layer) {
  std::vector<std::string> names;
  if (layer.empty()) {
    names = {"R", "G", "B"};
  } else {
    const std::string prefix = layer + ".";
    for (const std::string& name : frame.channelNames())
      if (name.compare(0, prefix.size(), prefix) == 0) names.push_back(name);
  }
  for (const std::string& name : names) channelOf(frame, name, "the frame");
  if (names.empty()) throw std::invalid_argument("the frame has no layer \"" + layer + "\"");
  return names;
}

ImageMetrics compareImages(const FrameImage& image, const FrameImage& reference,
                           const std::vector<std::string>& channels, const std::optional<Crop>& crop,
                           const std::vector<uint8_t>* only) {
  requireSameSize(image, reference);
  const Crop c = checkedCrop(image, crop);
  if (only && only->size() != image.pixelCount())
    throw std::invalid_argument("the pixel mask has " + std::to_string(only->size()) + " entries for " +
                                std::to_string(image.pixelCount()) + " pixels");
  Sums sums;
  PixelErrors pixels{std::vector<double>(image.pixelCount(), 0.0), std::vector<int>(image.pixelCount(), 0)};
  for (const std::string& name : channels) {
    const auto& x = channelOf(image, name, "the image");
    const auto& r = channelOf(reference, name, "the reference");
    forEachPixel(c, image.width(), [&](size_t p) {
      if (only && !(*only)[p]) return;
      const size_t before = sums.compared;
      pixels.error[p] += sums.add(x[p], r[p]);
      pixels.values[p] += static_cast<int>(sums.compared - before);
    });
  }
  ImageMetrics m = sums.metrics();
  addArtifactMeasures(pixels, c, image.width(), m);
  return m;
}

SequenceMetrics compareSequences(const std::vector<FrameImage>& images, const std::vector<FrameImage>& references,
                                 const std::vector<std::string>& channels, const std::optional<Crop>& crop) {
  if (images.size() != references.size() || images.empty())
    throw std::invalid_argument("the sequences must have the same, non-zero number of frames (" +
                                std::to_string(images.size()) + " against " + std::to_string(references.size()) + ")");
  SequenceMetrics result;
  Sums temporal;
  for (size_t i = 0; i < images.size(); ++i) {
    result.frames.push_back(compareImages(images[i], references[i], channels, crop));
    result.meanRelMse += result.frames.back().relMse / static_cast<double>(images.size());
    if (i == 0) continue;
    requireSameSize(images[i], images[i - 1]);
    const Crop c = checkedCrop(images[i], crop);
    for (const std::string& name : channels) {
      const auto& x = channelOf(images[i], name, "the image");
      const auto& xBefore = channelOf(images[i - 1], name, "the image");
      const auto& r = channelOf(references[i], name, "the reference");
      const auto& rBefore = channelOf(references[i - 1], name, "the reference");
      forEachPixel(c, images[i].width(), [&](size_t p) {
        temporal.add(static_cast<double>(x[p]) - xBefore[p], static_cast<double>(r[p]) - rBefore[p]);
      });
    }
  }
  result.temporalRelMse = images.size() > 1 ? temporal.metrics().relMse : 0;
  return result;
}

}  // namespace pathfarm
