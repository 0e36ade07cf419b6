#include "odocal/hal/linux_gpiod/software_pwm.hpp"

#include <time.h>

#include "odocal/hal/linux_gpiod/posix_clock.hpp"

namespace odocal::hal::linux_gpiod {
namespace {

void sleep_until(std::uint64_t deadline_ns) {
  timespec when{};
  when.tv_sec = static_cast<time_t>(deadline_ns / 1000000000u);
  when.tv_nsec = static_cast<long>(deadline_ns % 1000000000u);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &when, nullptr) != 0) {
  }
}

}  // namespace

SoftwarePwm::~SoftwarePwm() {
  close();
}

SetupResult SoftwarePwm::open(ChipSet& chips, const LinePin& pin, std::uint32_t frequency_hz,
                              int fifo_priority, const char* consumer) {
  close();
  if (frequency_hz < 1u || frequency_hz > 5000u) {
    return SetupResult::failure(SetupCode::bad_argument, pin.role + ": software PWM frequency " +
                                                             std::to_string(frequency_hz) +
                                                             " Hz outside 1..5000");
  }
  SetupResult opened = line_.open(chips, pin, false, consumer);
  if (!opened.ok()) {
    return opened;
  }
  frequency_hz_ = frequency_hz;
  duty_.store(0.0f, std::memory_order_relaxed);
  running_.store(true, std::memory_order_relaxed);
  const std::uint64_t period_ns = 1000000000u / frequency_hz;
  thread_ = std::thread([this, period_ns, fifo_priority] { run(period_ns, fifo_priority); });
  return SetupResult::success();
}

void SoftwarePwm::close() {
  running_.store(false, std::memory_order_relaxed);
  if (thread_.joinable()) {
    thread_.join();
  }
  line_.close();
  frequency_hz_ = 0u;
}

void SoftwarePwm::do_set_duty(float duty) {
  duty_.store(duty, std::memory_order_relaxed);
}

void SoftwarePwm::run(std::uint64_t period_ns, int fifo_priority) {
  realtime_.store(make_thread_realtime(fifo_priority).realtime, std::memory_order_relaxed);
  std::uint64_t start_ns = monotonic_ns();
  while (running_.load(std::memory_order_relaxed)) {
    const float duty = duty_.load(std::memory_order_relaxed);
    const auto high_ns = static_cast<std::uint64_t>(static_cast<double>(duty) * period_ns);
    if (high_ns > 0u) {
      line_.set(true);
    }
    if (high_ns > 0u && high_ns < period_ns) {
      sleep_until(start_ns + high_ns);
    }
    if (high_ns < period_ns) {
      line_.set(false);
    }
    start_ns += period_ns;
    const std::uint64_t now_ns = monotonic_ns();
    if (start_ns + period_ns < now_ns) {
      start_ns = now_ns;  // fell behind by more than a period: skip, do not burst
    }
    sleep_until(start_ns);
  }
}

}  // namespace odocal::hal::linux_gpiod
