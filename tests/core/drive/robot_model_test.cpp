#include "odocal/drive/robot_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numbers>

#include "odocal/drive/diff_drive_kinematics.hpp"
#include "odocal/drive/odometry.hpp"

namespace odocal::drive::model {
namespace {

using std::numbers::pi;

TEST(RobotModel, HalfTurnMatchesLibmOnBothSidesOfTheSeriesLimit) {
  // Double: within a few roundings of libm everywhere; the slope against its closed form away
  // from 0 and against the series' own limit (−h/3) near 0, where the closed form cancels.
  for (const double h : {0.0, 1e-9, 1e-5, 9.99e-4, 1.001e-3, 0.01, 0.3, 1.0, 2.5, -0.7, -1e-4}) {
    const HalfTurn<double> t = half_turn(h);
    EXPECT_NEAR(t.cos, std::cos(h), 4e-16) << h;
    EXPECT_NEAR(t.sin, std::sin(h), 4e-16) << h;
    const double sinc = h == 0.0 ? 1.0 : std::sin(h) / h;
    EXPECT_NEAR(t.sinc, sinc, 4e-16) << h;
    if (std::fabs(h) > 0.1) {
      EXPECT_NEAR(sinc_slope(h, t), (std::cos(h) - sinc) / h, 1e-14) << h;
    } else if (h == 0.0) {
      EXPECT_EQ(sinc_slope(h, t), 0.0);
    } else {
      // sinc'(h) = −h/3 + h³/30 − h⁵/840 ...: the series to h³ is within 1e-9·|h| here; above
      // the series limit the closed form loses ~4 roundings over |h| to cancellation.
      EXPECT_NEAR(sinc_slope(h, t), -h / 3.0 + h * h * h / 30.0,
                  1e-9 * std::fabs(h) + 1e-15 / std::fabs(h))
          << h;
    }
  }
  // Float: within two roundings of the double value.
  for (const float h : {0.0f, 1e-4f, 0.0199f, 0.0201f, 0.2f, 1.2f, -0.5f}) {
    const HalfTurn<float> t = half_turn(h);
    const double hd = static_cast<double>(h);
    const double sinc = h == 0.0f ? 1.0 : std::sin(hd) / hd;
    EXPECT_NEAR(static_cast<double>(t.cos), std::cos(hd), 2.4e-7) << h;
    EXPECT_NEAR(static_cast<double>(t.sin), std::sin(hd), 2.4e-7) << h;
    EXPECT_NEAR(static_cast<double>(t.sinc), sinc, 2.4e-7) << h;
  }
}

TEST(RobotModel, ArcStepsOfAnyLengthLandOnTheSameCircle) {
  // Constant curvature: one step of 1 m turning 2 rad, or 1000 steps of 1 mm, end at the closed
  // form point (R sin θ, R (1 − cos θ)), R = s/θ. Exact arcs, not Euler: only rounding differs.
  const double s = 1.0, turn = 2.0, radius = s / turn;
  PoseOf<double> one;
  advance_arc(one, s, turn);
  PoseOf<double> many;
  for (int i = 0; i < 1000; ++i) {
    advance_arc(many, s / 1000.0, turn / 1000.0);
  }
  for (const PoseOf<double>& p : {one, many}) {
    EXPECT_NEAR(p.x, radius * std::sin(turn), 1e-12);
    EXPECT_NEAR(p.y, radius * (1.0 - std::cos(turn)), 1e-12);
    EXPECT_NEAR(p.theta, turn, 1e-12);
  }
  // A straight line and a turn in place are the two limits.
  PoseOf<double> line;
  advance_arc(line, 2.0, 0.0);
  EXPECT_DOUBLE_EQ(line.x, 2.0);
  EXPECT_DOUBLE_EQ(line.y, 0.0);
  PoseOf<double> spin;
  advance_arc(spin, 0.0, pi);
  EXPECT_DOUBLE_EQ(spin.x, 0.0);
  EXPECT_DOUBLE_EQ(spin.theta, pi);
}

TEST(RobotModel, WheelStepIsTheCentreArcOfTheWheelTravel) {
  // Wheels 0.3 and 0.5 m apart by b = 0.2 m: Δs 0.4 m, Δθ 1 rad.
  PoseOf<double> by_wheels{0.1, -0.2, 0.3};
  PoseOf<double> by_arc = by_wheels;
  advance(by_wheels, 0.3, 0.5, 0.2);
  advance_arc(by_arc, 0.4, 1.0);
  EXPECT_DOUBLE_EQ(by_wheels.x, by_arc.x);
  EXPECT_DOUBLE_EQ(by_wheels.y, by_arc.y);
  EXPECT_DOUBLE_EQ(by_wheels.theta, by_arc.theta);
}

TEST(RobotModel, TravelForIsTheStepsInverseAndBelievingTheTruthDrivesTheArc) {
  // Two wheelbases 15 % apart, wheels 0.4 % apart: every kind of increment.
  const Geometry<double> g{70.1, 69.8, 160.0, 184.0};
  struct Arc {
    double distance;
    double turn;
  };
  for (const Arc a : {Arc{1000.0, 0.0}, Arc{0.0, 2.0 * pi}, Arc{0.0, -pi}, Arc{471.0, 1.2},
                      Arc{300.0, -2.5}, Arc{-250.0, 0.4}, Arc{50.0, 3.0}}) {
    SCOPED_TRACE(::testing::Message() << a.distance << " mm, " << a.turn << " rad");
    const WheelTravel<double> w = travel_for(g, a.distance, a.turn);
    // The step of those wheels, with the wheelbase their rotations pick, is the arc asked for:
    // the distance exactly, the turn to the fixed point's 2e-8 of the wheelbase.
    const double b = wheelbase_for(g.wheelbase, g.wheelbase_arc, w.left / g.left_diameter,
                                   w.right / g.right_diameter);
    EXPECT_NEAR(0.5 * (w.left + w.right), a.distance, 1e-12 * (1.0 + std::fabs(a.distance)));
    EXPECT_NEAR((w.right - w.left) / b, a.turn, 2e-8 * std::fabs(a.turn) + 1e-15);
    // Told the truth, the drive ends where the arc does.
    PoseOf<double> believed;
    advance_believing(believed, g, g, a.distance, a.turn);
    PoseOf<double> arc;
    advance_arc(arc, a.distance, a.turn);
    EXPECT_NEAR(believed.x, arc.x, 1e-6);
    EXPECT_NEAR(believed.y, arc.y, 1e-6);
    EXPECT_NEAR(believed.theta, arc.theta, 2e-8 * std::fabs(a.turn) + 1e-15);
  }
  // A right wheel 1 % larger than the drive believes (one wheelbase b): on a metre's line the
  // right wheel rolls 10 mm more, so the robot turns left by 10/b and goes 1005 mm along.
  const Geometry<double> told{70.0, 70.0, 150.0, 0.0};
  const Geometry<double> big_right{70.0, 70.7, 150.0, 0.0};
  PoseOf<double> p;
  advance_believing(p, told, big_right, 1000.0, 0.0);
  EXPECT_NEAR(p.theta, 10.0 / 150.0, 1e-12);
  PoseOf<double> expected;
  advance_arc(expected, 1005.0, 10.0 / 150.0);
  EXPECT_NEAR(p.x, expected.x, 1e-9);
  EXPECT_NEAR(p.y, expected.y, 1e-9);
  // A wheelbase 2 % wider than believed: a full turn in place comes 2 % short.
  const Geometry<double> wide{70.0, 70.0, 153.0, 0.0};
  PoseOf<double> spun;
  advance_believing(spun, told, wide, 0.0, 2.0 * pi);
  EXPECT_NEAR(spun.theta, 2.0 * pi * 150.0 / 153.0, 1e-12);
  EXPECT_NEAR(spun.x, 0.0, 1e-12);
  EXPECT_NEAR(spun.y, 0.0, 1e-12);
}

TEST(RobotModel, ArcWeightIsTheForwardShareOfTheWheelTravel) {
  EXPECT_EQ(arc_weight(1.0, -1.0), 0.0);  // turning in place
  EXPECT_EQ(arc_weight(2.0, 2.0), 1.0);   // straight
  EXPECT_EQ(arc_weight(0.0, 0.0), 0.0);   // at rest
  // An arc of radius R with wheelbase b: wheels travel (R ∓ b/2)·θ, weight R/(R + b/2).
  const double r = 0.5, b = 0.2;
  EXPECT_NEAR(arc_weight(r - b / 2, r + b / 2), r / (r + b / 2), 1e-15);
  EXPECT_NEAR(arc_weight(-(r - b / 2), -(r + b / 2)), r / (r + b / 2), 1e-15);  // backwards
  // The wheelbase in force: b_arc straight, b in place, between them on an arc; 0 = one.
  EXPECT_EQ(wheelbase_for(150.0, 0.0, 1.0, 3.0), 150.0);
  EXPECT_EQ(wheelbase_for(150.0, 152.0, 1.0, -1.0), 150.0);
  EXPECT_EQ(wheelbase_for(150.0, 152.0, 1.0, 1.0), 152.0);
  EXPECT_NEAR(wheelbase_for(150.0, 152.0, r - b / 2, r + b / 2), 150.0 + 2.0 * r / (r + b / 2),
              1e-12);
}

/// The angle a turn in place of `counts` per wheel (left back, right forward) turns under `p`.
double spin_angle(const Parameters<double>& p, double counts, double counts_per_rev) {
  const Geometry<double> g = geometry_in_force(p);
  const double left = -counts * pi * g.left_diameter / counts_per_rev;
  const double right = counts * pi * g.right_diameter / counts_per_rev;
  PoseOf<double> pose;
  advance(pose, left, right, wheelbase_for(g.wheelbase, g.wheelbase_arc, left, right));
  return pose.theta;
}

TEST(RobotModel, MaddahiFactorsKeepEveryTurnInPlace) {
  // The composition rule: F_lat and F_lon change what straight runs show (the wheel ratio, the
  // distance) and leave the angle of a turn in place as c_l, c_r and the wheelbase made it.
  const Parameters<double> calibrated{60.0, 151.3, 0.0, 0.998, 1.002, 1.0, 1.0};
  const double before = spin_angle(calibrated, 1000.0, 1440.0);
  for (const double f_lat : {0.95, 0.999, 1.0, 1.004, 1.08}) {
    for (const double f_lon : {0.92, 0.999003, 1.0, 1.001, 1.1}) {
      Parameters<double> p = calibrated;
      p.f_lat = f_lat;
      p.f_lon = f_lon;
      EXPECT_NEAR(spin_angle(p, 1000.0, 1440.0), before, 1e-14 * before) << f_lat << " " << f_lon;
      // And the arc wheelbase scales with the one for turns in place.
      p.wheelbase_arc = 152.9;
      const Geometry<double> g = geometry_in_force(p);
      EXPECT_NEAR(g.wheelbase_arc / g.wheelbase, 152.9 / 151.3, 1e-14);
    }
  }
}

TEST(RobotModel, LongitudinalFactorScalesDistanceAndLateralOnlyTheRatio) {
  Parameters<double> p{60.0, 150.0, 0.0, 1.001, 0.999, 1.0, 1.0};
  const Geometry<double> g0 = geometry_in_force(p);
  EXPECT_EQ(g0.left_diameter, 60.0 * 1.001);  // F = 1: c exactly, wheelbase exactly
  EXPECT_EQ(g0.right_diameter, 60.0 * 0.999);
  EXPECT_EQ(g0.wheelbase, 150.0);
  p.f_lon = 1.02;  // a straight line covers 1/F_lon of the distance per count
  const Geometry<double> g1 = geometry_in_force(p);
  EXPECT_NEAR(g1.left_diameter + g1.right_diameter, (g0.left_diameter + g0.right_diameter) / 1.02,
              1e-12);
  EXPECT_NEAR(g1.left_diameter / g1.right_diameter, g0.left_diameter / g0.right_diameter, 1e-15);
  p.f_lon = 1.0;
  p.f_lat = 1.01;  // the left wheel's effective diameter alone
  const Geometry<double> g2 = geometry_in_force(p);
  EXPECT_NEAR(g2.left_diameter, g0.left_diameter / 1.01, 1e-12);
  EXPECT_EQ(g2.right_diameter, g0.right_diameter);
  // parameters_for undoes geometry_in_force with F = 1.
  const Parameters<double> back = parameters_for(g2, 60.0);
  const Geometry<double> g3 = geometry_in_force(back);
  EXPECT_NEAR(g3.left_diameter, g2.left_diameter, 1e-12);
  EXPECT_NEAR(g3.right_diameter, g2.right_diameter, 1e-12);
  EXPECT_NEAR(g3.wheelbase, g2.wheelbase, 1e-12);
  EXPECT_EQ(back.f_lat, 1.0);
  EXPECT_EQ(back.f_lon, 1.0);
}

TEST(RobotModel, FirmwareOdometryAndKinematicsFollowTheModel) {
  // The robot's float odometry over a path of arcs, lines and turns ends where the model's
  // double steps end with the same geometry: single-precision rounding of ~3000 steps of a few
  // millimetres (2^-24 relative each, compensated sums) keeps them within 0.05 mm, 1e-5 rad.
  DriveConfig config;
  config.wheel_diameter_mm = 48.0f;
  config.wheelbase_mm = 92.0f;
  config.wheelbase_arc_mm = 93.1f;
  config.counts_per_rev = 1440.0f;
  config.c_l = 0.997f;
  config.c_r = 1.003f;
  config.f_lat = 1.004f;
  config.f_lon = 0.996f;
  const DiffDriveKinematics kinematics(config);
  const Geometry<double> g = geometry_in_force(Parameters<double>{
      0.048, 0.092, 0.0931, static_cast<double>(config.c_l), static_cast<double>(config.c_r),
      static_cast<double>(config.f_lat), static_cast<double>(config.f_lon)});
  EXPECT_NEAR(static_cast<double>(kinematics.left_diameter_m()), g.left_diameter, 1e-8);
  EXPECT_NEAR(static_cast<double>(kinematics.right_diameter_m()), g.right_diameter, 1e-8);
  EXPECT_NEAR(static_cast<double>(kinematics.wheelbase_m()), g.wheelbase, 1e-8);
  Odometry odometry;
  PoseOf<double> pose;
  const std::int32_t moves[][3] = {{7, 7, 600}, {-5, 5, 200}, {6, 9, 500}, {9, 4, 300}};
  for (const auto& move : moves) {
    for (int i = 0; i < move[2]; ++i) {
      const float left_m = static_cast<float>(move[0]) * kinematics.left_m_per_count();
      const float right_m = static_cast<float>(move[1]) * kinematics.right_m_per_count();
      odometry.update(left_m, right_m,
                      kinematics.wheelbase_for_rates_m(static_cast<float>(move[0]),
                                                       static_cast<float>(move[1])));
      const double left = move[0] * pi * g.left_diameter / 1440.0;
      const double right = move[1] * pi * g.right_diameter / 1440.0;
      advance(pose, left, right,
              wheelbase_for(g.wheelbase, g.wheelbase_arc, static_cast<double>(move[0]),
                            static_cast<double>(move[1])));
    }
  }
  const Pose end = odometry.pose();
  EXPECT_NEAR(static_cast<double>(end.x_m), pose.x, 5e-5);
  EXPECT_NEAR(static_cast<double>(end.y_m), pose.y, 5e-5);
  EXPECT_NEAR(static_cast<double>(end.theta_rad), std::remainder(pose.theta, 2.0 * pi), 1e-5);
}

}  // namespace
}  // namespace odocal::drive::model
