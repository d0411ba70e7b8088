#include "image/plane_memory.h"

#include <cstdlib>  // defines __GLIBC__ on glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace pathfarm {

namespace {

constexpr int kTrimThreshold = 512 << 20;

}  // namespace

bool keepFreedPlanesForReuse() {
#if defined(__GLIBC__)
  constexpr int kMmapThreshold = 64 << 20;
  // mallopt returns 1 on success.
  return mallopt(M_MMAP_THRESHOLD, kMmapThreshold) == 1 && mallopt(M_TRIM_THRESHOLD, kTrimThreshold) == 1;
#else
  return false;
#endif
}

void returnFreedBeyondReuse() {
#if defined(__GLIBC__)
  if (mallinfo2().fordblks > static_cast<size_t>(kTrimThreshold)) malloc_trim(0);
#endif
}

}  // namespace pathfarm
