#include "renderer/sampling/sample_stream.h"

#include <array>
#include <cstddef>

namespace pathfarm {
namespace {

// SplitMix64 finalizer: a strong 64-bit mix so neighbouring keys give unrelated streams.
uint64_t mix(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// The direction numbers of the dimension with primitive polynomial degree `degree`,
// coefficients `a` and initial numbers `m` (Joe and Kuo's table): the first `degree` are
// m_j scaled to the top bits, and the rest follow the polynomial's recurrence.
constexpr std::array<uint32_t, 32> sobolDirections(int degree, uint32_t a, std::array<uint32_t, 2> m) {
  std::array<uint32_t, 32> v{};
  for (int j = 0; j < degree; ++j) v[static_cast<size_t>(j)] = m[static_cast<size_t>(j)] << (31 - j);
  for (int j = degree; j < 32; ++j) {
    uint32_t next = v[static_cast<size_t>(j - degree)] ^ (v[static_cast<size_t>(j - degree)] >> degree);
    for (int k = 1; k < degree; ++k)
      if (((a >> (degree - 1 - k)) & 1u) != 0) next ^= v[static_cast<size_t>(j - k)];
    v[static_cast<size_t>(j)] = next;
  }
  return v;
}

constexpr std::array<uint32_t, 32> kVanDerCorputDirections = [] {
  std::array<uint32_t, 32> v{};
  for (size_t j = 0; j < 32; ++j) v[j] = 1u << (31 - j);
  return v;
}();

// Sobol's sequence in one dimension: bit j of the index flips the dimension's direction
// number v_j. The flips are tabled a byte of the index at a time (entry b of table t: the
// XOR of v_{8t + j} over the set bits j of b), so a point costs three lookups instead of a
// loop over the index's bits with a branch each; the points are the same bits. Indices
// below 2^kStratifiedBlockBits have three bytes.
class SobolDimension {
 public:
  constexpr explicit SobolDimension(const std::array<uint32_t, 32>& directions) : bytes_{} {
    for (size_t t = 0; t < kBytes; ++t)
      for (uint32_t b = 0; b < 256; ++b)
        for (size_t j = 0; j < 8; ++j)
          if (((b >> j) & 1u) != 0) bytes_[t][b] ^= directions[8 * t + j];
  }
  uint32_t operator()(uint32_t index) const {
    return bytes_[0][index & 0xffu] ^ bytes_[1][(index >> 8) & 0xffu] ^ bytes_[2][(index >> 16) & 0xffu];
  }

 private:
  static constexpr size_t kBytes = kStratifiedBlockBits / 8;
  std::array<std::array<uint32_t, 256>, kBytes> bytes_;
};
static_assert(kStratifiedBlockBits == 24, "SobolDimension tables three bytes of an index");

constexpr SobolDimension kVanDerCorput(kVanDerCorputDirections);
constexpr SobolDimension kSobolSecond(sobolDirections(1, 0, {1, 0}));  // x + 1
constexpr SobolDimension kSobolThird(sobolDirections(2, 1, {1, 3}));   // x^2 + x + 1

// The time dimension's scramble of a block whose position scramble is `h`.
uint64_t timeScrambleOf(uint64_t h) { return mix(h ^ 0xbb67ae8584caa73bULL); }

// 24 high bits, as SampleStream::next1D: exactly representable, strictly below 1.
float unitFloat(uint32_t bits) { return static_cast<float>(bits >> 8) * 0x1p-24f; }

}  // namespace

StratifiedPixel::StratifiedPixel(uint64_t sceneSeed, int64_t frame, int32_t x, int32_t y) {
  uint64_t h = mix(sceneSeed ^ 0x6a09e667f3bcc909ULL);
  h = mix(h ^ static_cast<uint64_t>(frame));
  pixelHash_ = mix(h ^ (static_cast<uint64_t>(static_cast<uint32_t>(x)) << 32 | static_cast<uint32_t>(y)));
  timeScramble_ = timeScrambleOf(pixelHash_);
}

StratifiedSample StratifiedPixel::sample(uint32_t sampleIndex) const {
  // Each block of 2^24 sample indices is a sequence of its own, scrambled apart: the
  // high bits of an index would only flip the points' lowest digits, so a render drawing
  // from another block (a reference's kIndependentFirstSample) would reuse the positions.
  const uint32_t block = sampleIndex >> kStratifiedBlockBits;
  const uint32_t i = sampleIndex & ((1u << kStratifiedBlockBits) - 1);
  // The first block keeps the pixel's own scramble.
  const uint64_t h = block != 0 ? mix(pixelHash_ ^ block) : pixelHash_;
  const uint64_t timeScramble = block != 0 ? timeScrambleOf(h) : timeScramble_;
  return {{unitFloat(kVanDerCorput(i) ^ static_cast<uint32_t>(h)), unitFloat(kSobolSecond(i) ^ static_cast<uint32_t>(h >> 32))},
          unitFloat(kSobolThird(i) ^ static_cast<uint32_t>(timeScramble))};
}

PixelStreams::PixelStreams(uint64_t sceneSeed, int64_t frame, int32_t x, int32_t y) {
  const uint64_t h = mix(mix(sceneSeed + 0x9e3779b97f4a7c15ULL) ^ static_cast<uint64_t>(frame));
  pixelHash_ = mix(h ^ (static_cast<uint64_t>(static_cast<uint32_t>(x)) << 32 | static_cast<uint32_t>(y)));
}

SampleStream::SampleStream(const SampleKey& key)
    : SampleStream(PixelStreams(key.sceneSeed, key.frame, key.x, key.y).stream(key.sampleIndex)) {}

SampleStream::SampleStream(uint64_t pixelHash, uint32_t sampleIndex) {
  const uint64_t h = mix(pixelHash ^ sampleIndex);
  increment_ = (mix(h ^ 0xda942042e4dd58b5ULL) << 1u) | 1u;
  state_ = 0;
  nextUint();
  state_ += h;
  nextUint();
}

}  // namespace pathfarm
