#pragma once
// The bytes of a filter task's output chunk, however the task gave them (TaskOutput: the
// bytes, a file holding them, or a frame or windows of rows the worker writes to a file,
// written here as the worker writes them).
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "image/exr_io.h"
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

}  // namespace pathfarm::farm
