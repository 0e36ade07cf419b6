#pragma once
/// @file
/// The project's one single-producer / single-consumer byte ring, for data crossing from an
/// interrupt (or a reader thread) to the main loop and back: the STM32F4 USART's receive and
/// transmit rings (hal/stm32f4), which the console reads and writes through its byte stream.
/// Header-only and dependency-free, so it sits in hal/include, the one include directory every
/// library may use (a HAL backend may not depend on the core).

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

namespace odocal::concurrency {

/// Lock-free SPSC ring of `Capacity` - 1 usable bytes (`Capacity` a power of two, >= 2).
///
/// Exactly one context calls `push` (e.g. the UART RX interrupt) and exactly one calls `pop` /
/// `peek` / `size` (the main loop). The producer publishes a byte with a release store of `head_`
/// after writing it; the consumer reads `head_` with acquire before reading the byte, and hands
/// the slot back with a release store of `tail_`, so neither side ever sees a half-written slot.
/// No critical section, no `volatile`.
template <std::size_t Capacity>
class SpscRing {
  static_assert(Capacity >= 2u && (Capacity & (Capacity - 1u)) == 0u,
                "capacity must be a power of two");

 public:
  /// Appends one byte. Producer context only; ISR-safe. @return false (byte dropped) when full.
  bool push(std::uint8_t byte) {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    const std::size_t next = (head + 1u) & (Capacity - 1u);
    if (next == tail_.load(std::memory_order_acquire)) {
      return false;
    }
    bytes_[head] = byte;
    head_.store(next, std::memory_order_release);
    return true;
  }

  /// Removes the oldest byte into `byte`. Consumer context only; ISR-safe. @return false when
  /// empty.
  bool pop(std::uint8_t& byte) {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) {
      return false;
    }
    byte = bytes_[tail];
    tail_.store((tail + 1u) & (Capacity - 1u), std::memory_order_release);
    return true;
  }

  /// Copies the oldest byte into `byte` without removing it. Consumer context only.
  /// @return false when empty.
  bool peek(std::uint8_t& byte) const {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) {
      return false;
    }
    byte = bytes_[tail];
    return true;
  }

  /// True when nothing is queued: exact in the consumer context; in the producer context, true
  /// may be stale (the consumer only ever makes it truer). Either side; ISR-safe.
  [[nodiscard]] bool empty() const {
    return head_.load(std::memory_order_acquire) == tail_.load(std::memory_order_acquire);
  }

  /// Bytes waiting. Exact in the consumer context; a lower bound elsewhere.
  [[nodiscard]] std::size_t size() const {
    const std::size_t head = head_.load(std::memory_order_acquire);
    const std::size_t tail = tail_.load(std::memory_order_acquire);
    return (head - tail) & (Capacity - 1u);
  }

  /// Bytes that can still be pushed (exact in the producer context).
  [[nodiscard]] std::size_t free_space() const { return Capacity - 1u - size(); }

 private:
  std::atomic<std::size_t> head_{0u};  ///< next slot the producer writes
  std::atomic<std::size_t> tail_{0u};  ///< next slot the consumer reads
  // Not zeroed: a slot is only read after `push` wrote it (the indices say which), and zeroing
  // would cost a memset per ring in the start-up code.
  std::array<std::uint8_t, Capacity> bytes_;
};

}  // namespace odocal::concurrency
