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

  // Maddahi eq. 7 on a straight command: F_lat multiplies the left row only, F_lon both rows.
  // On turns the one model's rule (robot_model.hpp, geometry_in_force) keeps the angle a turn
  // in place turns per wheel rotation: the wheelbases scale with the mean diameter.
  const Twist line{0.2f, 0.0f};
  const WheelRates straight = nominal.inverse(line);
  const WheelRates spin_wheels{-1.0f, 1.0f};
  const float spin_rate = nominal.forward(spin_wheels).w_radps;
  c = DriveConfig{};
  c.f_lat = 1.05f;
  k.configure(c);
  EXPECT_NEAR(k.inverse(line).left_radps, 1.05f * straight.left_radps, 1e-5f);
  EXPECT_NEAR(k.inverse(line).right_radps, straight.right_radps, 1e-5f);
  EXPECT_NEAR(k.forward(spin_wheels).w_radps, spin_rate, 1e-6f);

  c = DriveConfig{};
  c.f_lon = 1.1f;
  k.configure(c);
  EXPECT_NEAR(k.inverse(line).left_radps, 1.1f * straight.left_radps, 1e-5f);
  EXPECT_NEAR(k.inverse(line).right_radps, 1.1f * straight.right_radps, 1e-5f);
  EXPECT_NEAR(k.forward(spin_wheels).w_radps, spin_rate, 1e-6f);
  EXPECT_NEAR(k.wheelbase_m(), 0.15f / 1.1f, 1e-7f);  // b scaled with the diameters

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

// --- Arc wheelbase (wheelbase_arc_mm, odocal fit's arc-wheelbase model) ---

namespace arc {

// The wheelbase in force on an arc of radius R, from its definition: b_w = b + w·(b_arc − b) with
// w = R/(R + b_w/2) (forward over forward plus differential wheel travel). Solved by iteration in
// double precision (a contraction: |b_arc − b| is a few mm against R).
double arc_wheelbase_m(double b, double b_arc, double radius) {
  double bw = b;
  for (int i = 0; i < 100; ++i) {
    bw = b + radius / (radius + bw / 2.0) * (b_arc - b);
  }
  return bw;
}

DriveConfig arc_config() {
  DriveConfig c;  // 60 mm wheels, b = 150 mm
  c.wheelbase_arc_mm = 153.0f;
  return c;
}

}  // namespace arc

TEST(DiffDriveKinematics, ZeroArcWheelbaseChangesNothing) {
  DriveConfig c;
  c.c_l = 0.996f;
  c.wheelbase_mm = 151.5f;
  const DiffDriveKinematics one{c};
  c.wheelbase_arc_mm = 0.0f;  // the default: "the same as wheelbase_mm"
  const DiffDriveKinematics k{c};
  EXPECT_EQ(k.arc_gap_m(), 0.0f);
  for (float v : {-0.3f, 0.0f, 0.2f}) {
    for (float w : {-2.0f, 0.0f, 0.9f}) {
      const WheelRates a = one.inverse(Twist{v, w});
      const WheelRates b = k.inverse(Twist{v, w});
      EXPECT_EQ(a.left_radps, b.left_radps);
      EXPECT_EQ(a.right_radps, b.right_radps);
      EXPECT_EQ(k.wheelbase_for_rates_m(1.0f, 3.0f), k.wheelbase_m());
    }
  }
}

TEST(DiffDriveKinematics, ATurnInPlaceUsesTheTurnWheelbase) {
  const DiffDriveKinematics k{arc::arc_config()};
  // Turning in place each wheel moves ±ω·b/2: θ̇ = ∓ω·b/D with b = wheelbase_mm, not the arc one.
  const WheelRates r = k.inverse(Twist{0.0f, 1.2f});
  EXPECT_NEAR(r.left_radps, -1.2 * 0.150 / 0.060, 1e-5);
  EXPECT_NEAR(r.right_radps, 1.2 * 0.150 / 0.060, 1e-5);
  EXPECT_FLOAT_EQ(k.wheelbase_for_rates_m(-5.0f, 5.0f), 0.150f);
  // Straight: w = 1, the arc wheelbase (it multiplies nothing there).
  EXPECT_FLOAT_EQ(k.wheelbase_for_rates_m(5.0f, 5.0f), 0.153f);
  // At rest: w = 0 by convention, as the fit takes it.
  EXPECT_FLOAT_EQ(k.wheelbase_for_rates_m(0.0f, 0.0f), 0.150f);
}

