#pragma once
/// @file
/// CLOCK_MONOTONIC in nanoseconds and as the HAL's microsecond clock, and the realtime-scheduling
/// helper.

#include <cstdint>
#include <string>

#include "odocal/posix/fd_byte_stream.hpp"

namespace odocal::hal::linux_gpiod {

/// Nanoseconds of CLOCK_MONOTONIC, the clock the kernel stamps GPIO events with (Linux >= 5.7).
std::uint64_t monotonic_ns();

/// CLOCK_MONOTONIC in microseconds modulo 2^32: the same time base as the encoder event
/// timestamps handed to the decoders. One clock for every POSIX target (hal/posix).
using PosixMonotonicClock = posix::PosixClock;

/// Outcome of asking for SCHED_FIFO.
struct RealtimeResult {
  bool realtime = false;  ///< true when the thread now runs SCHED_FIFO
  std::string reason;     ///< why not, when it does not ("priority 0 requested", "EPERM ...")
};

/// Puts the calling thread on SCHED_FIFO at `priority` (1..99). `priority` 0 leaves it on the
/// normal scheduler. Never fails hard: a refusal is reported, the thread keeps running.
RealtimeResult make_thread_realtime(int priority);

}  // namespace odocal::hal::linux_gpiod
