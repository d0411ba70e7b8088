#include "image/plane_memory.h"

#include <cstdlib>  // defines __GLIBC__ on glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace pathfarm {

bool keepFreedPlanesForReuse() {
#if defined(__GLIBC__)
  constexpr int kMmapThreshold = 64 << 20;
  constexpr int kTrimThreshold = 512 << 20;
  // mallopt returns 1 on success.
  return mallopt(M_MMAP_THRESHOLD, kMmapThreshold) == 1 && mallopt(M_TRIM_THRESHOLD, kTrimThreshold) == 1;
#else
  return false;
#endif
}

}  // namespace pathfarm
