#include "odocal/hal/linux_gpiod/posix_clock.hpp"

#include <pthread.h>
#include <sched.h>
#include <time.h>

#include <cstring>

namespace odocal::hal::linux_gpiod {

std::uint64_t monotonic_ns() {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<std::uint64_t>(now.tv_sec) * 1000000000u +
         static_cast<std::uint64_t>(now.tv_nsec);
}

RealtimeResult make_thread_realtime(int priority) {
  RealtimeResult result;
  if (priority <= 0) {
    result.reason = "SCHED_FIFO not requested (priority 0)";
    return result;
  }
  const int highest = sched_get_priority_max(SCHED_FIFO);
  sched_param param{};
  param.sched_priority = priority > highest ? highest : priority;
  const int error_number = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  if (error_number != 0) {
    result.reason = std::string("SCHED_FIFO refused: ") + std::strerror(error_number) +
                    " (needs root, CAP_SYS_NICE or an rtprio limit)";
    return result;
  }
  result.realtime = true;
  return result;
}

}  // namespace odocal::hal::linux_gpiod
