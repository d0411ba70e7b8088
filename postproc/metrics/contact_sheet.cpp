#include "postproc/metrics/contact_sheet.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "postproc/metrics/relmse.h"

namespace pathfarm {
namespace {

constexpr int kPanels = 5;

float srgbToLinear(float v) { return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f); }

// One panel: value(c, x, y) for the panel's pixel (x, y) at full resolution, box-averaged
// over factor x factor pixels, written at (left, top) of the sheet.
template <class Value>
void drawPanel(FrameImage& sheet, int left, int top, int width, int height, int factor, Value value) {
  const float area = static_cast<float>(factor * factor);
  for (int c = 0; c < 3; ++c) {
    std::vector<float>& out = sheet.channel(kRgbChannels[c]);
    for (int y = 0; y < height / factor; ++y)
      for (int x = 0; x < width / factor; ++x) {
        float sum = 0;
        for (int dy = 0; dy < factor; ++dy)
          for (int dx = 0; dx < factor; ++dx) sum += value(c, x * factor + dx, y * factor + dy);
        out[static_cast<size_t>(top + y) * static_cast<size_t>(sheet.width()) + static_cast<size_t>(left + x)] =
            sum / area;
      }
  }
}

}  // namespace

std::array<float, 3> errorRamp(double relativeSquaredError) {
  // 0 at 1e-4, 1 at 1: black -> red -> yellow -> white in equal thirds.
  const double t = std::clamp((std::log10(std::max(relativeSquaredError, 1e-12)) + 4.0) / 4.0, 0.0, 1.0);
  const auto ramp = [&](double from) { return static_cast<float>(std::clamp((t - from) * 3.0, 0.0, 1.0)); };
  return {srgbToLinear(ramp(0.0)), srgbToLinear(ramp(1.0 / 3)), srgbToLinear(ramp(2.0 / 3))};
}

FrameImage contactSheet(const std::vector<ContactSheetRow>& rows, const ContactSheetSettings& settings) {
  if (rows.empty()) throw std::invalid_argument("contact sheet: no rows");
  const int width = rows.front().method->width(), height = rows.front().method->height();
  for (const ContactSheetRow& row : rows)
    for (const FrameImage* frame : {row.method, row.baseline, row.reference}) {
      if (frame == row.baseline && frame == nullptr) continue;
      if (frame == nullptr || frame->width() != width || frame->height() != height)
        throw std::invalid_argument("contact sheet: every frame must exist and be " + std::to_string(width) + "x" +
                                    std::to_string(height));
      for (const char* c : kRgbChannels) channelOf(*frame, c, "contact sheet: a frame");
    }
  const int rowCount = static_cast<int>(rows.size());
  int factor = std::max(1, (width + settings.maxPanelWidth - 1) / settings.maxPanelWidth);
  const auto sheetPixels = [&](int f) {
    return static_cast<size_t>(kPanels * (width / f) + (kPanels - 1) * settings.gap) *
           static_cast<size_t>(rowCount * (height / f) + (rowCount - 1) * settings.gap);
  };
  while (settings.maxPixels > 0 && sheetPixels(factor) > settings.maxPixels && width / factor > 1 && height / factor > 1)
    ++factor;
  const int panelWidth = width / factor, panelHeight = height / factor;
  FrameImage sheet(kPanels * panelWidth + (kPanels - 1) * settings.gap,
                   rowCount * panelHeight + (rowCount - 1) * settings.gap);
  for (const char* c : kRgbChannels) sheet.addChannel(c);

  for (int r = 0; r < rowCount; ++r) {
    const ContactSheetRow& row = rows[static_cast<size_t>(r)];
    const int top = r * (panelHeight + settings.gap);
    const auto left = [&](int panel) { return panel * (panelWidth + settings.gap); };
    const auto at = [&](int x, int y) { return static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x); };
    const auto image = [&](const FrameImage& frame) {
      return [&frame, &at](int c, int x, int y) {
        const float v = frame.channel(kRgbChannels[c])[at(x, y)];
        return std::isfinite(v) ? v : 0.0f;
      };
    };
    const auto error = [&](const FrameImage& frame) {
      return [&frame, &row, &at](int c, int x, int y) {
        double sum = 0;
        for (const char* channel : kRgbChannels) {
          const double v = frame.channel(channel)[at(x, y)];
          sum += std::isfinite(v) ? relativeSquaredError(v, row.reference->channel(channel)[at(x, y)]) : 1.0;
        }
        return errorRamp(sum / 3)[static_cast<size_t>(c)];
      };
    };
    drawPanel(sheet, left(0), top, width, height, factor, image(*row.method));
    if (row.baseline) drawPanel(sheet, left(1), top, width, height, factor, image(*row.baseline));
    drawPanel(sheet, left(2), top, width, height, factor, image(*row.reference));
    drawPanel(sheet, left(3), top, width, height, factor, error(*row.method));
    if (row.baseline) drawPanel(sheet, left(4), top, width, height, factor, error(*row.baseline));
  }
  return sheet;
}

}  // namespace pathfarm
