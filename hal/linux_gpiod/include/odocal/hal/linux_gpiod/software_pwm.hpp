#pragma once
/// @file
/// PWM bit-banged on a GPIO line by a thread: the fallback when no hardware PWM is available.

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

#include "odocal/hal/linux_gpiod/gpio_output.hpp"
#include "odocal/hal/pwm_output.hpp"

namespace odocal::hal::linux_gpiod {

/// LOW PRECISION. A thread sleeps to absolute deadlines and toggles a GPIO line, so every edge
/// carries the scheduling latency of the thread (tens of microseconds with SCHED_FIFO, up to
/// milliseconds without), and each edge costs an ioctl. Keep the carrier low (50..500 Hz) and
/// expect duty resolution of roughly latency x frequency. Use a sysfs PWM channel when the board
/// has one.
class SoftwarePwm final : public hal::PwmOutput {
 public:
  /// Always true: lets status lines and logs say so.
  static constexpr bool low_precision = true;

  SoftwarePwm() = default;
  ~SoftwarePwm();
  SoftwarePwm(const SoftwarePwm&) = delete;
  SoftwarePwm& operator=(const SoftwarePwm&) = delete;

  /// Requests `pin` as an output and starts the carrier at `frequency_hz` (1..5000) with duty 0.
  /// `fifo_priority` 1..99 asks for SCHED_FIFO for the thread (0: do not). Set-up only.
  SetupResult open(ChipSet& chips, const LinePin& pin, std::uint32_t frequency_hz,
                   int fifo_priority, const char* consumer);

  /// Stops the thread, drives the line low and releases it. Safe to call twice.
  void close();

  /// The last duty set, [0, 1].
  float duty() const { return duty_.load(std::memory_order_relaxed); }
  /// Whether the thread got SCHED_FIFO. Valid once the thread has started.
  bool realtime() const { return realtime_.load(std::memory_order_relaxed); }
  /// The carrier frequency, Hz (0 when closed).
  std::uint32_t frequency_hz() const { return frequency_hz_; }

 private:
  void do_set_duty(float duty) override;
  void run(std::uint64_t period_ns, int fifo_priority);

  GpioOutput line_;
  std::thread thread_;
  std::uint32_t frequency_hz_ = 0u;
  std::atomic<bool> running_{false};
  std::atomic<bool> realtime_{false};
  std::atomic<float> duty_{0.0f};
};

}  // namespace odocal::hal::linux_gpiod
