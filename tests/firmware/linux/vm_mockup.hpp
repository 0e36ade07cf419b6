// The VM test's harness (see vm_gpio_test.cpp): the gpio-mockup lines driven through debugfs,
// a quadrature generator on the encoder lines, and the check lines the result is made of.
#pragma once

#include <fcntl.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

#include "odocal/hal/linux_gpiod/posix_clock.hpp"

namespace odocal::vm_test {

using hal::linux_gpiod::monotonic_ns;

constexpr const char* kDebugfs = "/sys/kernel/debug/gpio-mockup";
constexpr std::uint32_t kHoldback_us = 1000u;
// SCHED_FIFO priorities: all below the kernel's threaded GPIO interrupt handlers (50), which
// decide each v1 event's edge type by reading the line and must not wait for our threads.
constexpr int kEventPriority = 45;
constexpr int kTickPriority = 40;
constexpr int kPwmPriority = 30;
constexpr int kGeneratorPriority = 20;
// The rate of the counting checks, edges/s over both wheels: each line toggles at a quarter of
// it, so the kernel's 16-event queue lasts 64 ms, more than a loaded host stalls the guest.
constexpr double kCheckRate = 1000.0;

/// Failed checks so far (the result line and the exit status).
inline int failures = 0;

/// Prints one check's line and counts it when it failed.
inline void check(bool ok, const char* name, const std::string& detail) {
  std::printf("check %-28s %s  %s\n", name, ok ? "ok  " : "FAIL", detail.c_str());
  std::fflush(stdout);
  if (!ok) {
    ++failures;
  }
}

/// Sleeps `ms` milliseconds.
inline void sleep_ms(unsigned ms) {
  const timespec pause{static_cast<time_t>(ms / 1000u), static_cast<long>(ms % 1000u) * 1000000L};
  nanosleep(&pause, nullptr);
}

/// Sleeps until the monotonic clock reads `deadline_ns`.
inline void sleep_until_ns(std::uint64_t deadline_ns) {
  timespec when{};
  when.tv_sec = static_cast<time_t>(deadline_ns / 1000000000u);
  when.tv_nsec = static_cast<long>(deadline_ns % 1000000000u);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &when, nullptr) != 0) {
  }
}

// One mockup line's debugfs file: writing "0"/"1" pulls an input line; reading gives the level
// (for an output, the level the owner drives).
class MockLine {
 public:
  MockLine(int chip, int offset) {
    const std::string path =
        std::string(kDebugfs) + "/gpiochip" + std::to_string(chip) + "/" + std::to_string(offset);
    fd_ = ::open(path.c_str(), O_RDWR | O_CLOEXEC);
    if (fd_ < 0) {
      std::printf("cannot open %s: %s\n", path.c_str(), std::strerror(errno));
    }
  }
  ~MockLine() {
    if (fd_ >= 0) {
      ::close(fd_);
    }
  }
  MockLine(const MockLine&) = delete;
  MockLine& operator=(const MockLine&) = delete;

  bool valid() const { return fd_ >= 0; }
  void pull(bool level) { (void)!::write(fd_, level ? "1" : "0", 1); }
  int read() {
    char text[4] = {};
    if (::pread(fd_, text, sizeof text - 1u, 0) <= 0) {
      return -1;
    }
    return text[0] == '1' ? 1 : 0;
  }

 private:
  int fd_ = -1;
};

// Generates quadrature on the four encoder lines by pulling the mockup's inputs.
class QuadratureGenerator {
 public:
  QuadratureGenerator() : lines_{{0, 0}, {0, 1}, {0, 2}, {0, 3}} {
    for (int i = 0; i < 4; ++i) {
      levels_[i] = false;
      lines_[i].pull(false);
    }
  }

  bool valid() const {
    return lines_[0].valid() && lines_[1].valid() && lines_[2].valid() && lines_[3].valid();
  }

  struct Result {
    std::uint32_t edges = 0u;
    double seconds = 0.0;
    double rate_hz() const { return seconds > 0.0 ? edges / seconds : 0.0; }
  };

  // Moves the left wheel by `left` counts and the right one by `right` (sign = direction),
  // alternating between wheels, one edge every 1/edges_per_s seconds (0: as fast as possible).
  Result move(long left, long right, double edges_per_s) {
    const std::uint64_t period_ns =
        edges_per_s > 0.0 ? static_cast<std::uint64_t>(1e9 / edges_per_s) : 0u;
    const std::uint64_t start_ns = monotonic_ns();
    std::uint64_t next_ns = start_ns;
    Result result;
    long remaining[2] = {left, right};
    int wheel = 0;
    while (remaining[0] != 0 || remaining[1] != 0) {
      if (remaining[wheel] == 0) {
        wheel ^= 1;
      }
      const bool forward = remaining[wheel] > 0;
      step(wheel, forward);
      remaining[wheel] += forward ? -1 : 1;
      wheel ^= 1;
      ++result.edges;
      if (period_ns != 0u) {
        next_ns += period_ns;
        const std::uint64_t now_ns = monotonic_ns();
        if (next_ns + 2u * period_ns < now_ns) {
          next_ns = now_ns;  // stalled (a busy host stops the guest): never catch up in a burst
        }
        sleep_until_ns(next_ns);
      }
    }
    result.seconds = static_cast<double>(monotonic_ns() - start_ns) * 1e-9;
    return result;
  }

 private:
  // Forward (A leads B): 00 -> 10 -> 11 -> 01 -> 00, so A toggles when A == B.
  void step(int wheel, bool forward) {
    const int a = wheel * 2;
    const int b = a + 1;
    const bool toggle_a = (levels_[a] == levels_[b]) == forward;
    const int line = toggle_a ? a : b;
    levels_[line] = !levels_[line];
    lines_[line].pull(levels_[line]);
  }

  MockLine lines_[4];
  bool levels_[4];
};

/// Whether `text` holds `part`.
inline bool contains(const std::string& text, const char* part) {
  return text.find(part) != std::string::npos;
}

}  // namespace odocal::vm_test
