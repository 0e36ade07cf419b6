#pragma once
/// @file
/// The critical section of the Linux target: a recursive mutex shared by the edge thread, the
/// tick thread and the main loop.

#include <mutex>

#include "odocal/hal/critical_section.hpp"

namespace odocal::hal::linux_gpiod {

/// Excludes the encoder-event thread, the tick thread and the console while a multi-word value
/// is read or written. Nesting on one thread is allowed (a recursive mutex). Any thread.
class MutexCriticalSection final : public hal::CriticalSection {
 private:
  void do_enter() override { mutex_.lock(); }
  void do_exit() override { mutex_.unlock(); }

  std::recursive_mutex mutex_;
};

}  // namespace odocal::hal::linux_gpiod
