#pragma once
/// @file
/// Monotonic clock.

#include <cstdint>

namespace odocal::hal {

/// A free-running microsecond clock that wraps modulo 2^32 (about 71.6 minutes).
/// Consumers take modular differences: `std::uint32_t elapsed = now - then;`.
class MonotonicClock {
 public:
  /// Microseconds since an arbitrary epoch, modulo 2^32. ISR-safe.
  std::uint32_t now_us() { return do_now_us(); }

 protected:
  ~MonotonicClock() = default;

 private:
  virtual std::uint32_t do_now_us() = 0;
};

}  // namespace odocal::hal
