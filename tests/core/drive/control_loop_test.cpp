#include "odocal/drive/control_loop.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "alloc_counter.hpp"
#include "test_plant.hpp"

namespace odocal::drive {
namespace {

using test::TestRig;

TEST(ControlLoop, DriveForADurationMovesTheCommandedDistanceStraight) {
  TestRig rig;
  ASSERT_TRUE(rig.loop.drive(Twist{0.2f, 0.0f}, 1000u));
  rig.run_for(1.5);
  EXPECT_EQ(rig.loop.status().mode, Mode::idle);
  // 1 s at 0.2 m/s, less what the first-order wheels (τ = 50 ms) lag at start (≈ v·τ with the
  // feed-forward alone; the PI shortens it), plus their coast at the end (≈ v·τ).
  const Pose p = rig.loop.pose();
  EXPECT_NEAR(p.x_m, 0.2f, 0.2f * 0.05f * 1.2f);
  EXPECT_NEAR(p.y_m, 0.0f, 1e-3f);
  // Nominal robot = true robot here: belief and truth agree to the encoder resolution.
  EXPECT_NEAR(rig.robot.x, p.x_m, 1e-3);
  EXPECT_NEAR(rig.robot.theta, p.theta_rad, 2.0 * M_PI * 0.06 / 1440 / 0.15);
}

TEST(ControlLoop, WheelSpeedsTrackTheInverseKinematics) {
  TestRig rig;
  ASSERT_TRUE(rig.loop.drive(Twist{0.15f, 0.8f}, 0u));
  rig.run_for(0.4);
  const LoopStatus s = rig.loop.status();
  // After 0.4 s, eight time constants of the test plant's wheel (τ = 50 ms), the PI error left of
  // a 3-7 rad/s step is e^-8 of it, < 0.003 rad/s; the speed itself comes from edge times stamped
  // to 1 µs about 1 ms apart (1440 counts/rev at ~5 rad/s), 0.1 % or 0.007 rad/s. 0.05 rad/s is
  // five times both together.
  EXPECT_NEAR(s.left_radps, (2 * 0.15 - 0.15 * 0.8) / 0.06, 0.05);
  EXPECT_NEAR(s.right_radps, (2 * 0.15 + 0.15 * 0.8) / 0.06, 0.05);
}

TEST(ControlLoop, ADriveWithoutDurationStopsAfterTheCommandTimeout) {
  TestRig rig;
  ASSERT_TRUE(rig.loop.drive(Twist{0.2f, 0.0f}, 0u));
  rig.run_for(0.4);
  EXPECT_EQ(rig.loop.status().mode, Mode::drive);
  rig.run_for(0.2);  // cmd_timeout_ms = 500
  EXPECT_EQ(rig.loop.status().mode, Mode::idle);
  rig.run_for(0.5);
  EXPECT_NEAR(rig.left.omega, 0.0, 0.05);
  EXPECT_NEAR(rig.right.omega, 0.0, 0.05);
}

TEST(ControlLoop, RenewedDriveCommandsKeepItGoing) {
  TestRig rig;
  for (int i = 0; i < 5; ++i) {
    ASSERT_TRUE(rig.loop.drive(Twist{0.2f, 0.0f}, 0u));
    rig.run_for(0.3);
  }
  EXPECT_EQ(rig.loop.status().mode, Mode::drive);
}

TEST(ControlLoop, AHeldDriveIsNoTrialAndStopsAfterItsOwnTimeout) {
  // ROSArduinoBridge's `m`: held 2 s (longer than cmd_timeout_ms), then stopped; no trial, so no
  // `# done` on the console and no record.
  TestRig rig;
  const std::uint32_t trials_before = rig.loop.last_trial().number;
  ASSERT_TRUE(rig.loop.drive(Twist{0.2f, 0.0f}, 2000u, false));
  EXPECT_FALSE(rig.loop.status().trial_open);
  rig.run_for(1.9);
  EXPECT_EQ(rig.loop.status().mode, Mode::drive);
  EXPECT_FALSE(rig.loop.status().trial_open);
  rig.run_for(0.2);
  EXPECT_EQ(rig.loop.status().mode, Mode::idle);
  rig.run_for(0.5);
  EXPECT_NEAR(rig.left.omega, 0.0, 0.05);
  EXPECT_NEAR(rig.right.omega, 0.0, 0.05);
  EXPECT_EQ(rig.loop.last_trial().number, trials_before);
  // A timed drive after it is a trial again.
  ASSERT_TRUE(rig.loop.drive(Twist{0.1f, 0.0f}, 200u));
  EXPECT_TRUE(rig.loop.status().trial_open);
}

TEST(ControlLoop, IllegalTransitionsTripAStickyFaultThatParksTheMotors) {
  TestRig rig;
  ASSERT_TRUE(rig.loop.drive(Twist{0.2f, 0.0f}, 0u));
  rig.run_for(0.2);
  for (int i = 0; i < 20; ++i) {  // both channels flipping together: missed edges
    rig.loop.left_decoder().on_edge(i % 2 == 0, i % 2 == 0, rig.time_us);
  }
  rig.run_for(0.01);
  LoopStatus s = rig.loop.status();
  EXPECT_EQ(s.mode, Mode::fault);
  EXPECT_NE(s.faults & fault_encoder_left, 0);
  EXPECT_FLOAT_EQ(rig.left.pwm.duty, 0.0f);
  EXPECT_FLOAT_EQ(rig.right.pwm.duty, 0.0f);
  EXPECT_FALSE(rig.loop.drive(Twist{0.2f, 0.0f}, 0u));  // refused while faulted
  rig.run_for(0.5);
  EXPECT_EQ(rig.loop.status().mode, Mode::fault);  // sticky
  rig.loop.stop();                                 // acknowledges
  rig.run_for(0.01);
  s = rig.loop.status();
  EXPECT_EQ(s.faults, fault_none);
  EXPECT_EQ(s.mode, Mode::idle);
  EXPECT_TRUE(rig.loop.drive(Twist{0.1f, 0.0f}, 100u));
}

TEST(ControlLoop, AStalledWheelTripsTheStallFault) {
  TestRig rig;
  rig.right.stalled = true;
  ASSERT_TRUE(rig.loop.drive(Twist{0.2f, 0.0f}, 0u));
  for (int i = 0; i < 3; ++i) {
    rig.run_for(0.2);
    (void)rig.loop.drive(Twist{0.2f, 0.0f}, 0u);
  }
  const LoopStatus s = rig.loop.status();
  EXPECT_EQ(s.mode, Mode::fault);
  EXPECT_NE(s.faults & fault_stall_right, 0);
  EXPECT_EQ(s.faults & fault_stall_left, 0);
  EXPECT_FLOAT_EQ(rig.right.pwm.duty, 0.0f);
}

TEST(ControlLoop, InvalidConfigurationIsRefusedAndChangesNothing) {
  TestRig rig;
  DriveConfig bad;
  bad.c_l = NAN;
  EXPECT_FALSE(rig.loop.configure(bad));
  bad = DriveConfig{};
  bad.wheelbase_mm = -3.0f;
  EXPECT_FALSE(rig.loop.configure(bad));
  EXPECT_FLOAT_EQ(rig.loop.config().wheelbase_mm, DriveConfig{}.wheelbase_mm);
  DriveConfig good;
  good.c_l = 1.01f;
  EXPECT_TRUE(rig.loop.configure(good));
  EXPECT_FLOAT_EQ(rig.loop.config().c_l, 1.01f);
}

TEST(ControlLoop, TheTickNeverAllocatesAndTakesShortCriticalSections) {
  TestRig rig;
  ASSERT_TRUE(rig.loop.run(make_umbmark_square(true, 0.5f)));
  test::AllocationWatch watch;
  rig.run_for(2.0);
  EXPECT_EQ(watch.allocations(), 0u);
  EXPECT_EQ(rig.critical.depth, 0);
  EXPECT_EQ(rig.critical.max_depth, 1);
}

TEST(ControlLoop, StopHaltsAPathAtOnce) {
  TestRig rig;
  ASSERT_TRUE(rig.loop.run(make_line(2.0f)));
  rig.run_for(1.0);
  EXPECT_EQ(rig.loop.status().mode, Mode::path);
  EXPECT_EQ(rig.loop.status().path, PathId::line);
  rig.loop.stop();
  rig.run_for(0.5);
  EXPECT_EQ(rig.loop.status().mode, Mode::idle);
  // At rest 0.5 s after the stop (ten wheel time constants; the brake holds it at zero speed).
  // Before the stop, 1 s of the line: 0.4 s accelerating at 0.5 m/s² to 0.2 m/s (0.04 m), 0.6 s
  // at 0.2 m/s (0.12 m), then the coast, 0.2 m/s · 50 ms = 0.01 m: 0.17 m; below 0.2 m with a
  // tick's margin of error to spare, where a path that kept going would be at 0.26 m.
  EXPECT_NEAR(rig.left.omega, 0.0, 0.05);
  EXPECT_LT(rig.loop.pose().x_m, 0.2f);
}

TEST(ControlLoop, ACommandNotYetTakenByATickReadsAsTaken) {
  // A console reads `status` right after `run` or `drive`, possibly before the next tick: the
  // reply must not say idle for a motion it has just accepted (nor a fault `stop` acknowledged).
  TestRig rig;
  rig.run_for(0.01);
  ASSERT_TRUE(rig.loop.run(make_line(1.0f)));
  LoopStatus s = rig.loop.status();
  EXPECT_EQ(s.mode, Mode::path);
  EXPECT_EQ(s.path, PathId::line);
  EXPECT_EQ(s.segment, 0u);
  EXPECT_TRUE(s.trial_open);
  rig.run_for(0.3);
  EXPECT_EQ(rig.loop.status().mode, Mode::path);
  ASSERT_GT(rig.loop.pose().x_m, 0.01f);

  rig.loop.reset_pose();  // pending: the pose reads as the one it will be
  EXPECT_EQ(rig.loop.pose().x_m, 0.0f);
  EXPECT_EQ(rig.loop.pose().theta_rad, 0.0f);

  rig.loop.stop();
  s = rig.loop.status();
  EXPECT_EQ(s.mode, Mode::idle);
  EXPECT_EQ(s.path, PathId::none);
  EXPECT_FALSE(s.trial_open);
  rig.run_for(0.5);
  EXPECT_EQ(rig.loop.status().mode, Mode::idle);

  ASSERT_TRUE(rig.loop.drive(Twist{0.1f, 0.0f}, 200u));
  s = rig.loop.status();
  EXPECT_EQ(s.mode, Mode::drive);
  EXPECT_TRUE(s.trial_open);
  rig.run_for(0.05);
  EXPECT_EQ(rig.loop.status().mode, Mode::drive);
  rig.run_for(1.0);
  s = rig.loop.status();
  EXPECT_EQ(s.mode, Mode::idle);
  EXPECT_FALSE(s.trial_open);
}

// A robot whose wheelbase is 150 mm turning in place and 153 mm on a straight line (the blend
// b + w·(b_arc − b) between), told so with wheelbase_arc_mm.
DriveConfig arc_config(float arc_mm) {
  DriveConfig c;
  c.wheelbase_arc_mm = arc_mm;
  return c;
}

// Heading resolution of the odometry: one count of one wheel, 2π·(D/2)/counts/b.
constexpr double kCountHeading_rad = 2.0 * M_PI * 0.03 / 1440.0 / 0.150;

TEST(ControlLoop, AnArcWheelbaseTurnsAndIntegratesWithTheBlend) {
  // v = 0.15 m/s, ω = 0.8 rad/s: an arc of R = 187.5 mm, w = R/(R + b_w/2) = 0.711 and
  // b_w = 152.13 mm. Told one wheelbase (150 mm) the robot turns 1.4 % slower than commanded and
  // its odometry overstates the heading by as much; told both, neither.
  double told_one_rate = 0.0;
  double told_one_error = 0.0;
  for (const float arc_mm : {0.0f, 153.0f}) {
    TestRig rig(arc_config(arc_mm));
    rig.robot.wheelbase_arc_m = 0.153;
    ASSERT_TRUE(rig.loop.drive(Twist{0.15f, 0.8f}, 2000u));
    rig.run_for(0.6);  // past the wheels' start (τ = 50 ms)
    const double theta0 = rig.robot.theta;
    rig.run_for(1.0);
    const double rate = rig.robot.theta - theta0;  // rad/s, over one steady second
    rig.run_for(1.0);                              // ends the drive, brakes to rest
    ASSERT_EQ(rig.loop.status().mode, Mode::idle);
    const double error = rig.loop.pose().theta_rad - rig.robot.theta;  // |θ| < π here
    if (arc_mm == 0.0f) {
      told_one_rate = rate;
      told_one_error = error;
    } else {
      // The wheel loops track their set-points (PI, exact M/T speeds at constant speed): the
      // commanded turn rate to 0.25 %, against the 1.4 % of the one-wheelbase robot.
      EXPECT_NEAR(rate, 0.8, 0.002);
      // Odometry and truth agree to the encoder's resolution (a few counts over the run).
      EXPECT_NEAR(error, 0.0, 3.0 * kCountHeading_rad);
    }
  }
  const double b_w = 0.150 + 0.003 * 0.1875 / (0.1875 + 0.0761);
  EXPECT_NEAR(told_one_rate, 0.8 * 0.150 / b_w, 0.002);
  // About 2 rad turned, each overstated by (b_w − b)/b_w = 1.4 %.
  EXPECT_GT(std::fabs(told_one_error), 10.0 * kCountHeading_rad);
}

TEST(ControlLoop, ATurnInPlaceWithAnArcWheelbaseUsesTheTurnWheelbase) {
  TestRig rig(arc_config(153.0f));
  rig.robot.wheelbase_arc_m = 0.153;
  ASSERT_TRUE(rig.loop.drive(Twist{0.0f, 1.5f}, 1000u));
  rig.run_for(0.5);
  const double theta0 = rig.robot.theta;
  rig.run_for(0.4);
  EXPECT_NEAR((rig.robot.theta - theta0) / 0.4, 1.5, 0.004);
  rig.run_for(1.0);
  EXPECT_NEAR(rig.loop.pose().theta_rad - rig.robot.theta, 0.0, 3.0 * kCountHeading_rad);
}

// wiring_fix swaps and inverts what the loop drives, once, when the configuration is taken.
TEST(ControlLoop, WiringFixSwapsAndInvertsTheOutputs) {
  TestRig rig;
  DriveConfig config;
  config.wiring_fix = swap_motors | invert_left_motor;
  ASSERT_TRUE(rig.loop.configure(config));
  // A turn in place to the left: the left set-point is backwards, the right forward.
  ASSERT_TRUE(rig.loop.drive(Twist{0.0f, 1.0f}, 0u));
  rig.run_for(0.003);
  const LoopStatus s = rig.loop.status();
  ASSERT_LT(s.left_duty, 0.0f);
  ASSERT_GT(s.right_duty, 0.0f);
  // The left duty goes to the right connector, its direction line inverted (backwards reads
  // high); the right duty to the left connector as it is.
  EXPECT_NEAR(rig.right.pwm.duty, -s.left_duty, 1e-6f);
  EXPECT_TRUE(rig.right.forward.level);
  EXPECT_NEAR(rig.left.pwm.duty, s.right_duty, 1e-6f);
  EXPECT_TRUE(rig.left.forward.level);
}

}  // namespace
}  // namespace odocal::drive
