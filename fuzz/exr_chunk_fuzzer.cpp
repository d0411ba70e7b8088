// libFuzzer target for the EXR decoder workers run on every chunk they fetch: any bytes
// must decode into a frame or be refused with an ExrError (which fails the attempt, naming
// the chunk); never crash, hang, leak or allocate without limit. OpenEXR itself is
// Debian's, uninstrumented: the sanitizers watch pathfarm's side and what OpenEXR writes
// into it. Built and run by bench/fuzz.sh (clang, ASan, UBSan).
#include <string>

#include "fuzz/fuzz_support.h"
#include "image/exr_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const pathfarm::FrameImage frame =
        pathfarm::decodeExr(std::string(pathfarm::fuzz::asText(data, size)), "fuzz chunk");
    (void)frame;
  } catch (const pathfarm::ExrError& e) {
    pathfarm::fuzz::noteRefusal(e);
  }
  return 0;
}
