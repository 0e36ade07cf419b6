#include "odocal/hal/linux_gpiod/encoder_events.hpp"

#include <gpiod.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "odocal/hal/linux_gpiod/posix_clock.hpp"

namespace odocal::hal::linux_gpiod {
namespace {

// The kernel's v1 event queue depth per line: a read that returns this many found it full.
constexpr int kKernelQueueDepth = 16;

std::uint64_t ns_of(const timespec& ts) {
  return static_cast<std::uint64_t>(ts.tv_sec) * 1000000000u +
         static_cast<std::uint64_t>(ts.tv_nsec);
}

}  // namespace

EncoderEvents::~EncoderEvents() {
  close();
}

SetupResult EncoderEvents::open(ChipSet& chips, const EncoderPins& left, const EncoderPins& right,
                                const char* consumer) {
  close();
  const LinePin* pins[4] = {&left.a, &left.b, &right.a, &right.b};
  for (std::size_t i = 0; i < 4u; ++i) {
    gpiod_line* line = nullptr;
    SetupResult found = chips.find(*pins[i], &line);
    if (found.ok() && gpiod_line_is_requested(line)) {
      found = request_failure(*pins[i], line, EBUSY);
    } else if (found.ok() && gpiod_line_request_both_edges_events(line, consumer) != 0) {
      found = request_failure(*pins[i], line, errno);
    }
    if (!found.ok()) {
      close();
      return found;
    }
    lines_[i] = line;
    fds_[i] = gpiod_line_event_get_fd(line);
    const int level = gpiod_line_get_value(line);
    if (fds_[i] < 0 || level < 0) {
      SetupResult failed = request_failure(*pins[i], line, errno);
      close();
      return failed;
    }
    levels_[i] = level != 0;
    disagreed_[i] = false;
    was_full_[i] = false;
  }
  {
    CriticalGuard guard(critical_);
    sinks_[0].reset(levels_[0], levels_[1]);
    sinks_[1].reset(levels_[2], levels_[3]);
  }
  pending_count_ = 0u;
  last_decoded_ns_ = 0u;
  return SetupResult::success();
}

SetupResult EncoderEvents::start(int fifo_priority, std::uint32_t holdback_us) {
  stop();
  if (lines_[0] == nullptr) {
    return SetupResult::failure(SetupCode::bad_argument, "encoder lines not opened");
  }
  if (holdback_us > 100000u) {
    return SetupResult::failure(
        SetupCode::bad_argument,
        "event hold-back " + std::to_string(holdback_us) + " us outside 0..100000");
  }
  stop_fd_ = eventfd(0u, EFD_CLOEXEC | EFD_NONBLOCK);
  if (stop_fd_ < 0) {
    return SetupResult::failure(SetupCode::system_error,
                                std::string("eventfd: ") + std::strerror(errno));
  }
  std::atomic<bool> ready{false};
  thread_ = std::thread([this, fifo_priority, holdback_us, &ready] {
    realtime_.store(make_thread_realtime(fifo_priority).realtime, std::memory_order_relaxed);
    ready.store(true, std::memory_order_release);
    run(static_cast<std::uint64_t>(holdback_us) * 1000u);
  });
  while (!ready.load(std::memory_order_acquire)) {
    std::this_thread::yield();
  }
  return SetupResult::success();
}

void EncoderEvents::stop() {
  if (thread_.joinable()) {
    const std::uint64_t one = 1u;
    (void)!write(stop_fd_, &one, sizeof one);
    thread_.join();
  }
  if (stop_fd_ >= 0) {
    ::close(stop_fd_);
    stop_fd_ = -1;
  }
}

void EncoderEvents::close() {
  stop();
  for (std::size_t i = 0; i < 4u; ++i) {
    if (lines_[i] != nullptr) {
      gpiod_line_release(lines_[i]);
      lines_[i] = nullptr;
    }
    fds_[i] = -1;
  }
}

EncoderStats EncoderEvents::stats(Wheel wheel) const {
  const Counters& c = counters_[static_cast<std::size_t>(wheel)];
  EncoderStats stats;
  stats.events = c.events.load(std::memory_order_relaxed);
  stats.dropped = c.dropped.load(std::memory_order_relaxed);
  stats.misread = c.misread.load(std::memory_order_relaxed);
  stats.queue_full = c.queue_full.load(std::memory_order_relaxed);
  stats.reordered = c.reordered.load(std::memory_order_relaxed);
  return stats;
}

void EncoderEvents::run(std::uint64_t holdback_ns) {
  pollfd fds[5];
  for (std::size_t i = 0; i < 4u; ++i) {
    fds[i] = pollfd{fds_[i], POLLIN, 0};
  }
  fds[4] = pollfd{stop_fd_, POLLIN, 0};
  for (;;) {
    // With events held back, wake up again once the oldest may be decoded.
    const int timeout_ms = pending_count_ == 0u ? -1 : static_cast<int>(holdback_ns / 1000000u) + 1;
    const int ready = poll(fds, 5, timeout_ms);
    if (ready < 0 && errno != EINTR) {
      return;
    }
    if ((fds[4].revents & POLLIN) != 0) {
      return;
    }
    // Taken before reading: every event older than this is already in its queue, except for
    // the few microseconds between the kernel's timestamp and its queuing (the hold-back).
    const std::uint64_t read_start_ns = monotonic_ns();
    for (std::size_t i = 0; i < 4u && ready > 0; ++i) {
      if ((fds[i].revents & POLLIN) != 0) {
        read_line(i);
      }
    }
    std::stable_sort(pending_.begin(),
                     pending_.begin() + static_cast<std::ptrdiff_t>(pending_count_),
                     [](const Event& x, const Event& y) { return x.ts_ns < y.ts_ns; });
    decode_up_to(read_start_ns > holdback_ns ? read_start_ns - holdback_ns : 0u);
  }
}

void EncoderEvents::read_line(std::size_t line) {
  gpiod_line_event events[kKernelQueueDepth];
  if (pending_count_ + kKernelQueueDepth > max_pending) {
    decode_up_to(~std::uint64_t{0});  // no room: decode everything rather than lose events
  }
  const int count = gpiod_line_event_read_fd_multiple(fds_[line], events, kKernelQueueDepth);
  if (count <= 0) {
    return;
  }
  Counters& counters = counters_[line / 2u];
  counters.events.fetch_add(static_cast<std::uint32_t>(count), std::memory_order_relaxed);
  const bool gap = was_full_[line];
  was_full_[line] = count == kKernelQueueDepth;
  if (was_full_[line]) {
    counters.queue_full.fetch_add(1u, std::memory_order_relaxed);
  }
  for (int i = 0; i < count; ++i) {
    pending_[pending_count_++] =
        Event{ns_of(events[i].ts), static_cast<std::uint8_t>(line),
              events[i].event_type == GPIOD_LINE_EVENT_RISING_EDGE, gap && i == 0};
  }
}

void EncoderEvents::decode_up_to(std::uint64_t limit_ns) {
  std::size_t done = 0u;
  {
    CriticalGuard guard(critical_);
    for (; done < pending_count_ && pending_[done].ts_ns <= limit_ns; ++done) {
      const Event& event = pending_[done];
      const std::size_t wheel = event.line / 2u;
      if (event.ts_ns < last_decoded_ns_) {
        counters_[wheel].reordered.fetch_add(1u, std::memory_order_relaxed);
      } else {
        last_decoded_ns_ = event.ts_ns;
      }
      if (event.rising == levels_[event.line]) {
        // Impossible: a rise on a line already high, or a fall on a low one.
        if (event.after_gap || disagreed_[event.line]) {
          // Edges were lost: the reported type is the line's level now; nothing to decode.
          counters_[wheel].dropped.fetch_add(1u, std::memory_order_relaxed);
          disagreed_[event.line] = false;
          continue;
        }
        // Most likely the kernel read the level after the next edge: trust the event count.
        counters_[wheel].misread.fetch_add(1u, std::memory_order_relaxed);
        disagreed_[event.line] = true;
      } else {
        disagreed_[event.line] = false;
      }
      levels_[event.line] = !levels_[event.line];
      sinks_[wheel].on_edge(levels_[wheel * 2u], levels_[wheel * 2u + 1u],
                            static_cast<std::uint32_t>(event.ts_ns / 1000u));
    }
  }
  std::copy(pending_.begin() + static_cast<std::ptrdiff_t>(done),
            pending_.begin() + static_cast<std::ptrdiff_t>(pending_count_), pending_.begin());
  pending_count_ -= done;
}

}  // namespace odocal::hal::linux_gpiod
