#include "odocal/drive/velocity_estimator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "odocal/drive/quadrature_decoder.hpp"

namespace odocal::drive {
namespace {

constexpr double kCpr = 1440.0;
constexpr bool kA[4] = {false, true, true, false};
constexpr bool kB[4] = {false, false, true, true};

// Feeds a wheel turning at a constant `omega` (rad/s) for `seconds`, ticking every 1 ms, and
// returns the largest relative error of the estimate over the ticks after `settle_s`.
double worst_relative_error(double omega, double seconds, double settle_s) {
  QuadratureDecoder decoder;
  decoder.reset(false, false);
  VelocityEstimator estimator(static_cast<float>(kCpr));
  const double edge_period_s = 2.0 * M_PI / (std::fabs(omega) * kCpr);
  const std::uint32_t t0 = 0xFFFF0000u;  // cross the clock wrap during the run
  estimator.reset(decoder.snapshot(), t0);
  double next_edge_s = edge_period_s;
  int phase = 0;
  double worst = 0.0;
  for (double tick_s = 1e-3; tick_s <= seconds; tick_s += 1e-3) {
    while (next_edge_s <= tick_s) {
      phase = omega > 0 ? (phase + 1) % 4 : (phase + 3) % 4;
      const auto stamp = t0 + static_cast<std::uint32_t>(std::llround(next_edge_s * 1e6));
      decoder.on_edge(kA[phase], kB[phase], stamp);
      next_edge_s += edge_period_s;
    }
    estimator.update(decoder.snapshot(),
                     t0 + static_cast<std::uint32_t>(std::llround(tick_s * 1e6)));
    if (tick_s > settle_s) {
      worst = std::fmax(worst, std::fabs(estimator.speed_radps() - omega) / std::fabs(omega));
    }
  }
  return worst;
}

TEST(VelocityEstimator, ExactAtHighSpeedWithManyEdgesPerTick) {
  // 25 rad/s: ~5.7 edges per 1 ms tick. Timestamps are whole µs, so a window of ~1 ms between
  // edges is timed to ±1 µs at each end: relative error ≤ 2 µs / (window - one edge period).
  const double omega = 25.0;
  const double period_us = 2.0 * M_PI / (omega * kCpr) * 1e6;
  const double bound = 2.0 / (1000.0 - period_us);
  EXPECT_LT(worst_relative_error(omega, 0.5, 0.01), bound);
  EXPECT_LT(worst_relative_error(-omega, 0.5, 0.01), bound);
}

TEST(VelocityEstimator, ExactAtLowSpeedWithOneEdgeEveryManyTicks) {
  // 0.05 rad/s: one edge every 87 ms. Between edges the estimate must hold (the decay bound
  // 1 count / quiet time stays above the true speed until the next edge is due).
  const double omega = 0.05;
  const double period_us = 2.0 * M_PI / (omega * kCpr) * 1e6;
  const double bound = 2.0 / period_us + 1e-6;
  EXPECT_LT(worst_relative_error(omega, 3.0, 0.2), bound);
  EXPECT_LT(worst_relative_error(-omega, 3.0, 0.2), bound);
}

TEST(VelocityEstimator, DecaysAndReachesZeroAfterTheStopTimeout) {
  QuadratureDecoder decoder;
  decoder.reset(false, false);
  VelocityEstimator estimator(static_cast<float>(kCpr), 200000u);
  estimator.reset(decoder.snapshot(), 0u);
  int phase = 0;
  std::uint32_t t = 0;
  for (int i = 0; i < 100; ++i) {  // 10 edges per ms
    phase = (phase + 1) % 4;
    decoder.on_edge(kA[phase], kB[phase], t += 100u);
    if (i % 10 == 9)
      estimator.update(decoder.snapshot(), t);
  }
  const float moving = estimator.speed_radps();
  EXPECT_NEAR(moving, 2.0 * M_PI / kCpr / 100e-6, 1e-3);
  // The wheel stops dead. The estimate may never exceed one count per quiet time.
  for (std::uint32_t quiet = 1000u; quiet < 200000u; quiet += 1000u) {
    estimator.update(decoder.snapshot(), t + quiet);
    const float bound = static_cast<float>(2.0 * M_PI / kCpr) / (static_cast<float>(quiet) * 1e-6f);
    EXPECT_LE(estimator.speed_radps(), bound * 1.0001f);
  }
  estimator.update(decoder.snapshot(), t + 200000u);
  EXPECT_EQ(estimator.speed_radps(), 0.0f);
  EXPECT_EQ(estimator.position_counts(), 100);
}

}  // namespace
}  // namespace odocal::drive
