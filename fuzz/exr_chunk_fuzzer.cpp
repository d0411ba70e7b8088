// libFuzzer target for the EXR readers of chunks: the decoder workers run on every chunk
// they fetch, the strip-wise scan the scheduler's completion check runs, in place, on
// every output file, and the header and row reads of an assembly's tiles. Any bytes must decode (or scan) or be refused with an ExrError (which
// fails the attempt, naming the chunk); never crash, hang, leak or allocate without limit.
// OpenEXR itself is Debian's, uninstrumented: the sanitizers watch pathfarm's side and what
// OpenEXR writes into it. Built and run by bench/fuzz.sh (clang, ASan, UBSan).
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <string>

#include "fuzz/fuzz_support.h"
#include "image/exr_io.h"

namespace {

// The file the scan reads each input from, one per fuzzing process, removed as it exits.
struct ScanFile {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("pathfarm_exr_fuzz_" + std::to_string(::getpid()) + ".exr");
  ~ScanFile() {
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
  }
};

const std::filesystem::path& scanFile() {
  static const ScanFile file;
  return file.path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(pathfarm::fuzz::asText(data, size));
  try {
    const pathfarm::FrameImage frame = pathfarm::decodeExr(bytes, "fuzz chunk");
    (void)frame;
  } catch (const pathfarm::ExrError& e) {
    pathfarm::fuzz::noteRefusal(e);
  }
  std::ofstream(scanFile(), std::ios::binary | std::ios::trunc) << bytes;
  try {
    const pathfarm::ExrScan scan = pathfarm::scanExrFile(scanFile(), "fuzz chunk", 3);
    (void)scan;
  } catch (const pathfarm::ExrError& e) {
    pathfarm::fuzz::noteRefusal(e);
  }
  // An assembly's reads of a tile in place: its header, then a strip of its rows.
  try {
    const pathfarm::ExrHeader header = pathfarm::readExrHeader(scanFile(), "fuzz chunk");
    const pathfarm::FrameImage rows =
        pathfarm::readExrRows(scanFile(), "fuzz chunk", header.height / 2, std::min(header.height, header.height / 2 + 3));
    (void)rows;
  } catch (const pathfarm::ExrError& e) {
    pathfarm::fuzz::noteRefusal(e);
  }
  return 0;
}
