#pragma once
/// @file
/// x4 quadrature decoder driven from encoder edge interrupts.

#include <cstdint>

#include "odocal/hal/edge_sink.hpp"

namespace odocal::drive {

/// What the tick reads from a decoder: a consistent copy taken under a critical section.
struct EncoderSnapshot {
  std::uint32_t count = 0u;         ///< position in counts, modulo 2^32 (wraps; take differences)
  std::uint32_t last_edge_us = 0u;  ///< timestamp of the last valid transition, modulo 2^32
  std::uint32_t edges = 0u;         ///< valid transitions seen, modulo 2^32
  std::uint32_t illegal = 0u;       ///< transitions where both channels changed, modulo 2^32
};

/// Decodes A/B levels into a position by a 16-entry transition table (x4: every edge of either
/// channel counts). A transition where both channels changed at once cannot be decoded (an edge
/// was missed); it is counted as illegal and the position is left unchanged.
///
/// Sign convention: A leading B (A rises while B is low) counts up.
class QuadratureDecoder {
 public:
  /// Sets the current pin levels without counting. Call before enabling edge interrupts.
  void reset(bool a, bool b);

  /// Feeds the pin levels sampled after an edge of A or B, with the edge timestamp.
  /// ISR-safe: constant time, no branches on history beyond the table.
  void on_edge(bool a, bool b, std::uint32_t now_us);

  /// The current state. Not atomic: call it where edges cannot interrupt (under a
  /// `hal::CriticalGuard`, or from the edge context itself).
  [[nodiscard]] EncoderSnapshot snapshot() const {
    return EncoderSnapshot{count_, last_edge_us_, edges_, illegal_};
  }

 private:
  std::uint32_t count_ = 0u;
  std::uint32_t last_edge_us_ = 0u;
  std::uint32_t edges_ = 0u;
  std::uint32_t illegal_ = 0u;
  std::uint8_t state_ = 0u;  ///< previous (A << 1) | B
};

/// `decoder` as the receiver of a HAL backend's encoder edges (hal::EdgeSink): the firmware or
/// simulator connects its backend's edges to its decoders with this. `decoder` must outlive it.
inline hal::EdgeSink edge_sink(QuadratureDecoder& decoder) {
  hal::EdgeSink sink;
  sink.edge = [](void* context, bool a, bool b, std::uint32_t t_us) {
    static_cast<QuadratureDecoder*>(context)->on_edge(a, b, t_us);
  };
  sink.preset = [](void* context, bool a, bool b) {
    static_cast<QuadratureDecoder*>(context)->reset(a, b);
  };
  sink.context = &decoder;
  return sink;
}

}  // namespace odocal::drive
