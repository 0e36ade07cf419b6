#pragma once
/// @file
/// Everything odocal-linux wires from its configuration: the chips, the direction and enable
/// lines, the two PWM outputs (sysfs, else the software fallback), the control loop, the encoder
/// event thread and the control tick. Used by main.cpp and by the kernel GPIO VM test.

#include <cstdint>
#include <memory>
#include <string>

#include "config.hpp"
#include "odocal/drive/control_loop.hpp"
#include "odocal/hal/linux_gpiod/encoder_events.hpp"
#include "odocal/hal/linux_gpiod/gpio_output.hpp"
#include "odocal/hal/linux_gpiod/mutex_critical_section.hpp"
#include "odocal/hal/linux_gpiod/posix_clock.hpp"
#include "odocal/hal/linux_gpiod/software_pwm.hpp"
#include "odocal/hal/linux_gpiod/sysfs_pwm.hpp"
#include "odocal/hal/linux_gpiod/timerfd_tick.hpp"

namespace odocal::linux_target {

/// The consumer name the lines are requested under.
constexpr const char* kConsumer = "odocal";

/// One motor's PWM: the sysfs channel when it works, else the software fallback.
struct MotorPwm {
  hal::linux_gpiod::SysfsPwm sysfs;
  hal::linux_gpiod::SoftwarePwm soft;
  hal::PwmOutput* active = nullptr;
  std::string description;

  /// Opens the sysfs channel of `spec`, or its software-PWM line when that fails (saying so on
  /// stderr). `role` names the output in messages.
  hal::linux_gpiod::SetupResult open(hal::linux_gpiod::ChipSet& chips, const PwmSpec& spec,
                                     const LinuxConfig& config, const char* role);
};

/// The robot, in construction order. `open` requests every line and channel and builds the loop
/// and the encoder thread (not started); `start` starts the encoder thread and the tick.
struct Robot {
  hal::linux_gpiod::ChipSet chips;
  hal::linux_gpiod::MutexCriticalSection critical;
  hal::linux_gpiod::GpioOutput left_dir;
  hal::linux_gpiod::GpioOutput right_dir;
  hal::linux_gpiod::GpioOutput enable;
  MotorPwm left_pwm;
  MotorPwm right_pwm;
  std::unique_ptr<drive::ControlLoop> loop;
  std::unique_ptr<hal::linux_gpiod::EncoderEvents> encoders;
  std::unique_ptr<hal::linux_gpiod::TimerfdTick> tick;
  hal::linux_gpiod::PosixMonotonicClock clock;

  /// The control tick (timerfd thread): one loop tick, timed.
  static void on_tick(void* context);

  /// Requests the lines and channels of `config`. Fails naming the first that cannot be had.
  hal::linux_gpiod::SetupResult open(const LinuxConfig& config);

  /// Starts the encoder event thread, then the tick at `rate_hz`. After `open` succeeded.
  hal::linux_gpiod::SetupResult start(const LinuxConfig& config, std::uint32_t rate_hz);

  /// Stops the tick and the loop, disables the motors and releases the outputs and lines.
  void shut_down();
};

}  // namespace odocal::linux_target
