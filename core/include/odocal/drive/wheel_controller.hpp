#pragma once
/// @file
/// Wheel-velocity PI controller with feed-forward and anti-windup.

namespace odocal::drive {

/// Gains in physical units. Duty is the signed PWM fraction in [-1, 1].
struct WheelGains {
  float kp = 0.05f;       ///< duty per (rad/s) of speed error
  float ki = 1.0f;        ///< duty per rad of integrated speed error
  float kff = 0.033f;     ///< duty per (rad/s) of set-point
  float max_duty = 1.0f;  ///< output saturation, in (0, 1]
};

/// PI + feed-forward: duty = kff·sp + kp·e + I, with I += ki·e·dt.
///
/// Anti-windup by conditional integration (clamping): the integrator does not grow in the
/// direction that would push a saturated output further; it is also bounded to ±max_duty.
/// The integrator is stored in duty units, so a change of ki does not step the output
/// (bumpless), and `reset()` on enable starts from the feed-forward alone.
class WheelController {
 public:
  explicit WheelController(const WheelGains& gains = WheelGains{}) : gains_(gains) {}

  /// Replaces the gains without a step in the output.
  void set_gains(const WheelGains& gains);
  [[nodiscard]] const WheelGains& gains() const { return gains_; }

  /// Clears the integrator (call on enable and after a fault).
  void reset() {
    integrator_ = 0.0f;
    last_error_ = 0.0f;
    last_setpoint_ = 0.0f;
  }

  /// One step. @param setpoint_radps and @param measured_radps wheel speeds, rad/s;
  /// @param dt_s time since the previous step, s (<= 0 or non-finite: no integration).
  /// @return duty in [-max_duty, max_duty]. Tick context.
  float update(float setpoint_radps, float measured_radps, float dt_s);

  /// True when the last update saturated.
  [[nodiscard]] bool saturated() const { return saturated_; }
  [[nodiscard]] float integrator() const { return integrator_; }

 private:
  WheelGains gains_;
  float integrator_ = 0.0f;
  float last_error_ = 0.0f;     ///< rad/s, for bumpless gain changes
  float last_setpoint_ = 0.0f;  ///< rad/s
  bool saturated_ = false;
};

}  // namespace odocal::drive
