#pragma once
// A minimal two-wheel plant for the drive-stack tests: first-order motors, exact encoder edges,
// rigid-body motion by exact arcs. (The full plant with slip, bumps and a DC-motor model is in
// hal/sim; this one is small enough to reason about in a test.)

#include <cmath>
#include <cstdint>

#include "fakes.hpp"
#include "odocal/drive/control_loop.hpp"

namespace odocal::test {

/// One wheel: dω/dt = (ω_free·duty − ω)/τ, angle integrated, edges emitted as the angle crosses
/// each count boundary, in quadrature order.
class TestWheel {
 public:
  double free_speed_radps = 30.0;  // at |duty| = 1 (so kff = 1/30 is the ideal feed-forward)
  double tau_s = 0.05;
  double counts_per_rev = 1440.0;
  bool stalled = false;

  FakePwm pwm;
  FakeOutput forward;

  double omega = 0.0;  // rad/s
  double angle = 0.0;  // rad

  /// Advances by dt, ending at `now_us`, and feeds every crossed edge to `decoder`, stamped with
  /// the instant the shaft crossed it (interpolated in the step). Returns the angle moved, rad.
  double step(double dt, std::uint32_t now_us, drive::QuadratureDecoder& decoder) {
    const double duty = (forward.level ? 1.0 : -1.0) * (pwm.duty < 0.0f ? 0.0 : pwm.duty);
    omega += (free_speed_radps * duty - omega) * dt / tau_s;
    if (stalled) {
      omega = 0.0;
    }
    const double before = angle;
    angle += omega * dt;
    const auto count_of = [this](double a) {
      return static_cast<std::int64_t>(std::floor(a / (2.0 * M_PI) * counts_per_rev));
    };
    std::int64_t c = count_of(before);
    const std::int64_t target = count_of(angle);
    while (c != target) {
      const bool up = target > c;
      c += up ? 1 : -1;
      const auto phase = static_cast<int>(((c % 4) + 4) % 4);
      // The boundary crossed: c when moving up, c + 1 when moving down.
      const double boundary = static_cast<double>(up ? c : c + 1) * 2.0 * M_PI / counts_per_rev;
      const double fraction = (angle - boundary) / (angle - before);  // of the step still to go
      const auto stamp = now_us - static_cast<std::uint32_t>(std::llround(fraction * dt * 1e6));
      // Forward sequence of (A, B): 00, 10, 11, 01.
      static constexpr bool kA[4] = {false, true, true, false};
      static constexpr bool kB[4] = {false, false, true, true};
      decoder.on_edge(kA[phase], kB[phase], stamp);
    }
    return angle - before;
  }
};

/// The true robot: its own wheel diameters and wheelbase, pose by exact arcs.
struct TestRobot {
  double left_diameter_m = 0.06;
  double right_diameter_m = 0.06;
  double wheelbase_m = 0.15;
  /// Arc wheelbase (0: one wheelbase): the wheelbase in force is b + w·(b_arc − b), with w the
  /// forward share of the wheels' rotation, |l + r| / (|l + r| + |r − l|), as odocal fit models it.
  double wheelbase_arc_m = 0.0;
  double x = 0.0, y = 0.0, theta = 0.0;

  void move(double left_rad, double right_rad) {
    const double dl = left_rad * left_diameter_m / 2.0;
    const double dr = right_rad * right_diameter_m / 2.0;
    const double ds = 0.5 * (dl + dr);
    double b = wheelbase_m;
    if (wheelbase_arc_m != 0.0) {
      const double forward = std::fabs(left_rad + right_rad);
      const double sum = forward + std::fabs(right_rad - left_rad);
      b += sum > 0.0 ? forward / sum * (wheelbase_arc_m - wheelbase_m) : 0.0;
    }
    const double dtheta = (dr - dl) / b;
    const double chord = std::fabs(dtheta) < 1e-12 ? ds : ds * std::sin(dtheta / 2) / (dtheta / 2);
    x += chord * std::cos(theta + dtheta / 2);
    y += chord * std::sin(theta + dtheta / 2);
    theta += dtheta;
  }
};

/// A control loop wired to two test wheels on a true robot, stepped at a physics rate.
class TestRig {
 public:
  explicit TestRig(const drive::DriveConfig& config = drive::DriveConfig{})
      : loop(drive::MotorChannel{left.pwm, left.forward},
             drive::MotorChannel{right.pwm, right.forward}, critical, config) {
    left.counts_per_rev = config.counts_per_rev;
    right.counts_per_rev = config.counts_per_rev;
  }

  /// Runs for `seconds` of robot time: physics every 50 µs, the tick at the configured rate.
  void run_for(double seconds) {
    const auto steps = static_cast<std::int64_t>(std::llround(seconds / kPhysicsDt));
    const auto tick_every = static_cast<std::int64_t>(
        std::llround(1.0 / (static_cast<double>(loop.config().control_hz) * kPhysicsDt)));
    for (std::int64_t i = 0; i < steps; ++i) {
      time_us += static_cast<std::uint32_t>(kPhysicsDt * 1e6);
      const double l = left.step(kPhysicsDt, time_us, loop.left_decoder());
      const double r = right.step(kPhysicsDt, time_us, loop.right_decoder());
      robot.move(l, r);
      if (++step_count % tick_every == 0) {
        loop.tick(time_us);
      }
    }
  }

  /// Runs until the loop is idle (or `limit_s` passes); returns the time taken, s.
  double run_until_idle(double limit_s) {
    double t = 0.0;
    run_for(0.01);
    t += 0.01;
    while (loop.status().mode != drive::Mode::idle && t < limit_s) {
      run_for(0.01);
      t += 0.01;
    }
    return t;
  }

  static constexpr double kPhysicsDt = 50e-6;
  TestWheel left;
  TestWheel right;
  TestRobot robot;
  FakeCritical critical;
  std::uint32_t time_us = 0xFFF00000u;  // starts near the wrap on purpose
  std::int64_t step_count = 0;
  drive::ControlLoop loop;
};

}  // namespace odocal::test
