#include "odocal/drive/wheel_controller.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace odocal::drive {
namespace {

// First-order wheel: dω/dt = (ω_free·duty − ω − drag)/τ. With kff = 1/ω_free the feed-forward
// alone is exact when drag = 0.
struct Motor {
  double free_radps = 30.0;
  double tau_s = 0.05;
  double drag_radps = 0.0;  // a constant load, in rad/s of lost speed
  double omega = 0.0;
  bool stalled = false;
  void step(double duty, double dt) {
    omega += (free_radps * duty - omega - drag_radps) * dt / tau_s;
    if (stalled)
      omega = 0.0;
  }
};

WheelGains default_gains() {
  WheelGains g;
  g.kp = 0.05f;
  g.ki = 1.0f;
  g.kff = 1.0f / 30.0f;
  return g;
}

TEST(WheelController, StepResponseReachesTheSetPointDespiteALoad) {
  WheelController controller(default_gains());
  Motor motor;
  motor.drag_radps = 3.0;  // 10 % of full speed lost to friction: only the integrator removes it
  const double dt = 1e-3;
  for (int i = 0; i < 3000; ++i) {
    const float duty = controller.update(10.0f, static_cast<float>(motor.omega), 1e-3f);
    motor.step(duty, dt);
  }
  EXPECT_NEAR(motor.omega, 10.0, 1e-3);
  // In steady state the integrator carries exactly the load: drag / ω_free in duty.
  EXPECT_NEAR(controller.integrator(), 3.0 / 30.0, 1e-3);
}

TEST(WheelController, SaturatesAtMaxDuty) {
  WheelGains g = default_gains();
  g.max_duty = 0.8f;
  WheelController controller(g);
  const float duty = controller.update(100.0f, 0.0f, 1e-3f);
  EXPECT_FLOAT_EQ(duty, 0.8f);
  EXPECT_TRUE(controller.saturated());
  EXPECT_FLOAT_EQ(controller.update(-100.0f, 0.0f, 1e-3f), -0.8f);
}

TEST(WheelController, RecoversFromAStallWithoutWindupOvershoot) {
  WheelController controller(default_gains());
  Motor motor;
  motor.stalled = true;
  const double dt = 1e-3;
  for (int i = 0; i < 2000; ++i) {  // 2 s held against a wall at a 20 rad/s set-point
    motor.step(controller.update(20.0f, static_cast<float>(motor.omega), 1e-3f), dt);
  }
  // Output saturated the whole time: the integrator must not have grown into it.
  EXPECT_LE(controller.integrator(), 1.0f - (20.0f / 30.0f) + 1e-6f);
  motor.stalled = false;
  double peak = 0.0;
  for (int i = 0; i < 2000; ++i) {
    motor.step(controller.update(20.0f, static_cast<float>(motor.omega), 1e-3f), dt);
    peak = std::fmax(peak, motor.omega);
  }
  // A first-order plant under PI+FF without windup overshoots by little: allow 5 %.
  EXPECT_LT(peak, 21.0);
  EXPECT_NEAR(motor.omega, 20.0, 1e-2);
}

TEST(WheelController, GainChangeIsBumpless) {
  WheelController controller(default_gains());
  float duty = 0.0f;
  for (int i = 0; i < 50; ++i)
    duty = controller.update(10.0f, 8.0f, 1e-3f);
  WheelGains g = default_gains();
  g.kp = 0.2f;
  g.kff = 0.04f;
  controller.set_gains(g);
  // Same inputs, zero time step: the output is where it was.
  EXPECT_NEAR(controller.update(10.0f, 8.0f, 0.0f), duty, 1e-6f);
}

TEST(WheelController, ResetStartsFromFeedForward) {
  WheelController controller(default_gains());
  for (int i = 0; i < 100; ++i)
    (void)controller.update(10.0f, 5.0f, 1e-3f);
  controller.reset();
  EXPECT_NEAR(controller.update(6.0f, 6.0f, 0.0f), 6.0f / 30.0f, 1e-6f);
}

TEST(WheelController, NonFiniteInputsGiveAFiniteBoundedOutput) {
  WheelController controller(default_gains());
  const float d1 = controller.update(NAN, 0.0f, 1e-3f);
  const float d2 = controller.update(5.0f, INFINITY, 1e-3f);
  const float d3 = controller.update(5.0f, 0.0f, NAN);
  for (float d : {d1, d2, d3}) {
    EXPECT_TRUE(std::isfinite(d));
    EXPECT_LE(std::fabs(d), 1.0f);
  }
}

}  // namespace
}  // namespace odocal::drive
