#include "odocal/drive/odometry.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace odocal::drive {
namespace {

TEST(Odometry, StraightKilometreInHalfMillimetreSteps) {
  // Two million single-precision increments: plain float summation would lose metres here;
  // compensated summation keeps the error near one rounding of the total (2^-24 · 1000 m).
  Odometry odometry;
  const float step = 0.0005f;
  for (int i = 0; i < 2000000; ++i)
    odometry.update(step, step, 0.15f);
  const double expected = 2000000.0 * static_cast<double>(step);
  EXPECT_NEAR(odometry.pose().x_m, expected, 5e-4);
  EXPECT_NEAR(odometry.pose().y_m, 0.0, 1e-9);
  EXPECT_NEAR(odometry.distance_m(), expected, 5e-4);
}

TEST(Odometry, ConstantCurvatureStaysOnTheClosedFormCircle) {
  // Left and right travel fixed per step: an exact arc integrator puts every point on the circle
  // of radius R = b (dl + dr) / (2 (dr − dl)) centred at (0, R), whatever the step size.
  const float b = 0.15f;
  const float dl = 0.0004f, dr = 0.0006f;
  const double radius = 0.15 * (0.0004 + 0.0006) / (2.0 * (0.0006 - 0.0004));  // 0.375 m
  const double dtheta = (0.0006 - 0.0004) / 0.15;
  Odometry odometry;
  double worst = 0.0;
  const int steps = 200000;  // about 42 laps
  for (int i = 1; i <= steps; ++i) {
    odometry.update(dl, dr, b);
    if (i % 997 == 0) {
      const double theta = i * dtheta;
      const Pose p = odometry.pose();
      worst = std::fmax(worst, std::hypot(p.x_m - radius * std::sin(theta),
                                          p.y_m - radius * (1.0 - std::cos(theta))));
    }
  }
  // Single precision on a 0.75 m circle: a few ULPs of the coordinates (6e-8 m each) per lap.
  EXPECT_LT(worst, 5e-5);
  EXPECT_NEAR(odometry.rotation_rad(), steps * dtheta, 1e-3);
}

TEST(Odometry, LargeStepsAreStillExactArcs) {
  // A quarter circle in one step: Euler would land at (π/2·R, 0); the arc lands at (R, R).
  Odometry odometry;
  const float b = 0.2f;
  const float radius = 1.0f;
  const float angle = static_cast<float>(M_PI / 2);
  odometry.update((radius - b / 2) * angle, (radius + b / 2) * angle, b);
  EXPECT_NEAR(odometry.pose().x_m, 1.0f, 1e-6f);
  EXPECT_NEAR(odometry.pose().y_m, 1.0f, 1e-6f);
  EXPECT_NEAR(odometry.pose().theta_rad, angle, 1e-6f);
}

TEST(Odometry, TurnInPlaceWrapsTheHeadingAndKeepsPosition) {
  Odometry odometry;
  const float b = 0.15f;
  const float per_step = 0.001f;  // each wheel, opposite directions
  const int steps = 10000;        // 10 m of wheel travel each: 133 rad
  for (int i = 0; i < steps; ++i)
    odometry.update(-per_step, per_step, b);
  const double total = steps * 2.0 * per_step / b;
  EXPECT_NEAR(odometry.pose().x_m, 0.0f, 1e-6f);
  EXPECT_NEAR(odometry.pose().y_m, 0.0f, 1e-6f);
  EXPECT_NEAR(odometry.pose().theta_rad, std::remainder(total, 2.0 * M_PI), 1e-4);
  EXPECT_LE(std::fabs(odometry.pose().theta_rad), M_PI);
}

TEST(Odometry, ResetSetsThePoseAndKeepsTheOdometer) {
  Odometry odometry;
  for (int i = 0; i < 100; ++i)
    odometry.update(0.01f, 0.01f, 0.15f);
  odometry.reset(Pose{1.0f, 2.0f, 3.0f});
  EXPECT_FLOAT_EQ(odometry.pose().x_m, 1.0f);
  EXPECT_FLOAT_EQ(odometry.pose().y_m, 2.0f);
  EXPECT_NEAR(odometry.pose().theta_rad, 3.0f, 1e-6f);
  EXPECT_NEAR(odometry.distance_m(), 1.0f, 1e-5f);
  odometry.update(0.1f, 0.1f, 0.15f);  // moves along θ = 3 rad
  EXPECT_NEAR(odometry.pose().x_m, 1.0f + 0.1f * std::cos(3.0f), 1e-5f);
  EXPECT_NEAR(odometry.pose().y_m, 2.0f + 0.1f * std::sin(3.0f), 1e-5f);
}

}  // namespace
}  // namespace odocal::drive
