#pragma once
/// @file
/// Periodic tick source (timer interrupt, timerfd thread, simulator loop).

#include <cstdint>

namespace odocal::hal {

/// Called once per period from the tick context.
using TickHandler = void (*)(void* context);

/// A periodic timer that calls a handler at a fixed rate.
class TickSource {
 public:
  /// Starts calling `handler(context)` every 1/rate_hz seconds. rate_hz is clamped to
  /// [1, 20000]. Returns the rate actually set (the backend may round to its timer). Not ISR-safe.
  std::uint32_t start(std::uint32_t rate_hz, TickHandler handler, void* context) {
    if (rate_hz < 1u) {
      rate_hz = 1u;
    } else if (rate_hz > 20000u) {
      rate_hz = 20000u;
    }
    return do_start(rate_hz, handler, context);
  }

  /// Stops the tick. Not ISR-safe.
  void stop() { do_stop(); }

 protected:
  ~TickSource() = default;

 private:
  virtual std::uint32_t do_start(std::uint32_t rate_hz, TickHandler handler, void* context) = 0;
  virtual void do_stop() = 0;
};

}  // namespace odocal::hal
