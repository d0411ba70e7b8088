#pragma once
// Rows of a frame cut into bands of about equal height, top to bottom: as few as hold at
// most `maxRows` rows each (one more where a border moves up to an even row), of heights
// that differ by at most two rows, with borders on even rows so that a band of a frame at
// half resolution is whole rows. The farm's filter windows (contract/pipeline.h) and the
// flow's bands (postproc/interpolation/irradiance_flow.h) are cut this way, so that with
// windows of a band's rows each window holds one band.
#include <cstdint>
#include <utility>
#include <vector>

namespace pathfarm {

// [first, end) of each band; one band when maxRows is 0 or the frame is no taller.
inline std::vector<std::pair<int, int>> evenRowBands(int64_t height, int64_t maxRows) {
  const int64_t count = maxRows > 0 ? (height + maxRows - 1) / maxRows : 1;
  const int64_t pairs = (height + 1) / 2;
  const auto border = [&](int64_t i) { return static_cast<int>(i == count ? height : 2 * (i * pairs / count)); };
  std::vector<std::pair<int, int>> bands;
  for (int64_t i = 0; i < count; ++i) bands.emplace_back(border(i), border(i + 1));
  return bands;
}

}  // namespace pathfarm