TEST(DiffDriveKinematics, AnArcOfRadiusRUsesTheBlend) {
  const DiffDriveKinematics k{arc::arc_config()};
  for (const double radius : {0.1, 0.1875, 0.375, 1.5, -0.3}) {
    const double w_turn = 0.8;
    const double v = radius * w_turn;
    const double bw = arc::arc_wheelbase_m(0.150, 0.153, std::fabs(radius));
    // Equal wheels: each wheel's contact point runs on its own circle, R ∓ b_w/2.
    const WheelRates r = k.inverse(Twist{static_cast<float>(v), static_cast<float>(w_turn)});
    EXPECT_NEAR(r.left_radps, (2.0 * v - bw * w_turn) / 0.060, 2e-5 * std::fabs(v) / 0.03 + 1e-5)
        << radius;
    EXPECT_NEAR(r.right_radps, (2.0 * v + bw * w_turn) / 0.060, 2e-5 * std::fabs(v) / 0.03 + 1e-5)
        << radius;
    // Those rates give the same wheelbase back (odometry's weight is the wheel rates').
    EXPECT_NEAR(k.wheelbase_for_rates_m(r.left_radps, r.right_radps), bw, 1e-6) << radius;
    EXPECT_NEAR(k.wheelbase_for_twist_m(Twist{static_cast<float>(v), static_cast<float>(w_turn)}),
                bw, 1e-6)
        << radius;
    // And the forward map returns the commanded twist.
    const Twist back = k.forward(r);
    EXPECT_NEAR(back.v_mps, v, 1e-6);
    EXPECT_NEAR(back.w_radps, w_turn, 1e-5);
  }
  // Radius 375 mm on the 150/153 mm robot: w = R/(R + b_w/2) ≈ 0.833, b_w ≈ 152.5 mm.
  EXPECT_NEAR(arc::arc_wheelbase_m(0.150, 0.153, 0.375), 0.150 + 0.375 / (0.375 + 0.0762) * 0.003,
              1e-6);
}

TEST(DiffDriveKinematics, ForwardAndInverseStayInversesWithAnArcWheelbaseAndFactors) {
  DriveConfig c = arc::arc_config();
  c.c_l = 0.996f;
  c.c_r = 1.004f;
  c.f_lat = 1.01f;
  c.f_lon = 0.98f;
  for (const float arc_mm : {120.0f, 180.0f, 151.0f}) {  // -20 % and +20 %: the widest allowed
    c.wheelbase_arc_mm = arc_mm;
    const DiffDriveKinematics k{c};
    for (float v : {-0.5f, 0.0f, 0.13f, 0.4f}) {
      for (float w : {-3.0f, -0.2f, 0.0f, 1.7f}) {
        const Twist back = k.forward(k.inverse(Twist{v, w}));
        EXPECT_NEAR(back.v_mps, v, 1e-6f);
        // The inverse takes the weight from the twist, the forward map from the wheel rates: with
        // unequal effective wheels (here D_L 60.38, D_R 61.47 mm) the rates' weight differs from
        // the twist's by up to half the wheels' relative difference, 0.9 %, and ω by
        // Δb_w/b_w <= |b_arc − b|·Δw/(b − |b_arc − b|): 0.22 % of ω at worst (arc −20 %). (The
        // June robot: 0.8 % times 0.05 %, 4e-6.)
        const float gap = std::fabs(arc_mm - 150.0f);
        const float rel = gap / (150.0f - gap) * 0.5f *
                          std::fabs(k.right_diameter_m() - k.left_diameter_m()) /
                          (0.5f * (k.right_diameter_m() + k.left_diameter_m()));
        EXPECT_NEAR(back.w_radps, w, 1e-5f + 1.1f * rel * std::fabs(w)) << arc_mm;
      }
    }
  }
}

}  // namespace
}  // namespace odocal::drive
