// libFuzzer target for the EXR readers of chunks: the decoder workers run on every chunk
// they fetch, and the strip-wise scan the scheduler's completion check runs on every
// output. Any bytes must decode (or scan) or be refused with an ExrError (which fails the
// attempt, naming the chunk); never crash, hang, leak or allocate without limit. OpenEXR
// itself is Debian's, uninstrumented: the sanitizers watch pathfarm's side and what
// OpenEXR writes into it. Built and run by bench/fuzz.sh (clang, ASan, UBSan).
#include <string>

#include "fuzz/fuzz_support.h"
#include "image/exr_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string bytes(pathfarm::fuzz::asText(data, size));
  try {
    const pathfarm::FrameImage frame = pathfarm::decodeExr(bytes, "fuzz chunk");
    (void)frame;
  } catch (const pathfarm::ExrError& e) {
    pathfarm::fuzz::noteRefusal(e);
  }
  try {
    const pathfarm::ExrScan scan = pathfarm::scanExr(bytes, "fuzz chunk", 3);
    (void)scan;
  } catch (const pathfarm::ExrError& e) {
    pathfarm::fuzz::noteRefusal(e);
  }
  return 0;
}
