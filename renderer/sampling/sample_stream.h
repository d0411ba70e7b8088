#pragma once
// The renderer's sampling contract: every camera sample draws its uniform numbers from
// its own stream, seeded only by (scene seed, frame, pixel, sample index), except its
// film position and shutter time, which are stratified over the pixel's samples
// (StratifiedPixel) by the same key. An image is therefore the same bits for any thread count or tile size, and a
// method can replay a sample's random numbers in another frame (Manzi et al. 2016's
// temporal shift).
#include <cstdint>

#include "renderer/math/vecmath.h"

namespace pathfarm {

struct SampleKey {
  uint64_t sceneSeed = 0;
  int64_t frame = 0;
  int32_t x = 0, y = 0;
  uint32_t sampleIndex = 0;
};

// PCG32 (O'Neill 2014) with the stream selected by a hash of the key.
class SampleStream {
 public:
  explicit SampleStream(const SampleKey& key);

  float next1D() {
    // 24 high bits give floats exactly representable and strictly below 1.
    return static_cast<float>(nextUint() >> 8) * 0x1p-24f;
  }
  Vec2f next2D() {
    const float a = next1D();
    return {a, next1D()};
  }
  uint32_t nextUint() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ULL + increment_;
    const auto xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    const auto rot = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32 - rot) & 31));
  }

 private:
  friend class PixelStreams;
  SampleStream(uint64_t pixelHash, uint32_t sampleIndex);

  uint64_t state_ = 0;
  uint64_t increment_ = 1;
};

// The streams of one pixel's samples, SampleStream({sceneSeed, frame, x, y, i}) for each
// sample index i, with the pixel's part of the key hashed once rather than per sample.
class PixelStreams {
 public:
  PixelStreams(uint64_t sceneSeed, int64_t frame, int32_t x, int32_t y);
  SampleStream stream(uint32_t sampleIndex) const { return {pixelHash_, sampleIndex}; }

 private:
  uint64_t pixelHash_ = 0;
};

// The first three dimensions of a camera sample, stratified over the pixel's samples:
// the film position within the pixel, in [0, 1)^2, and the time within the shutter, in
// [0, 1). Sample `sampleIndex` is point number `sampleIndex` of the first three dimensions of Sobol's
// sequence, each dimension's digits scrambled by a random bit pattern of the pixel
// (scene seed, frame, x, y). For every 2^k samples whose indices start at a multiple of
// 2^k, each dimension alone puts one sample in each of 2^k equal intervals, and position
// and time together are spread as evenly: an edge, a texture line or a thin feature
// moving across the pixel during the shutter is covered far more evenly than by
// independent points. The scramble keeps neighbouring pixels' patterns unrelated, and
// each block of 2^kStratifiedBlockBits sample indices has a scramble of its own, so
// renders drawing from different blocks are independent.
inline constexpr int kStratifiedBlockBits = 24;
struct StratifiedSample {
  Vec2f film;
  float time = 0;
};
// One pixel's pattern: its scramble is hashed once, and each sample reads its point.
class StratifiedPixel {
 public:
  StratifiedPixel(uint64_t sceneSeed, int64_t frame, int32_t x, int32_t y);
  StratifiedSample sample(uint32_t sampleIndex) const;

 private:
  uint64_t pixelHash_ = 0, timeScramble_ = 0;  // the first block's
};

}  // namespace pathfarm
