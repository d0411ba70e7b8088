#pragma once
// bfloat16: a float's sign, exponent and top 7 mantissa bits in 16 bits. The Poisson
// system keeps its row weight factors this way, half the memory of floats; 0 and powers
// of two are exact, any other positive normal value comes back within 2^-8 relative.
#include <bit>
#include <cstdint>

namespace pathfarm {

// Rounded to nearest, ties to even; for finite values.
inline uint16_t toBfloat16(float value) {
  const uint32_t bits = std::bit_cast<uint32_t>(value);
  return static_cast<uint16_t>((bits + 0x7FFFu + ((bits >> 16) & 1u)) >> 16);
}

inline float fromBfloat16(uint16_t value) { return std::bit_cast<float>(static_cast<uint32_t>(value) << 16); }

}  // namespace pathfarm
