#pragma once
/// @file
/// Small integer and float helpers that keep libgcc's larger routines out of the robot image: the
/// Cortex-M4 divides 32-bit integers in hardware but not 64-bit ones (libgcc's `__udivmoddi4` is
/// ~0.7 KB). Pure, ISR-safe. Tests: tests/core/math/numeric_test.cpp.

#include <cstdint>

namespace odocal::math {

/// x / d for a divisor below 2^16, by long division in 16-bit digits (each step fits in 32 bits).
constexpr std::uint64_t divide_u64(std::uint64_t x, std::uint16_t d) {
  std::uint64_t quotient = 0u;
  std::uint32_t remainder = 0u;
  for (int shift = 48; shift >= 0; shift -= 16) {
    const std::uint32_t part =
        (remainder << 16u) |
        static_cast<std::uint32_t>((x >> static_cast<unsigned>(shift)) & 0xFFFFu);
    quotient = (quotient << 16u) | (part / d);
    remainder = part % d;
  }
  return quotient;
}

/// True when `value` is a whole number (floats of 2^24 and more are all whole; NaN and inf not).
inline bool is_whole(float value) {
  constexpr float exact_limit = 16777216.0f;  // 2^24
  if (!(value > -exact_limit && value < exact_limit)) {
    return value - value == 0.0f;  // finite
  }
  return static_cast<float>(static_cast<std::int32_t>(value)) == value;
}

}  // namespace odocal::math
