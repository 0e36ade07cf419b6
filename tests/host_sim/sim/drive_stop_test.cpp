// How a timed `drive` ends, against the plant's physics (hal/sim: J·dω/dt = (k/R)·V −
// (k²/R + c)·ω − τ_c·sign ω per wheel, tests/hal/sim/plant_test.cpp). "Stop" means the firmware
// brakes: each wheel's speed loop holds a zero set-point until that wheel is at rest, so the
// robot stops between the motors' full-reverse limit and the proportional-brake bound, instead
// of rolling out on the shorted windings alone (24.5 mm / 290 ms from 0.3 m/s before).

#include <gtest/gtest.h>

#include <cmath>

#include "odocal/drive/drive_config.hpp"
#include "odocal/host/sim_robot.hpp"

namespace odocal::host {
namespace {

RobotSpec quiet_spec() {
  RobotSpec spec = default_robot();
  spec.truth.slip_sigma = 0.0;
  spec.truth.bump_height_m = 0.0;
  return spec;
}

struct Stop {
  double speed_at_end_mps = 0.0;  ///< robot speed when the drive's time ran out
  double distance_m = 0.0;        ///< travelled after that
  double stopped_after_s = 0.0;   ///< until both wheels were at rest
  double drift_after_m = 0.0;     ///< moved in the second after coming to rest (creep)
};

enum class End { duration, stop, command_timeout };

Stop drive_and_end(double v_mps, End end) {
  SimulatedRobot robot(quiet_spec(), 1u);
  robot.tick_once();
  const std::uint32_t ms = end == End::duration ? 1500u : 0u;
  EXPECT_TRUE(robot.loop().drive(drive::Twist{static_cast<float>(v_mps), 0.0f}, ms));
  robot.tick_once();
  if (end == End::stop) {
    // At speed, then `stop` (before the 500 ms command timeout would end it).
    robot.run_until_ns(robot.plant().now_ns() + 400'000'000u);
    robot.loop().stop();
    robot.tick_once();
  }
  while (robot.loop().status().mode == drive::Mode::drive) {
    robot.tick_once();
  }
  Stop s;
  const sim::Plant& p = robot.plant();
  const double r = 0.25 * (p.model().left_diameter_m + p.model().right_diameter_m);
  s.speed_at_end_mps = 0.5 * (p.left().speed_radps() + p.right().speed_radps()) * r;
  const double start_m = p.distance_m();
  const double start_s = robot.simulated_s();
  std::int64_t peak_l = p.left().encoder_count();
  std::int64_t peak_r = p.right().encoder_count();
  const std::int64_t way = v_mps > 0.0 ? 1 : -1;
  while (p.left().speed_radps() != 0.0 || p.right().speed_radps() != 0.0) {
    robot.tick_once();
    // Braking never turns a wheel back (not even one encoder count).
    EXPECT_GE(way * p.left().encoder_count(), way * peak_l);
    EXPECT_GE(way * p.right().encoder_count(), way * peak_r);
    peak_l = way * p.left().encoder_count() > way * peak_l ? p.left().encoder_count() : peak_l;
    peak_r = way * p.right().encoder_count() > way * peak_r ? p.right().encoder_count() : peak_r;
    if (robot.simulated_s() - start_s > 3.0) {
      break;
    }
  }
  s.stopped_after_s = robot.simulated_s() - start_s;
  s.distance_m = p.distance_m() - start_m;
  const double rest_m = p.distance_m();
  robot.run_until_ns(p.now_ns() + 1'000'000'000u);
  s.drift_after_m = p.distance_m() - rest_m;
  return s;
}

// Distance a wheel spinning at w0 rolls with the terminals shorted (V = 0): dω/dt = −a·ω − f,
// a = (k²/R + c)/J, f = τ_c/J, stops at t* = ln(1 + a·w0/f)/a; angle = (w0 − f·t*)/a.
double shorted_stop_m(const sim::MotorModel& m, double w0, double r) {
  const double a = (m.k_v_per_radps * m.k_v_per_radps / m.resistance_ohm + m.viscous_nm_per_radps) /
                   m.inertia_kgm2;
  const double f = m.coulomb_nm / m.inertia_kgm2;
  const double t = std::log(1.0 + a * w0 / f) / a;
  return r * (w0 - f * t) / a;
}

// The shortest stop physics allows: full reverse supply, dω/dt = −a·ω − f − (k/R)·V/J.
double full_reverse_stop_m(const sim::MotorModel& m, double w0, double r) {
  const double a = (m.k_v_per_radps * m.k_v_per_radps / m.resistance_ohm + m.viscous_nm_per_radps) /
                   m.inertia_kgm2;
  const double f =
      (m.coulomb_nm + m.k_v_per_radps * m.supply_v / m.resistance_ohm) / m.inertia_kgm2;
  const double t = std::log(1.0 + a * w0 / f) / a;
  return r * (w0 - f * t) / a;
}

// The longest stop of a speed loop braking to zero: its proportional term alone drives
// V = −kp·ω·V_supply (below saturation), adding the damping b = (k/R)·kp·V_supply/J to the
// windings' a, and friction only shortens it: angle <= ω0/(a + b).
double proportional_brake_stop_m(const sim::MotorModel& m, double kp, double w0, double r) {
  const double a = (m.k_v_per_radps * m.k_v_per_radps / m.resistance_ohm + m.viscous_nm_per_radps) /
                   m.inertia_kgm2;
  const double b = m.k_v_per_radps / m.resistance_ohm * kp * m.supply_v / m.inertia_kgm2;
  return r * w0 / (a + b);
}

TEST(DriveStop, ATimedDriveBrakesToRestWithinThePhysicsOfTheMotors) {
  const sim::MotorModel m = quiet_spec().truth.left_motor;
  const double r =
      0.25 * (quiet_spec().truth.left_diameter_m + quiet_spec().truth.right_diameter_m);
  for (const double v : {0.1, 0.3, -0.3, 0.5}) {
    const Stop s = drive_and_end(v, End::duration);
    const double w0 = std::fabs(s.speed_at_end_mps) / r;
    const double shorted = shorted_stop_m(m, w0, r);
    const double fastest = full_reverse_stop_m(m, w0, r);
    const double kp = static_cast<double>(drive::DriveConfig{}.kp);
    // One control period (1 kHz) at full speed before the brake acts, then the P-brake bound.
    const double bound = proportional_brake_stop_m(m, kp, w0, r) + 1e-3 * std::fabs(v);
    EXPECT_LE(std::fabs(s.distance_m), bound) << "v=" << v;
    // Braking, not rolling out on the shorted windings (what a drive's end used to do).
    EXPECT_LT(std::fabs(s.distance_m), 0.5 * shorted) << "v=" << v;
    // No stop beats physics, and the robot does not back up.
    EXPECT_GE(std::fabs(s.distance_m), 0.9 * fastest) << "v=" << v;
    EXPECT_GE(s.distance_m * v, 0.0) << "v=" << v;
    // At rest it stays there: no creep from a wound-up integrator.
    EXPECT_NEAR(s.drift_after_m, 0.0, 1e-6) << "v=" << v;
    std::printf(
        "v=%.1f: speed at end %.3f m/s, stop %.2f mm in %.0f ms (shorted windings %.1f mm, "
        "full reverse %.2f mm)\n",
        v, s.speed_at_end_mps, s.distance_m * 1e3, s.stopped_after_s * 1e3, shorted * 1e3,
        fastest * 1e3);
  }
}

// `stop` during a drive, and a drive without a duration that no new `drive` renews within
// cmd_timeout_ms, end the same way: braking to rest.
TEST(DriveStop, StopAndTheCommandTimeoutBrakeToo) {
  const sim::MotorModel m = quiet_spec().truth.left_motor;
  const double r =
      0.25 * (quiet_spec().truth.left_diameter_m + quiet_spec().truth.right_diameter_m);
  const double kp = static_cast<double>(drive::DriveConfig{}.kp);
  for (const End end : {End::stop, End::command_timeout}) {
    const Stop s = drive_and_end(0.3, end);
    const double w0 = std::fabs(s.speed_at_end_mps) / r;
    EXPECT_NEAR(s.speed_at_end_mps, 0.3, 0.03);
    EXPECT_LE(s.distance_m, proportional_brake_stop_m(m, kp, w0, r) + 1e-3 * 0.3);
    EXPECT_GE(s.distance_m, 0.9 * full_reverse_stop_m(m, w0, r));
    EXPECT_NEAR(s.drift_after_m, 0.0, 1e-6);
  }
}

}  // namespace
}  // namespace odocal::host
