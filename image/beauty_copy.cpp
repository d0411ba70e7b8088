#include "image/beauty_copy.h"

#include <algorithm>

#include "image/exr_io.h"

namespace pathfarm {

void writeBeautyCopy(const std::filesystem::path& frame, const std::filesystem::path& copy) {
  constexpr int kRowsPerStrip = 64;
  const std::vector<std::string> beauty = {"R", "G", "B"};
  const ExrHeader header = readExrHeader(frame, frame.string());
  ExrStripWriter writer(copy, header.width, header.height, beauty, header.attributes, ExrCompression::Small);
  readExrStrips(frame, frame.string(), beauty, kRowsPerStrip, [&](const ExrStrip& strip) {
    FrameImage rows(strip.width, strip.rows);
    for (size_t c = 0; c < strip.names.size(); ++c)
      std::copy_n(strip.planes[c], rows.pixelCount(), rows.addChannel(strip.names[c]).begin());
    writer.write(rows);
    return true;
  });
  writer.finish();
}

}  // namespace pathfarm
