#pragma once
/// @file
/// Connects two encoder lines to a quadrature decoder through the HAL edge callbacks, the way a
/// board file wires its EXTI lines: on every edge, sample both levels and the clock, and call
/// drive::QuadratureDecoder::on_edge. Used by the host simulator and the QEMU image.

#include "odocal/drive/quadrature_decoder.hpp"
#include "odocal/hal/digital_input.hpp"
#include "odocal/hal/monotonic_clock.hpp"

namespace odocal::sim {

/// One wheel's edge path: lines A and B -> decoder. Must outlive the registration.
class EncoderWiring {
 public:
  EncoderWiring(hal::DigitalInput& a, hal::DigitalInput& b, hal::MonotonicClock& clock,
                drive::QuadratureDecoder& decoder)
      : a_(a), b_(b), clock_(clock), decoder_(decoder) {}

  EncoderWiring(const EncoderWiring&) = delete;
  EncoderWiring& operator=(const EncoderWiring&) = delete;

  /// Presets the decoder to the current levels and registers the edge handler on both lines.
  /// Start-up only (not ISR-safe).
  void attach() {
    decoder_.reset(a_.read(), b_.read());
    a_.on_edge(&EncoderWiring::on_edge, this);
    b_.on_edge(&EncoderWiring::on_edge, this);
  }

  /// Unregisters the handler from both lines.
  void detach() {
    a_.on_edge(nullptr, nullptr);
    b_.on_edge(nullptr, nullptr);
  }

 private:
  /// Edge context: latch the levels and the time into the decoder, nothing else.
  static void on_edge(void* context) {
    auto* self = static_cast<EncoderWiring*>(context);
    self->decoder_.on_edge(self->a_.read(), self->b_.read(), self->clock_.now_us());
  }

  hal::DigitalInput& a_;
  hal::DigitalInput& b_;
  hal::MonotonicClock& clock_;
  drive::QuadratureDecoder& decoder_;
};

}  // namespace odocal::sim
