#pragma once
// The bytes of a filter task's output chunk, however the task gave them (TaskOutput: the
// bytes, a file holding them, or a frame or windows of rows the worker writes to a file,
// written here as the worker writes them); a frame as an intermediate chunk holds it; and a
// filter task's lease for a window of rows.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "contract/pipeline.h"
#include "image/exr_io.h"
#include "worker/chunk_channels.h"
#include "worker/filter_tasks.h"

namespace pathfarm::farm {

inline std::string outputBytes(TaskOutput output) {
  if (output.frame || !output.rowWindows.empty()) {
    output.chunkFile = std::make_shared<const ScratchFile>(
        std::filesystem::temp_directory_path() / ("pathfarm-output-" + std::to_string(::getpid()) + ".exr"));
    writeOutputFrame(output, output.chunkFile->path());
  }
  if (!output.chunkFile) return output.chunk;
  std::ifstream file(output.chunkFile->path(), std::ios::binary);
  std::ostringstream bytes;
  bytes << file.rdbuf();
  return bytes.str();
}

// `frame` as an intermediate chunk holds it: what halfPrecisionChannels allows rounded to
// the nearest half float (image/exr_io.h), the rest as it is.
inline FrameImage asIntermediateChunk(const FrameImage& frame) {
  return decodeExr(encodeExr(frame, ExrCompression::Fast, halfPrecisionChannels(frame)), "an intermediate chunk");
}

// `lease` (of no window, with no inputs) for rows [first, end) of its frame, whole rows.
inline Lease windowOf(Lease lease, const RowWindow& rows) {
  PixelWindow& window = *lease.mutable_params()->mutable_window();
  window.set_x0(0);
  window.set_x1(lease.spec().width());
  window.set_y0(rows.first);
  window.set_y1(rows.end);
  return lease;
}

}  // namespace pathfarm::farm
