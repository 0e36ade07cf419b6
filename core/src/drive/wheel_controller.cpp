#include "odocal/drive/wheel_controller.hpp"

#include <cmath>

namespace odocal::drive {
namespace {
float clamp(float value, float limit) {
  if (value > limit) {
    return limit;
  }
  if (value < -limit) {
    return -limit;
  }
  return value;
}
}  // namespace

void WheelController::set_gains(const WheelGains& gains) {
  // Bumpless: move the integrator so the output of the last step is unchanged by the new
  // proportional and feed-forward terms (the integral term is already in duty units).
  integrator_ += (gains_.kp - gains.kp) * last_error_ + (gains_.kff - gains.kff) * last_setpoint_;
  gains_ = gains;
  integrator_ = clamp(integrator_, gains_.max_duty);
}

float WheelController::update(float setpoint_radps, float measured_radps, float dt_s) {
  if (!std::isfinite(setpoint_radps)) {
    setpoint_radps = 0.0f;
  }
  if (!std::isfinite(measured_radps)) {
    measured_radps = setpoint_radps;  // no information: no proportional action
  }
  const float error = setpoint_radps - measured_radps;
  const float base = gains_.kff * setpoint_radps + gains_.kp * error;
  if (dt_s > 0.0f && dt_s < 1.0f) {
    const float candidate = integrator_ + gains_.ki * error * dt_s;
    const float output = base + candidate;
    // Conditional integration: never grow the integrator further into saturation.
    const bool winding_up =
        (output > gains_.max_duty && error > 0.0f) || (output < -gains_.max_duty && error < 0.0f);
    if (!winding_up) {
      integrator_ = clamp(candidate, gains_.max_duty);
    }
  }
  const float raw = base + integrator_;
  const float duty = clamp(raw, gains_.max_duty);
  saturated_ = duty != raw;
  last_error_ = error;
  last_setpoint_ = setpoint_radps;
  return duty;
}

}  // namespace odocal::drive
