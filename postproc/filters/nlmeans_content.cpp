// jointNlMeans on the bounding box of what the frames hold (nlmeans.h).
#include <algorithm>
#include <cmath>

#include "postproc/filters/nlmeans.h"

namespace pathfarm {
namespace {

struct Box {
  int x0, y0, x1, y1;  // [x0, x1) x [y0, y1); empty when x0 >= x1
  int width() const { return x1 - x0; }
  int height() const { return y1 - y0; }
};

bool holdsSomething(const Planes& planes, size_t p) {
  for (const std::vector<float>& channel : planes.channels)
    if (!(channel[p] == 0.0f)) return true;  // NaN too
  return false;
}

// Every plane of every frame has the first color plane's size (else jointNlMeans says what is wrong).
bool allOneSize(const NlMeansInput& input) {
  const Planes& center = input.frames[0].color;
  const auto fits = [&](const Planes& planes) {
    if (planes.channels.empty()) return true;
    if (planes.width != center.width || planes.height != center.height) return false;
    return std::all_of(planes.channels.begin(), planes.channels.end(),
                       [&](const std::vector<float>& c) { return c.size() == center.pixelCount(); });
  };
  for (const NlMeansFrame& frame : input.frames) {
    if (!fits(frame.color) || !fits(frame.variance)) return false;
    if (!std::all_of(frame.features.begin(), frame.features.end(), fits)) return false;
    if (!std::all_of(frame.featureVariance.begin(), frame.featureVariance.end(), fits)) return false;
    if (!frame.valid.empty() && frame.valid.size() != center.pixelCount()) return false;
  }
  return true;
}

Box contentBox(const NlMeansInput& input, int margin) {
  const int width = input.frames[0].color.width, height = input.frames[0].color.height;
  Box box{width, height, 0, 0};
  for (size_t f = 0; f < input.frames.size(); ++f) {
    const NlMeansFrame& frame = input.frames[f];
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const size_t p = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
        const bool invalidCenter = f == 0 && !frame.valid.empty() && !(frame.valid[p] > 0.0f);
        if (!invalidCenter && !holdsSomething(frame.color, p) && !holdsSomething(frame.variance, p)) continue;
        box = {std::min(box.x0, x), std::min(box.y0, y), std::max(box.x1, x + 1), std::max(box.y1, y + 1)};
      }
  }
  if (box.x0 >= box.x1) return box;
  return {std::max(0, box.x0 - margin), std::max(0, box.y0 - margin), std::min(width, box.x1 + margin),
          std::min(height, box.y1 + margin)};
}

std::vector<float> cropPlane(const std::vector<float>& plane, int width, const Box& box) {
  std::vector<float> out(static_cast<size_t>(box.width()) * static_cast<size_t>(box.height()));
  for (int y = box.y0; y < box.y1; ++y)
    std::copy_n(plane.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(y) * width + box.x0), box.width(),
                out.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(y - box.y0) * box.width()));
  return out;
}

Planes cropPlanes(const Planes& planes, const Box& box) {
  Planes out;
  out.width = planes.channels.empty() ? 0 : box.width();
  out.height = planes.channels.empty() ? 0 : box.height();
  for (const std::vector<float>& channel : planes.channels) out.channels.push_back(cropPlane(channel, planes.width, box));
  return out;
}

}  // namespace

Planes jointNlMeansOnContent(const NlMeansInput& input, const NlMeansSettings& settings, NlMeansStats* stats,
                             const NlMeansArea* wanted) {
  if (input.frames.empty() || !allOneSize(input)) return jointNlMeans(input, settings, stats);  // its error
  const Planes& center = input.frames[0].color;
  const int margin = 2 * (settings.radius + settings.patch);
  Box box = contentBox(input, margin);
  // A wanted pixel's value depends on its partners within the radius and on their patches
  // (and on the features' 1-pixel gradient at the pixel itself): radius + patch around it.
  const int reach = std::max(1, settings.radius + settings.patch);
  if (wanted != nullptr)
    box = {std::max(box.x0, wanted->x0 - reach), std::max(box.y0, wanted->y0 - reach),
           std::min(box.x1, wanted->x1 + reach), std::min(box.y1, wanted->y1 + reach)};
  if (box.x0 >= box.x1 || box.y0 >= box.y1) box = {0, 0, 0, 0};
  const auto area = [](int w, int h) { return static_cast<double>(w) * h; };
  // Most of the frame holds something: cropping would save little.
  if (area(box.width(), box.height()) > 0.8 * area(center.width, center.height))
    return jointNlMeans(input, settings, stats);

  Planes out(center.width, center.height, static_cast<int>(center.channels.size()));
  if (stats) *stats = NlMeansStats{0, 0, std::vector<uint8_t>(center.pixelCount(), 0)};
  if (box.x0 >= box.x1) return out;  // nothing anywhere: zero, as filtering it would give

  NlMeansInput cropped;
  cropped.featureKinds = input.featureKinds;
  for (const NlMeansFrame& frame : input.frames) {
    NlMeansFrame& part = cropped.frames.emplace_back();
    part.color = cropPlanes(frame.color, box);
    part.variance = cropPlanes(frame.variance, box);
    for (const Planes& feature : frame.features) part.features.push_back(cropPlanes(feature, box));
    for (const Planes& variance : frame.featureVariance) part.featureVariance.push_back(cropPlanes(variance, box));
    if (!frame.valid.empty()) part.valid = cropPlane(frame.valid, center.width, box);
  }
  NlMeansStats croppedStats;
  const Planes filtered = jointNlMeans(cropped, settings, &croppedStats);
  for (size_t c = 0; c < out.channels.size(); ++c)
    for (int y = box.y0; y < box.y1; ++y)
      std::copy_n(filtered.channels[c].begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(y - box.y0) * box.width()),
                  box.width(),
                  out.channels[c].begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(y) * center.width + box.x0));
  if (stats) {
    stats->invalidCenters = croppedStats.invalidCenters;
    stats->unfilledCenters = croppedStats.unfilledCenters;
    for (int y = box.y0; y < box.y1; ++y)
      for (int x = box.x0; x < box.x1; ++x)
        stats->invalidCenter[static_cast<size_t>(y) * center.width + x] =
            croppedStats.invalidCenter[static_cast<size_t>(y - box.y0) * box.width() + (x - box.x0)];
  }
  return out;
}

}  // namespace pathfarm
