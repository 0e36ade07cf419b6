#pragma once
/// @file
/// Single-producer / single-consumer byte ring between an interrupt and the main loop.

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

namespace odocal::hal::stm32f4 {

/// A lock-free byte queue for exactly one producer context and one consumer context. The
/// producer owns `head_`, the consumer owns `tail_`; each publishes its index with release
/// and reads the other's with acquire, so the byte written before a publish is seen after it.
/// `Capacity` is a power of two; the indices run freely modulo 2^32, so the ring holds exactly
/// `Capacity` bytes.
template <std::size_t Capacity>
class SpscRing {
  static_assert(Capacity >= 2u && (Capacity & (Capacity - 1u)) == 0u, "power of two");

 public:
  /// Appends one byte; false when full. Producer only.
  bool push(std::uint8_t byte) {
    const std::uint32_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) >= Capacity) {
      return false;
    }
    bytes_[head % Capacity] = byte;
    head_.store(head + 1u, std::memory_order_release);
    return true;
  }

  /// Removes the oldest byte into `byte`; false when empty. Consumer only.
  bool pop(std::uint8_t& byte) {
    const std::uint32_t tail = tail_.load(std::memory_order_relaxed);
    if (head_.load(std::memory_order_acquire) == tail) {
      return false;
    }
    byte = bytes_[tail % Capacity];
    tail_.store(tail + 1u, std::memory_order_release);
    return true;
  }

  /// True when nothing is queued. Either side.
  [[nodiscard]] bool empty() const {
    return head_.load(std::memory_order_acquire) == tail_.load(std::memory_order_acquire);
  }

 private:
  // Not zeroed: a byte is only read after `push` wrote it (the indices say which), and zeroing
  // would cost a memset per ring in the start-up code.
  std::array<std::uint8_t, Capacity> bytes_;
  std::atomic<std::uint32_t> head_{0u};
  std::atomic<std::uint32_t> tail_{0u};
};

}  // namespace odocal::hal::stm32f4
