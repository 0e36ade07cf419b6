#pragma once
/// @file
/// Connects two encoder lines to an edge sink (hal::EdgeSink, in practice a quadrature decoder)
/// through the HAL edge callbacks, the way a board file wires its EXTI lines: on every edge,
/// sample both levels and the clock, and hand them to the sink. Used by the host simulator and
/// the QEMU image.

#include <cstdint>

#include "odocal/hal/edge_sink.hpp"
#include "odocal/sim/plant.hpp"

namespace odocal::sim {

/// A fault of an encoder's channel A, for exercising the firmware's fault path.
enum class ChannelFault : std::uint8_t {
  none,
  dead,   ///< channel A stuck at its level: no A edges reach the decoder
  noisy,  ///< every 5th B edge arrives with a glitch on A (both channels change at once)
};

/// What a channel-A fault does to the levels of each edge, for any wiring of one wheel's lines.
class ChannelFilter {
 public:
  /// The levels at start-up (no edge seen yet).
  void preset(bool a, bool b) {
    a_seen_ = a;
    b_seen_ = b;
  }
  /// From now on, channel A behaves as `fault` says; `a_level` is its level now.
  void set_fault(ChannelFault fault, bool a_level) {
    fault_ = fault;
    stuck_a_ = a_level;
    edges_ = 0u;
  }
  /// An edge left the lines at `a_line`, `b`: sets `a` to the level of A the sink sees with it
  /// (B is never faulty). False when the edge does not reach the sink (an A edge on a dead A).
  bool pass(bool a_line, bool b, bool& a) {
    a = a_line;
    if (fault_ != ChannelFault::none) {
      if (fault_ == ChannelFault::dead) {
        if (a_line != a_seen_) {  // an A edge: the dead channel shows none
          a_seen_ = a_line;
          return false;
        }
        a = stuck_a_;
      } else if (b != b_seen_ && ++edges_ % 5u == 0u) {
        a = !a;  // a glitch on A at a B edge: the decoder sees both change at once
      }
    }
    a_seen_ = a_line;
    b_seen_ = b;
    return true;
  }

 private:
  ChannelFault fault_ = ChannelFault::none;
  bool stuck_a_ = false;
  bool a_seen_ = false;
  bool b_seen_ = false;
  std::uint32_t edges_ = 0u;
};

/// One wheel's edge path: lines A and B -> sink. Must outlive the registration. It takes the
/// plant's concrete line and clock types (final classes): reading them on every edge then costs
/// no virtual call. `Sink` has `reset(a, b)` and `on_edge(a, b, t_us)`: a hal::EdgeSink (held by
/// value: a build that must not know the core's types) or a reference to a decoder (the host
/// simulator, where the decoder then inlines into the handler: one indirect call per edge).
template <class Sink>
class BasicEncoderWiring {
 public:
  BasicEncoderWiring(EncoderLine& a, EncoderLine& b, SimClock& clock, Sink sink)
      : a_(a), b_(b), clock_(clock), sink_(sink) {}

  BasicEncoderWiring(const BasicEncoderWiring&) = delete;
  BasicEncoderWiring& operator=(const BasicEncoderWiring&) = delete;

  /// Presets the sink to the current levels and registers the edge handler on both lines.
  /// Start-up only (not ISR-safe).
  void attach() {
    const bool a = a_.read();
    const bool b = b_.read();
    filter_.preset(a, b);
    sink_.reset(a, b);
    a_.on_edge(&BasicEncoderWiring::on_edge, this);
    b_.on_edge(&BasicEncoderWiring::on_edge, this);
  }

  /// From now on, channel A behaves as `fault` says. Not ISR-safe (call between edges).
  void set_fault(ChannelFault fault) { filter_.set_fault(fault, a_.read()); }

  /// Unregisters the handler from both lines.
  void detach() {
    a_.on_edge(nullptr, nullptr);
    b_.on_edge(nullptr, nullptr);
  }

 private:
  /// Edge context: latch the levels and the time into the sink, nothing else.
  static void on_edge(void* context) {
    auto* self = static_cast<BasicEncoderWiring*>(context);
    const bool b = self->b_.level();
    bool a = false;
    if (self->filter_.pass(self->a_.level(), b, a)) {
      self->sink_.on_edge(a, b, self->clock_.now_us());
    }
  }

  EncoderLine& a_;
  EncoderLine& b_;
  SimClock& clock_;
  Sink sink_;
  ChannelFilter filter_;
};

/// Through a hal::EdgeSink (the QEMU image, hal tests).
using EncoderWiring = BasicEncoderWiring<hal::EdgeSink>;

}  // namespace odocal::sim
