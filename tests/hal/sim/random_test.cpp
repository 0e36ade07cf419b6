// The simulator's generator is the project's one xoshiro256** engine.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "odocal/random/xoshiro256.hpp"
#include "odocal/sim/random.hpp"

namespace odocal::sim {
namespace {

TEST(SimRandom, DrawsTheSharedEngineSequence) {
  Random r(7u);
  random::Xoshiro256 engine(7u);
  // xoshiro256** seed 7, first value (computed from the published definition by a script).
  EXPECT_EQ(r.next_u64(), 0xb358faf74ef9765au);
  engine.next_u64();
  for (int i = 0; i < 100; ++i) {
    EXPECT_EQ(r.next_u64(), engine.next_u64());
  }
}

TEST(SimRandom, ReseedForgetsTheSpareNormal) {
  Random r(3u);
  const double first = r.normal();
  r.reseed(3u);
  EXPECT_EQ(r.normal(), first);
}

TEST(SimRandom, NormalHasUnitVarianceWithinSamplingError) {
  Random r(11u);
  constexpr int n = 20000;
  double sum = 0.0;
  double sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    const double x = r.normal();
    sum += x;
    sum2 += x * x;
  }
  const double mean = sum / n;
  // Standard error of the mean 1/sqrt(n) = 0.007, of the variance sqrt(2/n) = 0.01: 5 sigma.
  EXPECT_NEAR(mean, 0.0, 5.0 / std::sqrt(n));
  EXPECT_NEAR(sum2 / n - mean * mean, 1.0, 5.0 * std::sqrt(2.0 / n));
}

}  // namespace
}  // namespace odocal::sim
