#include "odocal/hal/linux_gpiod/timerfd_tick.hpp"

#include <poll.h>
#include <sys/eventfd.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "odocal/hal/linux_gpiod/posix_clock.hpp"

namespace odocal::hal::linux_gpiod {
namespace {

timespec timespec_of(std::uint64_t ns) {
  timespec value{};
  value.tv_sec = static_cast<time_t>(ns / 1000000000u);
  value.tv_nsec = static_cast<long>(ns % 1000000000u);
  return value;
}

void raise_max(std::atomic<std::uint32_t>& maximum, std::uint32_t value) {
  std::uint32_t seen = maximum.load(std::memory_order_relaxed);
  while (value > seen && !maximum.compare_exchange_weak(seen, value, std::memory_order_relaxed)) {
  }
}

}  // namespace

TimerfdTick::~TimerfdTick() {
  do_stop();
}

TickStats TimerfdTick::stats() const {
  TickStats stats;
  stats.ticks = ticks_.load(std::memory_order_relaxed);
  stats.missed = missed_.load(std::memory_order_relaxed);
  stats.late_us_max = late_us_max_.load(std::memory_order_relaxed);
  const std::uint32_t samples = late_samples_.load(std::memory_order_relaxed);
  stats.late_us_mean =
      samples == 0u
          ? 0u
          : static_cast<std::uint32_t>(late_us_sum_.load(std::memory_order_relaxed) / samples);
  stats.handler_us_max = handler_us_max_.load(std::memory_order_relaxed);
  stats.rate_hz = rate_hz_.load(std::memory_order_relaxed);
  stats.realtime = realtime_.load(std::memory_order_relaxed);
  return stats;
}

std::string TimerfdTick::realtime_reason() const {
  return reason_ready_.load(std::memory_order_acquire) ? realtime_reason_ : std::string();
}

void TimerfdTick::reset_stats() {
  missed_.store(0u, std::memory_order_relaxed);
  late_us_max_.store(0u, std::memory_order_relaxed);
  late_us_sum_.store(0u, std::memory_order_relaxed);
  late_samples_.store(0u, std::memory_order_relaxed);
  handler_us_max_.store(0u, std::memory_order_relaxed);
}

std::uint32_t TimerfdTick::do_start(std::uint32_t rate_hz, TickHandler handler, void* context) {
  do_stop();
  error_.clear();
  timer_fd_ = timerfd_create(CLOCK_MONOTONIC, TFD_CLOEXEC);
  stop_fd_ = eventfd(0u, EFD_CLOEXEC | EFD_NONBLOCK);
  if (timer_fd_ < 0 || stop_fd_ < 0) {
    error_ = std::string("timerfd/eventfd: ") + std::strerror(errno);
    do_stop();
    return 0u;
  }
  // The period is a whole number of nanoseconds; report the rate that gives.
  const std::uint64_t period_ns = 1000000000u / rate_hz;
  // Absolute deadlines: start + k * period, so lateness never accumulates into drift.
  const std::uint64_t first_ns = monotonic_ns() + period_ns;
  itimerspec spec{};
  spec.it_value = timespec_of(first_ns);
  spec.it_interval = timespec_of(period_ns);
  if (timerfd_settime(timer_fd_, TFD_TIMER_ABSTIME, &spec, nullptr) != 0) {
    error_ = std::string("timerfd_settime: ") + std::strerror(errno);
    do_stop();
    return 0u;
  }
  handler_ = handler;
  context_ = context;
  rate_hz_.store(static_cast<std::uint32_t>(1000000000u / period_ns), std::memory_order_relaxed);
  reason_ready_.store(false, std::memory_order_relaxed);
  thread_ = std::thread([this, period_ns, first_ns] { run(period_ns, first_ns); });
  // Whether the thread got SCHED_FIFO is known before start returns, so `status` and the
  // start-up warning never report a thread that has not tried yet.
  while (!reason_ready_.load(std::memory_order_acquire)) {
    std::this_thread::yield();
  }
  return rate_hz_.load(std::memory_order_relaxed);
}

void TimerfdTick::do_stop() {
  if (thread_.joinable()) {
    const std::uint64_t one = 1u;
    (void)!write(stop_fd_, &one, sizeof one);
    thread_.join();
  }
  if (timer_fd_ >= 0) {
    ::close(timer_fd_);
    timer_fd_ = -1;
  }
  if (stop_fd_ >= 0) {
    ::close(stop_fd_);
    stop_fd_ = -1;
  }
}

void TimerfdTick::run(std::uint64_t period_ns, std::uint64_t first_ns) {
  const RealtimeResult rt = make_thread_realtime(priority_);
  realtime_reason_ = rt.reason;
  realtime_.store(rt.realtime, std::memory_order_relaxed);
  reason_ready_.store(true, std::memory_order_release);

  std::uint64_t deadline_ns = first_ns;
  pollfd fds[2] = {{timer_fd_, POLLIN, 0}, {stop_fd_, POLLIN, 0}};
  for (;;) {
    if (poll(fds, 2, -1) < 0) {
      if (errno == EINTR) {
        continue;
      }
      failed_.store(true, std::memory_order_relaxed);
      return;
    }
    if ((fds[1].revents & POLLIN) != 0) {
      return;
    }
    std::uint64_t expirations = 0u;
    if (read(timer_fd_, &expirations, sizeof expirations) != sizeof expirations ||
        expirations == 0u) {
      continue;
    }
    const std::uint64_t woke_ns = monotonic_ns();
    // The deadline of the newest expiration; older ones were missed (the handler runs once).
    deadline_ns += (expirations - 1u) * period_ns;
    if (expirations > 1u) {
      missed_.fetch_add(static_cast<std::uint32_t>(expirations - 1u), std::memory_order_relaxed);
    }
    const std::uint64_t late_ns = woke_ns > deadline_ns ? woke_ns - deadline_ns : 0u;
    const auto late_us = static_cast<std::uint32_t>(late_ns / 1000u);
    raise_max(late_us_max_, late_us);
    late_us_sum_.fetch_add(late_us, std::memory_order_relaxed);
    late_samples_.fetch_add(1u, std::memory_order_relaxed);

    handler_(context_);
    ticks_.fetch_add(1u, std::memory_order_relaxed);
    raise_max(handler_us_max_, static_cast<std::uint32_t>((monotonic_ns() - woke_ns) / 1000u));
    deadline_ns += period_ns;
  }
}

}  // namespace odocal::hal::linux_gpiod
