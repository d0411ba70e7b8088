#include "postproc/metrics/contact_sheet.h"

#include <gtest/gtest.h>

#include "image/png_preview.h"

namespace pathfarm {
namespace {

FrameImage flat(int w, int h, float value) {
  FrameImage f(w, h);
  for (const char* c : {"R", "G", "B"}) f.addChannel(c) = std::vector<float>(static_cast<size_t>(w * h), value);
  return f;
}

TEST(ContactSheet, ErrorRampRunsFromBlackToWhiteOnALogScale) {
  EXPECT_EQ(errorRamp(0.0), (std::array<float, 3>{0, 0, 0}));
  EXPECT_EQ(errorRamp(1e-4), (std::array<float, 3>{0, 0, 0}));
  EXPECT_EQ(errorRamp(1.0), (std::array<float, 3>{1, 1, 1}));
  EXPECT_EQ(errorRamp(50.0), (std::array<float, 3>{1, 1, 1}));
  const auto middle = errorRamp(1e-2);  // halfway: red full, green half way, no blue
  EXPECT_FLOAT_EQ(middle[0], 1.0f);
  EXPECT_GT(middle[1], 0.0f);
  EXPECT_LT(middle[1], 1.0f);
  EXPECT_EQ(middle[2], 0.0f);
}

TEST(ContactSheet, PanelsShowTheFramesAndWhereTheyErr) {
  const FrameImage reference = flat(8, 6, 0.5f), baseline = flat(8, 6, 0.5f);
  FrameImage method = flat(8, 6, 0.5f);
  for (const char* c : {"R", "G", "B"}) method.channel(c)[2 * 8 + 3] = 5.0f;  // one bright wrong pixel
  ContactSheetSettings settings;
  settings.gap = 2;
  const FrameImage sheet = contactSheet({{&method, &baseline, &reference}, {&method, nullptr, &reference}}, settings);
  ASSERT_EQ(sheet.width(), 5 * 8 + 4 * 2);
  ASSERT_EQ(sheet.height(), 2 * 6 + 2);
  const auto at = [&](int x, int y) { return sheet.channel("G")[static_cast<size_t>(y * sheet.width() + x)]; };
  EXPECT_EQ(at(3, 2), 5.0f);         // the method's frame
  EXPECT_EQ(at(10 + 3, 2), 0.5f);    // pt's
  EXPECT_EQ(at(20 + 3, 2), 0.5f);    // the reference
  EXPECT_EQ(at(30 + 3, 2), 1.0f);    // the method's error map: white where it is wrong
  EXPECT_EQ(at(30 + 4, 2), 0.0f);    // and black where it is right
  EXPECT_EQ(at(40 + 3, 2), 0.0f);    // pt is right everywhere
  EXPECT_EQ(at(8, 2), 0.0f);         // a gap
  EXPECT_EQ(at(10 + 3, 8 + 2), 0.0f);  // the second row has no pt panel
  EXPECT_EQ(encodePngPreview(sheet).rfind("\x89PNG", 0), 0u);
}

TEST(ContactSheet, WideFramesAreDownsampledAndMismatchesRefused) {
  const FrameImage wide = flat(20, 4, 1.0f);
  ContactSheetSettings settings;
  settings.maxPanelWidth = 8;  // a factor of 3: panels of 6x1
  settings.gap = 0;
  const FrameImage sheet = contactSheet({{&wide, &wide, &wide}}, settings);
  EXPECT_EQ(sheet.width(), 5 * 6);
  EXPECT_EQ(sheet.height(), 1);
  const FrameImage other = flat(10, 4, 1.0f);
  EXPECT_THROW(contactSheet({{&wide, &other, &wide}}), std::invalid_argument);
  EXPECT_THROW(contactSheet({}), std::invalid_argument);
}

TEST(ContactSheet, ASheetBoundInPixelsShrinksItsPanelsUntilItFits) {
  const FrameImage frame = flat(320, 180, 0.5f);
  const std::vector<ContactSheetRow> rows(8, ContactSheetRow{&frame, &frame, &frame});
  ContactSheetSettings settings;
  settings.maxPixels = 500'000;
  const FrameImage sheet = contactSheet(rows, settings);
  EXPECT_LE(sheet.pixelCount(), settings.maxPixels);
  // The largest panels that fit: one step less downsampling would not.
  const int factor = 320 / ((sheet.width() - 4 * settings.gap) / 5);
  ASSERT_GT(factor, 1);
  const size_t larger = static_cast<size_t>(5 * (320 / (factor - 1)) + 4 * settings.gap) *
                        static_cast<size_t>(8 * (180 / (factor - 1)) + 7 * settings.gap);
  EXPECT_GT(larger, settings.maxPixels);
  EXPECT_EQ(contactSheet(rows).width(), 5 * 320 + 4 * settings.gap) << "unbounded: panels of the frame's size";
}

}  // namespace
}  // namespace pathfarm
