// core/include/odocal/math/numeric.hpp: the robot's own 64-bit division (no libgcc
// __udivmoddi4) and the whole-number test the parameter table uses, against the host's
// arithmetic on edge values and on a sweep.

#include "odocal/math/numeric.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

namespace {

using odocal::math::divide_u64;
using odocal::math::is_whole;

TEST(Numeric, DivideU64MatchesTheHostsDivisionOnEdges) {
  const std::uint64_t xs[] = {0u,
                              1u,
                              999u,
                              1000u,
                              0xFFFFu,
                              0x10000u,
                              0xFFFFFFFFu,
                              0x100000000u,
                              0x123456789ABCDEFull,
                              std::numeric_limits<std::uint64_t>::max() - 1u,
                              std::numeric_limits<std::uint64_t>::max()};
  const std::uint16_t ds[] = {1u, 2u, 3u, 7u, 10u, 1000u, 0x8000u, 0xFFFFu};
  for (std::uint64_t x : xs) {
    for (std::uint16_t d : ds) {
      EXPECT_EQ(divide_u64(x, d), x / d) << x << " / " << d;
    }
  }
}

TEST(Numeric, DivideU64MatchesOnASweep) {
  // A multiplicative sweep over the whole 64-bit range (odd step: every bit pattern moves).
  std::uint64_t x = 0x9E3779B97F4A7C15ull;
  for (int i = 0; i < 20000; ++i) {
    x = x * 6364136223846793005ull + 1442695040888963407ull;
    const auto d = static_cast<std::uint16_t>((x >> 48) | 1u);
    ASSERT_EQ(divide_u64(x, d), x / d) << x << " / " << d;
  }
}

TEST(Numeric, DivideU64IsUsableAtCompileTime) {
  static_assert(divide_u64(1000000000000ull, 1000u) == 1000000000ull);
  SUCCEED();
}

TEST(Numeric, IsWholeTellsWholeFromFractionalAndNonFinite) {
  EXPECT_TRUE(is_whole(0.0f));
  EXPECT_TRUE(is_whole(-0.0f));
  EXPECT_TRUE(is_whole(1440.0f));
  EXPECT_TRUE(is_whole(-3.0f));
  EXPECT_TRUE(is_whole(16777215.0f));  // 2^24 - 1
  EXPECT_TRUE(is_whole(16777216.0f));  // 2^24: every float from here on is whole
  EXPECT_TRUE(is_whole(1.0e30f));
  EXPECT_TRUE(is_whole(-1.0e30f));
  EXPECT_FALSE(is_whole(0.5f));
  EXPECT_FALSE(is_whole(-2.25f));
  EXPECT_FALSE(is_whole(8388607.5f));  // the largest float with a fraction
  EXPECT_FALSE(is_whole(std::nextafter(1.0f, 2.0f)));
  EXPECT_FALSE(is_whole(std::numeric_limits<float>::quiet_NaN()));
  EXPECT_FALSE(is_whole(std::numeric_limits<float>::infinity()));
  EXPECT_FALSE(is_whole(-std::numeric_limits<float>::infinity()));
}

}  // namespace
