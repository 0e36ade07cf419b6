#pragma once
/// @file
/// Quadrature encoder edges from libgpiod v1 line events, fed to one edge sink per wheel.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <thread>

#include "odocal/hal/critical_section.hpp"
#include "odocal/hal/edge_sink.hpp"
#include "odocal/hal/linux_gpiod/gpio_chips.hpp"

namespace odocal::hal::linux_gpiod {

/// The two channels of one wheel's encoder.
struct EncoderPins {
  LinePin a;
  LinePin b;
};

/// Which wheel.
enum class Wheel : std::uint8_t { left = 0, right = 1 };

/// Counters of one wheel's event stream. All wrap modulo 2^32.
struct EncoderStats {
  std::uint32_t events = 0u;      ///< events read from the kernel
  std::uint32_t dropped = 0u;     ///< impossible transitions where edges were lost (resyncs)
  std::uint32_t misread = 0u;     ///< one-off edge types read late by the kernel (harmless)
  std::uint32_t queue_full = 0u;  ///< reads that found a kernel queue full: edges may be lost
  std::uint32_t reordered = 0u;   ///< events older than one already decoded (ordering lost)
};

/// Requests the four encoder lines for both-edge events and decodes them on a thread.
///
/// libgpiod v1 gives each line its own event queue (16 events deep in the kernel; newer events
/// are dropped when it is full) and stamps each event with CLOCK_MONOTONIC. The thread polls
/// the four queues, merges what it reads by timestamp, holds back events younger than
/// `holdback_us` (an event of one line may still be on its way while a later one of the other
/// line is already readable), and hands each wheel's edge sink (`hal::EdgeSink`, in practice the
/// core's quadrature decoder) the line levels after every edge, under the critical section.
///
/// Each event is one edge, so a line's level is toggled per event. The edge type the kernel
/// reports is used as a check, not as the level: v1 decides it by reading the line when its
/// interrupt thread runs, which can be after the next edge. An event whose type disagrees with
/// the toggled level is an impossible transition (a rise on a line already high). Once, it is
/// counted as `misread` and the toggle is trusted; twice in a row on a line, or on the first
/// event after a read that found the kernel queue full (the only time v1 drops), edges were
/// lost: it is counted as `dropped` and the level resynchronised to the reported type. An even
/// number lost on one line leaves no impossible transition; `queue_full` shows it may happen.
class EncoderEvents {
 public:
  /// Events buffered between reads (held back or not yet decoded).
  static constexpr std::size_t max_pending = 256u;

  EncoderEvents(const hal::EdgeSink& left, const hal::EdgeSink& right,
                hal::CriticalSection& critical)
      : sinks_{left, right}, critical_(critical) {}
  ~EncoderEvents();
  EncoderEvents(const EncoderEvents&) = delete;
  EncoderEvents& operator=(const EncoderEvents&) = delete;

  /// Requests the four lines for both-edge events, reads their levels and presets the sinks
  /// to them. Set-up only. Fails naming the line when a chip or line is missing or in use.
  SetupResult open(ChipSet& chips, const EncoderPins& left, const EncoderPins& right,
                   const char* consumer);

  /// Starts the event thread. `fifo_priority` 1..99 asks for SCHED_FIFO (0: do not);
  /// `holdback_us` is how long an event waits for older events of the other lines (0..100000).
  /// The lines stay requested between `stop` and `start`: the kernel keeps queuing meanwhile.
  SetupResult start(int fifo_priority, std::uint32_t holdback_us);

  /// Stops the thread (events stay queued in the kernel). Safe to call twice.
  void stop();

  /// Stops and releases the lines.
  void close();

  /// The counters of one wheel. Any thread.
  EncoderStats stats(Wheel wheel) const;

  /// Whether the event thread got SCHED_FIFO. Valid once `start` returned.
  bool realtime() const { return realtime_.load(std::memory_order_relaxed); }

 private:
  struct Event {
    std::uint64_t ts_ns;
    std::uint8_t line;  // 0 left A, 1 left B, 2 right A, 3 right B
    bool rising;
    bool after_gap;  // first event read after a full queue: edges may be missing before it
  };
  struct Counters {
    std::atomic<std::uint32_t> events{0u};
    std::atomic<std::uint32_t> dropped{0u};
    std::atomic<std::uint32_t> misread{0u};
    std::atomic<std::uint32_t> queue_full{0u};
    std::atomic<std::uint32_t> reordered{0u};
  };

  void run(std::uint64_t holdback_ns);
  void read_line(std::size_t line);
  void decode_up_to(std::uint64_t limit_ns);

  std::array<hal::EdgeSink, 2> sinks_;
  hal::CriticalSection& critical_;
  std::array<gpiod_line*, 4> lines_{};
  std::array<int, 4> fds_{-1, -1, -1, -1};
  std::array<bool, 4> levels_{};     // the level of each line after the last decoded event
  std::array<bool, 4> disagreed_{};  // the last event of the line disagreed with its type
  std::array<bool, 4> was_full_{};   // the last read of the line returned a full queue
  std::array<Event, max_pending> pending_{};
  std::size_t pending_count_ = 0u;
  std::uint64_t last_decoded_ns_ = 0u;
  std::array<Counters, 2> counters_{};
  int stop_fd_ = -1;
  std::thread thread_;
  std::atomic<bool> realtime_{false};
};

}  // namespace odocal::hal::linux_gpiod
