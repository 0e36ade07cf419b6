#include "odocal/drive/diff_drive_kinematics.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "test_plant.hpp"

namespace odocal::drive {
namespace {

TEST(DiffDriveKinematics, ForwardAndInverseAreExactInversesWithUnitFactors) {
  DiffDriveKinematics k{DriveConfig{}};
  for (float v : {-0.5f, 0.0f, 0.13f, 0.4f}) {
    for (float w : {-3.0f, -0.2f, 0.0f, 1.7f}) {
      const Twist back = k.forward(k.inverse(Twist{v, w}));
      EXPECT_NEAR(back.v_mps, v, 1e-6f);
      EXPECT_NEAR(back.w_radps, w, 1e-5f);
    }
  }
}

TEST(DiffDriveKinematics, ForwardAndInverseStayInversesWithCalibrationFactors) {
  DriveConfig c;
  c.c_l = 0.996f;
  c.c_r = 1.004f;
  c.f_lat = 1.01f;
  c.f_lon = 0.98f;
  c.wheelbase_mm = 151.5f;
  DiffDriveKinematics k{c};
  const Twist back = k.forward(k.inverse(Twist{0.2f, 0.7f}));
  EXPECT_NEAR(back.v_mps, 0.2f, 1e-6f);
  EXPECT_NEAR(back.w_radps, 0.7f, 1e-5f);
}

TEST(DiffDriveKinematics, NominalStraightLineAndTurnInPlace) {
  DiffDriveKinematics k{DriveConfig{}};  // D = 60 mm, b = 150 mm
  const WheelRates straight = k.inverse(Twist{0.3f, 0.0f});
  EXPECT_NEAR(straight.left_radps, 2.0f * 0.3f / 0.06f, 1e-4f);  // Maddahi eq. 6
  EXPECT_NEAR(straight.right_radps, 2.0f * 0.3f / 0.06f, 1e-4f);
  const WheelRates spin = k.inverse(Twist{0.0f, 1.0f});
  EXPECT_NEAR(spin.left_radps, -0.15f / 0.06f, 1e-5f);
  EXPECT_NEAR(spin.right_radps, 0.15f / 0.06f, 1e-5f);
  EXPECT_NEAR(k.left_m_per_count(), M_PI * 0.06 / 1440.0, 1e-9);
}

TEST(DiffDriveKinematics, EachFactorScalesWhatTheEquationsSay) {
  const DiffDriveKinematics nominal{DriveConfig{}};
  const WheelRates base = nominal.inverse(Twist{0.2f, 0.5f});

  DriveConfig c;
  c.c_l = 1.02f;  // UMBmark eq. 6.35: left counts are worth 2 % more distance
  DiffDriveKinematics k{c};
  EXPECT_NEAR(k.left_m_per_count(), 1.02f * nominal.left_m_per_count(), 1e-10f);
  EXPECT_NEAR(k.inverse(Twist{0.2f, 0.5f}).left_radps, base.left_radps / 1.02f, 1e-5f);
  EXPECT_NEAR(k.inverse(Twist{0.2f, 0.5f}).right_radps, base.right_radps, 1e-5f);

  c = DriveConfig{};
  c.f_lat = 1.05f;  // Maddahi eq. 7: F_lat multiplies the left row only
  k.configure(c);
  EXPECT_NEAR(k.inverse(Twist{0.2f, 0.5f}).left_radps, 1.05f * base.left_radps, 1e-5f);
  EXPECT_NEAR(k.inverse(Twist{0.2f, 0.5f}).right_radps, base.right_radps, 1e-5f);

  c = DriveConfig{};
  c.f_lon = 1.1f;  // Maddahi eq. 7: F_lon multiplies both rows
  k.configure(c);
  EXPECT_NEAR(k.inverse(Twist{0.2f, 0.5f}).left_radps, 1.1f * base.left_radps, 1e-5f);
  EXPECT_NEAR(k.inverse(Twist{0.2f, 0.5f}).right_radps, 1.1f * base.right_radps, 1e-5f);

  c = DriveConfig{};
  c.wheelbase_mm = 160.0f;  // the corrected wheelbase sets the turn term
  k.configure(c);
  const WheelRates spin = k.inverse(Twist{0.0f, 1.0f});
  EXPECT_NEAR(spin.right_radps, 0.16f / 0.06f, 1e-5f);
}

TEST(DiffDriveKinematics, RightFactorAboveOneBendsAStraightCommandToTheRight) {
  // The firmware believes the right wheel is 1 % larger (c_R = 1.01) on a robot whose wheels are
  // equal: for a straight command it turns the right wheel 1 % slower, so the true robot drives
  // a clockwise circle of radius R = b(1 + 1/c_R) / (2(1/c_R − 1)) (negative: to the right).
  DriveConfig c;
  c.c_r = 1.01f;
  DiffDriveKinematics k{c};
  const WheelRates rates = k.inverse(Twist{0.2f, 0.0f});
  test::TestRobot robot;  // true wheels 60 mm, wheelbase 150 mm
  const double dt = 1e-3;
  const double seconds = 5.0;
  for (int i = 0; i < static_cast<int>(seconds / dt); ++i) {
    robot.move(rates.left_radps * dt, rates.right_radps * dt);
  }
  const double cr = 1.01;
  const double radius = 0.15 * (1.0 + 1.0 / cr) / (2.0 * (1.0 / cr - 1.0));
  const double v_centre = 0.2 * (1.0 + 1.0 / cr) / 2.0;
  const double heading = v_centre * seconds / radius;
  EXPECT_LT(robot.y, 0.0);
  EXPECT_NEAR(robot.theta, heading, 1e-5);
  EXPECT_NEAR(robot.x, radius * std::sin(heading), 1e-5);
  EXPECT_NEAR(robot.y, radius * (1.0 - std::cos(heading)), 1e-5);
}

}  // namespace
}  // namespace odocal::drive
