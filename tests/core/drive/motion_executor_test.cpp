#include "odocal/drive/motion_executor.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "test_plant.hpp"

namespace odocal::drive {
namespace {

using test::TestRig;

// The creep speed the profile ends at with the default robot (D 60 mm, b 150 mm, 1440 counts):
// 2 % of cruise, or one encoder edge per 20 ms on each wheel if that is faster.
double creep(double cruise, bool line) {
  const double wheel_radps = 2.0 * M_PI / (1440.0 * 0.02);
  const double edge_limited = line ? wheel_radps * 0.03 : wheel_radps * 0.06 / 0.15;
  return std::fmax(0.02 * cruise, edge_limited);
}

// How far a segment can overrun its odometry end: the first-order wheels (τ = 50 ms) coast about
// creep·τ after the end, plus one tick of travel at creep speed; half as much again for margin.
double overrun(double cruise, bool line) {
  return creep(cruise, line) * (0.05 + 0.001) * 1.5;
}

TEST(Paths, ReadyMadePathsHaveTheirShapes) {
  const Path cw = make_umbmark_square(true, 4.0f);
  ASSERT_EQ(cw.count, 8u);
  EXPECT_EQ(cw.id, PathId::umbmark_cw);
  EXPECT_FLOAT_EQ(cw.segments[0].distance_m, 4.0f);
  EXPECT_NEAR(cw.segments[1].angle_rad, -M_PI / 2, 1e-6);
  const Path ccw = make_umbmark_square(false, 4.0f);
  EXPECT_NEAR(ccw.segments[1].angle_rad, M_PI / 2, 1e-6);
  EXPECT_EQ(make_umbmark_square(true, 0.0f).count, 0u);
  EXPECT_EQ(make_umbmark_square(true, NAN).count, 0u);
  EXPECT_EQ(make_line(1.5f).count, 1u);
  EXPECT_EQ(make_line(-1.0f).count, 0u);

  // The unseen path, integrated ideally, ends at (0, 1.6 m) facing 180°.
  const Path unseen = make_unseen_path();
  double x = 0, y = 0, th = 0;
  for (int i = 0; i < unseen.count; ++i) {
    const Segment& s = unseen.segments[i];
    if (s.distance_m != 0 && s.angle_rad == 0) {
      x += s.distance_m * std::cos(th);
      y += s.distance_m * std::sin(th);
    } else if (s.distance_m == 0) {
      th += s.angle_rad;
    } else {
      const double r = s.distance_m / s.angle_rad;
      x += r * (std::sin(th + s.angle_rad) - std::sin(th));
      y += -r * (std::cos(th + s.angle_rad) - std::cos(th));
      th += s.angle_rad;
    }
  }
  EXPECT_NEAR(x, 0.0, 1e-5);
  EXPECT_NEAR(y, 1.6, 1e-5);
  EXPECT_NEAR(std::fabs(std::remainder(th, 2 * M_PI)), M_PI, 1e-5);
}

TEST(MotionExecutor, LineEndsOnOdometryAtItsLength) {
  TestRig rig;
  ASSERT_TRUE(rig.loop.run(make_line(1.0f)));
  const double t = rig.run_until_idle(20.0);
  EXPECT_LT(t, 1.0 / 0.2 + 2.0);
  EXPECT_NEAR(rig.loop.pose().x_m, 1.0, overrun(0.2, true) + 1e-3);
  EXPECT_GE(rig.loop.pose().x_m, 1.0f);
}

class SquareTest : public testing::TestWithParam<bool> {};

TEST_P(SquareTest, UmbmarkSquareClosesOnItselfInOdometry) {
  const bool clockwise = GetParam();
  TestRig rig;
  ASSERT_TRUE(rig.loop.run(make_umbmark_square(clockwise, 1.0f)));
  rig.run_until_idle(60.0);
  ASSERT_EQ(rig.loop.status().mode, Mode::idle);
  const Pose p = rig.loop.pose();
  // Headings are planned from the path's start: what one turn overruns the next turn and the
  // legs' steering make good, so the end heading is off by at most the last turn's overrun. A
  // leg that starts off its heading by δ (at most one turn's overrun) steers it away over about
  // kSteerDistance (0.2 m): δ · 0.2 m of sideways offset each, twice that for the wheels' lag.
  const double turn_err = overrun(1.5, false);
  const double leg_err = overrun(0.2, true);
  EXPECT_LE(std::fabs(p.theta_rad), turn_err);
  EXPECT_LE(std::hypot(p.x_m, p.y_m), 4 * leg_err + 4 * turn_err * 0.2 * 2);
  // The ideal true robot did the same.
  EXPECT_NEAR(rig.robot.x, p.x_m, 2e-3);
  EXPECT_NEAR(rig.robot.y, p.y_m, 2e-3);
}

INSTANTIATE_TEST_SUITE_P(BothDirections, SquareTest, testing::Values(true, false));

TEST(MotionExecutor, UnseenPathEndsWhereItsGeometrySays) {
  TestRig rig;
  ASSERT_TRUE(rig.loop.run(make_unseen_path()));
  rig.run_until_idle(120.0);
  ASSERT_EQ(rig.loop.status().mode, Mode::idle);
  const Pose p = rig.loop.pose();
  // 8 legs and arcs, 7 turns: each leg's length may overrun, each turn's heading error is steered
  // away within about 0.2 m (twice that for the wheels' lag), and the arc ends by distance on its
  // planned heading.
  const double bound = 8 * overrun(0.2, true) + 7 * overrun(1.5, false) * 0.2 * 2;
  EXPECT_NEAR(p.x_m, 0.0, bound);
  EXPECT_NEAR(p.y_m, 1.6, bound);
  EXPECT_NEAR(std::fabs(p.theta_rad), M_PI, overrun(1.5, false));
}

TEST(MotionExecutor, TurnsDoNotAddUpTheirOverruns) {
  // Twelve quarter turns in place: each ends when odometry says it is covered and overruns by up
  // to `overrun`; planned from the path's start, the twelfth ends within one overrun of 3 turns.
  TestRig rig;
  Path turns;
  for (int i = 0; i < 12; ++i) {
    turns.push(Segment{0.0f, static_cast<float>(M_PI) / 2.0f});
  }
  ASSERT_TRUE(rig.loop.run(turns));
  rig.run_until_idle(60.0);
  ASSERT_EQ(rig.loop.status().mode, Mode::idle);
  const double turned = rig.loop.pose().theta_rad;  // wrapped to [-pi, pi]
  EXPECT_NEAR(std::remainder(turned, 2 * M_PI), 0.0, overrun(1.5, false));
  EXPECT_GE(std::remainder(turned, 2 * M_PI), 0.0);  // the last turn ends on or past its goal
}

TEST(MotionExecutor, LineSteersAwayAHeadingErrorItStartsWith) {
  // A quarter turn overruns by up to `overrun`; the line after it holds the planned heading (90°),
  // so it ends on that heading, and its sideways offset is the steering's, about δ · 0.2 m.
  TestRig rig;
  Path path;
  path.push(Segment{0.0f, static_cast<float>(M_PI) / 2.0f});
  path.push(Segment{1.0f, 0.0f});
  ASSERT_TRUE(rig.loop.run(path));
  rig.run_until_idle(30.0);
  const Pose p = rig.loop.pose();
  const double delta = overrun(1.5, false);
  EXPECT_NEAR(p.theta_rad, M_PI / 2, 0.1 * delta);
  EXPECT_NEAR(p.x_m, 0.0, delta * 0.2 * 2);
  EXPECT_NEAR(p.y_m, 1.0, overrun(0.2, true) + 1e-3);
}

TEST(MotionExecutor, ArcFollowsItsRadius) {
  TestRig rig;
  Path arc;
  arc.push(Segment{0.5f * static_cast<float>(M_PI), static_cast<float>(M_PI) / 2.0f});  // R 1 m
  ASSERT_TRUE(rig.loop.run(arc));
  rig.run_until_idle(20.0);
  const Pose p = rig.loop.pose();
  EXPECT_NEAR(p.x_m, 1.0, 0.01);
  EXPECT_NEAR(p.y_m, 1.0, 0.01);
  EXPECT_NEAR(p.theta_rad, M_PI / 2, 0.01);
}

}  // namespace
}  // namespace odocal::drive
