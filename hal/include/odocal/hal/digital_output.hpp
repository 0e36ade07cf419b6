#pragma once
/// @file
/// Digital output line (motor direction, driver enable).

namespace odocal::hal {

/// A push-pull output line.
class DigitalOutput {
 public:
  /// Drives the line high (true) or low (false). ISR-safe.
  void set(bool level) { do_set(level); }

 protected:
  ~DigitalOutput() = default;

 private:
  virtual void do_set(bool level) = 0;
};

}  // namespace odocal::hal
