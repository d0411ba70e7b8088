#include "renderer/sampling/sample_stream.h"

namespace pathfarm {
namespace {

// SplitMix64 finalizer: a strong 64-bit mix so neighbouring keys give unrelated streams.
uint64_t mix(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace

SampleStream::SampleStream(const SampleKey& key) {
  uint64_t h = mix(key.sceneSeed + 0x9e3779b97f4a7c15ULL);
  h = mix(h ^ static_cast<uint64_t>(key.frame));
  h = mix(h ^ (static_cast<uint64_t>(static_cast<uint32_t>(key.x)) << 32 |
               static_cast<uint32_t>(key.y)));
  h = mix(h ^ key.sampleIndex);
  increment_ = (mix(h ^ 0xda942042e4dd58b5ULL) << 1u) | 1u;
  state_ = 0;
  nextUint();
  state_ += h;
  nextUint();
}

}  // namespace pathfarm
