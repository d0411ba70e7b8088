// Writing a filter task's output frame to its chunk file (worker/filter_tasks.h).
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "image/exr_io.h"
#include "worker/chunk_channels.h"
#include "worker/filter_tasks.h"

namespace pathfarm::farm {

void writingOutput(const std::function<void()>& step) {
  try {
    step();
  } catch (const ExrError& e) {
    throw std::runtime_error(std::string("cannot write the task's output: ") + e.what());
  }
}

void writeOutputFrame(TaskOutput& output, const std::filesystem::path& file) {
  if (output.frame) {
    const bool intermediate = output.compression == ExrCompression::Fast;
    writingOutput([&] {
      writeExrInStrips(file, *output.frame, output.compression,
                       intermediate ? halfPrecisionChannels(*output.frame) : ChannelFilter{});
    });
    output.frame.reset();
    return;
  }
  std::optional<ExrStripWriter> writer;
  for (std::function<FrameImage()>& window : output.rowWindows) {
    const FrameImage rows = window();
    window = {};
    writingOutput([&] {
      if (!writer)
        writer.emplace(file, rows.width(), output.joinedHeight, rows.channelNames(), rows.attributes(),
                       output.compression, output.halfChannels);
      writer->write(rows);
    });
  }
  if (!writer) throw std::logic_error("a task output without a frame or windows to write");
  writingOutput([&] { writer->finish(); });
  output.rowWindows.clear();
}

}  // namespace pathfarm::farm
