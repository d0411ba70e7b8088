#pragma once
// The bytes of a filter task's output chunk, however the task gave them (TaskOutput: the
// bytes, a file holding them, or a frame the worker writes to a file).
#include <fstream>
#include <sstream>
#include <string>

#include "image/exr_io.h"
#include "worker/filter_tasks.h"

namespace pathfarm::farm {

inline std::string outputBytes(const TaskOutput& output) {
  if (output.frame) return encodeExr(*output.frame, ExrCompression::Fast);
  if (!output.chunkFile) return output.chunk;
  std::ifstream file(output.chunkFile->path(), std::ios::binary);
  std::ostringstream bytes;
  bytes << file.rdbuf();
  return bytes.str();
}

}  // namespace pathfarm::farm
