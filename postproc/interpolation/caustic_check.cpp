#include "postproc/interpolation/caustic_check.h"

#include <stdexcept>
#include <string>

#include "postproc/interpolation/window_sums.h"

namespace pathfarm {

std::vector<uint8_t> movingCausticPixels(const FrameImage& frame, const CausticCheckSettings& settings) {
  const int width = frame.width(), height = frame.height();
  std::vector<uint8_t> flagged(frame.pixelCount(), 0);
  if (!frame.hasChannel("moving_caustic.Y")) return flagged;
  for (const char* c : {"R", "G", "B"})
    if (!frame.hasChannel(c)) throw std::invalid_argument(std::string("caustic check: the frame has no channel \"") + c + "\"");
  const std::vector<float>& caustic = frame.channel("moving_caustic.Y");
  const std::vector<float>& r = frame.channel("R");
  const std::vector<float>& g = frame.channel("G");
  const std::vector<float>& b = frame.channel("B");
  std::vector<double> light(frame.pixelCount()), focused(frame.pixelCount()), seen(frame.pixelCount());
  for (size_t p = 0; p < light.size(); ++p) {
    light[p] = 0.2126 * r[p] + 0.7152 * g[p] + 0.0722 * b[p];
    focused[p] = caustic[p];
    seen[p] = caustic[p] > 0.0f ? 1.0 : 0.0;
  }
  const WindowSums lightSums(light, width, height), focusedSums(focused, width, height), seenSums(seen, width, height);
  std::vector<uint8_t> spots(frame.pixelCount(), 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double share = focusedSums.around(x, y, settings.radius);
      if (share > 0 && share > settings.share * lightSums.around(x, y, settings.radius) &&
          seenSums.around(x, y, settings.radius) >= settings.minPixels)
        spots[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)] = 1;
    }
  std::vector<double> spotValues(spots.begin(), spots.end());
  const WindowSums near(spotValues, width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (near.around(x, y, settings.margin) > 0)
        flagged[static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)] = 1;
  return flagged;
}

}  // namespace pathfarm
