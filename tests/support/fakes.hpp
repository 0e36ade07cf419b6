#pragma once
/// @file
/// Hand-written HAL fakes that record into fixed storage.

#include <cstdint>

#include "odocal/hal/critical_section.hpp"
#include "odocal/hal/digital_output.hpp"
#include "odocal/hal/pwm_output.hpp"

namespace odocal::test {

/// Records the last duty and how many times it was set.
class FakePwm final : public hal::PwmOutput {
 public:
  float duty = -1.0f;
  std::uint32_t writes = 0;

 private:
  void do_set_duty(float d) override {
    duty = d;
    ++writes;
  }
};

/// Records the last level.
class FakeOutput final : public hal::DigitalOutput {
 public:
  bool level = false;
  std::uint32_t writes = 0;

 private:
  void do_set(bool l) override {
    level = l;
    ++writes;
  }
};

/// Counts nesting; single-threaded tests need no real exclusion.
class FakeCritical final : public hal::CriticalSection {
 public:
  int depth = 0;
  int max_depth = 0;
  std::uint32_t entries = 0;

 private:
  void do_enter() override {
    ++depth;
    ++entries;
    if (depth > max_depth)
      max_depth = depth;
  }
  void do_exit() override { --depth; }
};

}  // namespace odocal::test
