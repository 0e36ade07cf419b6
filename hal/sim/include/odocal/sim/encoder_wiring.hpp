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

/// One wheel's edge path: lines A and B -> sink. Must outlive the registration. It takes the
/// plant's concrete line and clock types (final classes): reading them on every edge then costs
/// no virtual call.
class EncoderWiring {
 public:
  EncoderWiring(EncoderLine& a, EncoderLine& b, SimClock& clock, const hal::EdgeSink& sink)
      : a_(a), b_(b), clock_(clock), sink_(sink) {}

  EncoderWiring(const EncoderWiring&) = delete;
  EncoderWiring& operator=(const EncoderWiring&) = delete;

  /// Presets the sink to the current levels and registers the edge handler on both lines.
  /// Start-up only (not ISR-safe).
  void attach() {
    a_seen_ = a_.read();
    b_seen_ = b_.read();
    sink_.reset(a_seen_, b_seen_);
    a_.on_edge(&EncoderWiring::on_edge, this);
    b_.on_edge(&EncoderWiring::on_edge, this);
  }

  /// From now on, channel A behaves as `fault` says. Not ISR-safe (call between edges).
  void set_fault(ChannelFault fault) {
    fault_ = fault;
    stuck_a_ = a_.read();
    edges_ = 0u;
  }

  /// Unregisters the handler from both lines.
  void detach() {
    a_.on_edge(nullptr, nullptr);
    b_.on_edge(nullptr, nullptr);
  }

 private:
  /// Edge context: latch the levels and the time into the sink, nothing else.
  static void on_edge(void* context) {
    auto* self = static_cast<EncoderWiring*>(context);
    const bool a_line = self->a_.level();
    const bool b = self->b_.level();
    bool a = a_line;
    if (self->fault_ != ChannelFault::none) {
      if (self->fault_ == ChannelFault::dead) {
        if (a_line != self->a_seen_) {  // an A edge: the dead channel shows none
          self->a_seen_ = a_line;
          return;
        }
        a = self->stuck_a_;
      } else if (b != self->b_seen_ && ++self->edges_ % 5u == 0u) {
        a = !a;  // a glitch on A at a B edge: the decoder sees both change at once
      }
    }
    self->a_seen_ = a_line;
    self->b_seen_ = b;
    self->sink_.on_edge(a, b, self->clock_.now_us());
  }

  EncoderLine& a_;
  EncoderLine& b_;
  SimClock& clock_;
  const hal::EdgeSink sink_;
  ChannelFault fault_ = ChannelFault::none;
  bool stuck_a_ = false;
  bool a_seen_ = false;
  bool b_seen_ = false;
  std::uint32_t edges_ = 0u;
};

}  // namespace odocal::sim
