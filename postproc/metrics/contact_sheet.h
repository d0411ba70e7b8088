#pragma once
// A contact sheet for people to look at: per evaluation frame one row of panels, the
// method's frame, plain pt's, the reference, and the per-pixel relative error of each of
// the first two against the reference. A ghost or a misplaced highlight shows in the
// error maps even where the frame's mean relMSE is low.
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "image/frame_image.h"

namespace pathfarm {

struct ContactSheetRow {
  const FrameImage* method = nullptr;    // the pipeline's final frame
  const FrameImage* baseline = nullptr;  // plain pt at the same spp (may be null: panel left black)
  const FrameImage* reference = nullptr;
};

struct ContactSheetSettings {
  int maxPanelWidth = 640;  // wider frames are box-downsampled by an integer factor
  int gap = 4;              // pixels between panels and rows
  size_t maxPixels = 0;     // > 0: the panels downsampled further until the sheet has no more
};

// The error maps show relMSE per pixel (mean over R, G, B of (x - r)^2 / (r^2 + 0.01)) on a
// logarithmic ramp: black at 1e-4 and below, through red and yellow, white at 1 and above.
std::array<float, 3> errorRamp(double relativeSquaredError);

// The sheet's beauty R, G, B (linear: the ramp's colors are sRGB-decoded so a PNG preview
// shows them as designed). Throws std::invalid_argument for rows of different sizes or
// frames without R, G, B.
FrameImage contactSheet(const std::vector<ContactSheetRow>& rows, const ContactSheetSettings& settings = {});

}  // namespace pathfarm
