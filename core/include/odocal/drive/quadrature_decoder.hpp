#pragma once
/// @file
/// x4 quadrature decoder driven from encoder edge interrupts.

#include <cstdint>
#include <cstring>

#include "odocal/hal/edge_sink.hpp"

namespace odocal::drive {

namespace quadrature {

/// Marks a transition where both channels changed: direction unknown, an edge was missed.
inline constexpr std::int8_t illegal = 2;

/// Index: (previous state << 2) | new state, a state being (A << 1) | B.
/// Forward (A leads B) walks 0 -> 2 -> 3 -> 1 -> 0; backward walks the other way.
inline constexpr std::int8_t transition[16] = {
    // to:  00       01       10       11
    0,       -1,      +1,      illegal,  // from 00
    +1,      0,       illegal, -1,       // from 01
    -1,      illegal, 0,       +1,       // from 10
    illegal, +1,      -1,      0,        // from 11
};
/// The same for an encoder whose A and B lines are exchanged (it counts down going forward).
inline constexpr std::int8_t transition_reversed[16] = {
    0,       +1,      -1,      illegal,  // from 00
    -1,      0,       illegal, +1,       // from 01
    +1,      illegal, 0,       -1,       // from 10
    illegal, -1,      +1,      0,        // from 11
};

constexpr std::uint8_t state_of(bool a, bool b) {
  return static_cast<std::uint8_t>((a ? 2u : 0u) | (b ? 1u : 0u));
}

}  // namespace quadrature

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
  /// ISR-safe: constant time, no branches on history beyond the table. Inline: the robot's edge
  /// vectors take it into their own body (the whole edge path is one function).
  void on_edge(bool a, bool b, std::uint32_t now_us) {
    const std::uint8_t next = quadrature::state_of(a, b);
    const std::int8_t step = table_[(state_ << 2) | next];
    state_ = next;
    QuadratureDecoder& out = *counts_;
    if (step == quadrature::illegal) {
      ++out.illegal_;
    } else if (step != 0) {
      // Modular arithmetic: the raw count wraps at 2^32 and readers take differences.
      out.count_ += static_cast<std::uint32_t>(static_cast<std::int32_t>(step));
      ++out.edges_;
      out.last_edge_us_ = now_us;
    }
  }

  /// From now on this decoder's edges advance the counters of `counts` (itself by default: the
  /// other wheel's decoder when the encoder connectors are swapped), counting down going forward
  /// when `reversed`. Not ISR-safe: call where edges cannot interrupt. The counts carry on from
  /// where they are (no jump).
  [[gnu::noinline]] void route(QuadratureDecoder& counts, bool reversed) {
    counts_ = &counts;
    std::memcpy(table_, reversed ? quadrature::transition_reversed : quadrature::transition,
                sizeof table_);
  }

  /// The current state. Not atomic: call it where edges cannot interrupt (under a
  /// `hal::CriticalGuard`, or from the edge context itself).
  [[nodiscard]] EncoderSnapshot snapshot() const {
    return EncoderSnapshot{count_, last_edge_us_, edges_, illegal_};
  }

 private:
  /// The transition table in force, held in the decoder and first in it: the edge reads
  /// `table_[index]` as one load from the decoder's address plus the index (no load of a table's
  /// address, no offset to add), which pays for the load of `counts_`: the edge costs what it did
  /// before the wiring fixes.
  // clang-format off
  std::int8_t table_[16] = {0, -1, +1, quadrature::illegal,  +1, 0, quadrature::illegal, -1,
                            -1, quadrature::illegal, 0, +1,  quadrature::illegal, +1, -1, 0};
  // clang-format on
  std::uint32_t count_ = 0u;
  std::uint32_t last_edge_us_ = 0u;
  std::uint32_t edges_ = 0u;
  std::uint32_t illegal_ = 0u;
  std::uint8_t state_ = 0u;           ///< previous (A << 1) | B
  QuadratureDecoder* counts_ = this;  ///< whose counters the edges advance (`route`)
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
