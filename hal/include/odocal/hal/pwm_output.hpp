#pragma once
/// @file
/// PWM output channel (one H-bridge input).

namespace odocal::hal {

/// A PWM channel at a fixed carrier frequency chosen by the backend.
class PwmOutput {
 public:
  /// Sets the duty cycle, a fraction in [0, 1]. Values outside are clamped; NaN means 0.
  /// ISR-safe (called from the control tick).
  void set_duty(float duty) {
    if (!(duty > 0.0f)) {
      duty = 0.0f;
    } else if (duty > 1.0f) {
      duty = 1.0f;
    }
    do_set_duty(duty);
  }

 protected:
  ~PwmOutput() = default;

 private:
  virtual void do_set_duty(float duty) = 0;
};

}  // namespace odocal::hal
