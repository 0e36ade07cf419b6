// Maddahi & Zareinia eq. 4, 5 and 7: hand-computed values, physical direction of the factors,
// and agreement with the drive stack's inverse kinematics.
#include "odocal/calib/lateral.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "alloc_counter.hpp"
#include "odocal/drive/diff_drive_kinematics.hpp"

namespace odocal::calib {
namespace {

LateralStatus solve(const std::vector<StopPoint>& trials, LateralResult& r, double length = 1000.0,
                    double theta_l = 0.0) {
  LateralInput in;
  in.trials = trials.data();
  in.trial_count = trials.size();
  in.length_mm = length;
  in.wheelbase_mm = 150.0;
  in.left_diameter_mm = 60.0;
  in.right_diameter_mm = 60.0;
  in.theta_l_rad = theta_l;
  return solve_lateral(in, r);
}

// L = 1000, l = 150, D = 60: θ_L = 2L/D_L = 33.333 rad and 4l/(n·D_R·θ_L) = 600/(2·2000) = 0.15.
// Two trials at (1000, 10): Σ atan(0.01) = 0.0199993334, F_lat = 1 + 0.15·0.0199993334
// = 1.0029999; F_lon = 1000/hypot(1000, 10) = 0.9999500037.
TEST(Lateral, Eq4And5MatchHandComputedValues) {
  LateralResult r;
  ASSERT_EQ(solve({{1000.0, 10.0}, {1000.0, 10.0}}, r), LateralStatus::ok);
  EXPECT_NEAR(r.theta_l_rad, 1000.0 / 30.0, 1e-12);
  EXPECT_NEAR(r.f_lat, 1.0029999, 1e-7);
  EXPECT_NEAR(r.f_lon, 0.9999500037, 1e-10);
}

// Stopping short (mean x = 985 on a 1000 mm line): F_lon = 1000/985 = 1.015228426; straight,
// so F_lat = D_L/D_R = 1 exactly. A drift to the right (y < 0) gives F_lat < 1.
TEST(Lateral, FactorsPointTheRightWay) {
  LateralResult r;
  ASSERT_EQ(solve({{990.0, 0.0}, {980.0, 0.0}}, r), LateralStatus::ok);
  EXPECT_NEAR(r.f_lon, 1.015228426, 1e-9);
  EXPECT_DOUBLE_EQ(r.f_lat, 1.0);
  ASSERT_EQ(solve({{1000.0, -20.0}, {1000.0, -30.0}}, r), LateralStatus::ok);
  EXPECT_LT(r.f_lat, 1.0);
  // An explicit θ_L halves the correction when it doubles.
  LateralResult half;
  ASSERT_EQ(solve({{1000.0, -20.0}, {1000.0, -30.0}}, half, 1000.0, 2.0 * 1000.0 / 30.0),
            LateralStatus::ok);
  EXPECT_NEAR(1.0 - half.f_lat, (1.0 - r.f_lat) / 2.0, 1e-12);
}

// Physical check of eq. 4: the extra left-wheel share 4lφ/(D·θ_L) is the left-wheel travel that
// turns the robot back by the 2φ its chord leaned (φ = atan(y/x)): (F_lat − 1)·L = 2φ·l.
TEST(Lateral, Eq4CancelsTheHeadingChangeOfTheArc) {
  LateralResult r;
  ASSERT_EQ(solve({{999.0, 25.0}, {999.0, 25.0}}, r), LateralStatus::ok);
  const double phi = std::atan(25.0 / 999.0);
  EXPECT_NEAR((r.f_lat - 1.0) * 1000.0, 2.0 * phi * 150.0, 1e-9);
}

TEST(Lateral, RefusesBadInput) {
  LateralResult r;
  r.f_lat = 7.0;
  EXPECT_EQ(solve({{1000.0, 0.0}}, r), LateralStatus::too_few_trials);
  EXPECT_EQ(solve({{1000.0, 0.0}, {1000.0, 0.0}}, r, -1.0), LateralStatus::bad_geometry);
  EXPECT_EQ(solve({{NAN, 0.0}, {1000.0, 0.0}}, r), LateralStatus::non_finite);
  EXPECT_EQ(solve({{1000.0, INFINITY}, {1000.0, 0.0}}, r), LateralStatus::non_finite);
  EXPECT_EQ(solve({{0.0, 0.0}, {1000.0, 0.0}}, r), LateralStatus::error_too_large);
  EXPECT_EQ(solve({{2500.0, 0.0}, {1000.0, 0.0}}, r), LateralStatus::error_too_large);
  EXPECT_EQ(solve({{1000.0, 1200.0}, {1000.0, 0.0}}, r), LateralStatus::error_too_large);
  EXPECT_EQ(r.f_lat, 7.0);
}

// Eq. 7 by hand: ẋ = 0.3 m/s, ẏ = 0, θ̇ = 0.1 rad/s, l = 0.15 m, D = 0.06 m, F_lat = 1.02,
// F_lon = 0.97: θ̇_R = 0.97·(0.6 + 0.015)/0.06 = 9.9425, θ̇_L = 0.97·1.02·(0.6 − 0.015)/0.06
// = 9.646650 rad/s. Inverting gives the factors back.
TEST(Lateral, Eq7FactorsFromWheelRatesByHand) {
  // F_lon 0.97, F_lat 1.02, v 0.3 m/s, ω 0.1 rad/s, l 0.15 m, D 0.06 m. The wheelbase in force
  // scales with the mean effective diameter: s = (1/(1.02·0.97) + 1/0.97)/2, b = 0.15·s
  // (= 0.1531231 m); θ̇_R = 0.97·(0.6 + 0.1·b)/0.06 = 9.947549019607843,
  // θ̇_L = 0.97·1.02·(0.6 − 0.1·b)/0.06 = 9.6415 (exactly: 0.9894·(0.6 − 0.1·b) = 0.57849).
  LateralResult r;
  ASSERT_EQ(
      factors_from_wheel_rates({0.3, 0.0, 0.1, 9.6415, 9.947549019607843}, {150.0, 60.0, 60.0}, r),
      LateralStatus::ok);
  EXPECT_NEAR(r.f_lon, 0.97, 1e-12);
  EXPECT_NEAR(r.f_lat, 1.02, 1e-12);
}

// The drive stack implements eq. 7 for the robot; inverting its wheel rates must give back the
// factors it was configured with (single precision: ~1e-6 relative).
TEST(Lateral, Eq7AgreesWithDriveKinematics) {
  drive::DriveConfig config;
  config.wheel_diameter_mm = 60.0f;
  config.wheelbase_mm = 150.0f;
  config.f_lat = 1.013f;
  config.f_lon = 0.985f;
  const drive::DiffDriveKinematics kinematics(config);
  for (const float w : {-0.4f, 0.0f, 0.3f}) {
    const drive::WheelRates rates = kinematics.inverse({0.25f, w});
    // Travelling along a heading θ: the start-frame velocity is (v cos θ, v sin θ).
    const double theta = 0.05;
    LateralResult r;
    ASSERT_EQ(factors_from_wheel_rates({0.25 * std::cos(theta), 0.25 * std::sin(theta), w,
                                        rates.left_radps, rates.right_radps},
                                       {150.0, 60.0, 60.0}, r),
              LateralStatus::ok);
    EXPECT_NEAR(r.f_lat, 1.013, 1e-5) << "w = " << w;
    EXPECT_NEAR(r.f_lon, 0.985, 1e-5) << "w = " << w;
  }
}

TEST(Lateral, Eq7RefusesDegenerateMotion) {
  LateralResult r;
  // A turn in place (v = 0) keeps its angle whatever F_lon is: it cannot show it.
  EXPECT_EQ(factors_from_wheel_rates({0.0, 0.0, 1.0, -2.5, 2.5}, {150.0, 60.0, 60.0}, r),
            LateralStatus::degenerate);
  // θ̇_R = 2lω/(D_L + D_R): the right row says nothing of F_lat.
  EXPECT_EQ(factors_from_wheel_rates({0.1, 0.0, 1.0, 2.0, 2.5}, {150.0, 60.0, 60.0}, r),
            LateralStatus::degenerate);
  EXPECT_EQ(factors_from_wheel_rates({0.0, 0.0, 0.0, 1.0, 1.0}, {150.0, 60.0, 60.0}, r),
            LateralStatus::degenerate);
  EXPECT_EQ(factors_from_wheel_rates({0.3, 0.0, 0.0, NAN, 1.0}, {150.0, 60.0, 60.0}, r),
            LateralStatus::non_finite);
  EXPECT_EQ(factors_from_wheel_rates({0.3, 0.0, 0.0, 1.0, 1.0}, {0.0, 60.0, 60.0}, r),
            LateralStatus::bad_geometry);
}

TEST(Lateral, AllocatesNothing) {
  const StopPoint trials[2] = {{1000.0, 10.0}, {990.0, 5.0}};
  LateralInput in;
  in.trials = trials;
  in.trial_count = 2;
  in.length_mm = 1000.0;
  in.wheelbase_mm = 150.0;
  in.left_diameter_mm = 60.0;
  in.right_diameter_mm = 60.0;
  LateralResult r;
  const test::AllocationWatch watch;
  EXPECT_EQ(solve_lateral(in, r), LateralStatus::ok);
  EXPECT_EQ(factors_from_wheel_rates({0.3, 0.0, 0.1, 9.6, 9.9}, {150.0, 60.0, 60.0}, r),
            LateralStatus::ok);
  EXPECT_EQ(watch.allocations(), 0u);
}

}  // namespace
}  // namespace odocal::calib
