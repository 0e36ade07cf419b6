#pragma once
/// @file
/// The control tick from a timerfd on its own thread, SCHED_FIFO when permitted.

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

#include "odocal/hal/tick_source.hpp"

namespace odocal::hal::linux_gpiod {

/// What the tick thread measured. Lateness is how long after its deadline a tick's handler
/// started (timer slack, scheduling latency); it is the tick jitter.
struct TickStats {
  std::uint32_t ticks = 0u;           ///< handler calls
  std::uint32_t missed = 0u;          ///< periods that passed with no call (overruns)
  std::uint32_t late_us_max = 0u;     ///< worst lateness
  std::uint32_t late_us_mean = 0u;    ///< mean lateness
  std::uint32_t handler_us_max = 0u;  ///< longest handler run
  std::uint32_t rate_hz = 0u;         ///< rate set
  bool realtime = false;              ///< the thread runs SCHED_FIFO
};

/// A periodic tick from CLOCK_MONOTONIC absolute deadlines. The handler runs on the tick thread.
class TimerfdTick final : public hal::TickSource {
 public:
  /// `fifo_priority` 1..99 asks for SCHED_FIFO on the tick thread; 0 does not ask.
  explicit TimerfdTick(int fifo_priority) : priority_(fifo_priority) {}
  ~TimerfdTick();
  TimerfdTick(const TimerfdTick&) = delete;
  TimerfdTick& operator=(const TimerfdTick&) = delete;

  /// A consistent-enough copy of the counters (each field is read atomically). Any thread.
  TickStats stats() const;
  /// Why the thread is not realtime ("" when it is, or before start). Valid after `start`.
  std::string realtime_reason() const;
  /// Clears the lateness and handler statistics (not the tick count). Any thread.
  void reset_stats();
  /// Why `start` returned 0 (the timer could not be created). Main thread, after `start`.
  const std::string& error() const { return error_; }
  /// True when the tick thread stopped on a failing system call. Any thread.
  bool failed() const { return failed_.load(std::memory_order_relaxed); }

 private:
  std::uint32_t do_start(std::uint32_t rate_hz, TickHandler handler, void* context) override;
  void do_stop() override;
  void run(std::uint64_t period_ns, std::uint64_t first_ns);

  int priority_;
  int timer_fd_ = -1;
  int stop_fd_ = -1;
  TickHandler handler_ = nullptr;
  void* context_ = nullptr;
  std::thread thread_;
  std::string error_;
  std::atomic<bool> failed_{false};
  std::atomic<bool> realtime_{false};
  std::atomic<std::uint32_t> rate_hz_{0u};
  std::atomic<std::uint32_t> ticks_{0u};
  std::atomic<std::uint32_t> missed_{0u};
  std::atomic<std::uint32_t> late_us_max_{0u};
  std::atomic<std::uint64_t> late_us_sum_{0u};
  std::atomic<std::uint32_t> late_samples_{0u};
  std::atomic<std::uint32_t> handler_us_max_{0u};
  std::string realtime_reason_;
  std::atomic<bool> reason_ready_{false};
};

}  // namespace odocal::hal::linux_gpiod
