#pragma once
/// @file
/// Where an encoder backend delivers the edges of one wheel's two channels.

#include <cstdint>

namespace odocal::hal {

/// One wheel's receiver of quadrature edges: two plain functions and their context, so a backend
/// needs no type from the core. The firmware (or simulator) that owns the decoder fills it in
/// (`drive::edge_sink` makes one for a `drive::QuadratureDecoder`); the backend calls `preset`
/// once with the levels it found at start-up, then `edge` after every edge of either channel.
struct EdgeSink {
  /// Both channel levels after an edge and the edge's time in microseconds (wraps modulo 2^32).
  /// Called from the edge context (interrupt, event thread): must only latch and return.
  using EdgeFunction = void (*)(void* context, bool level_a, bool level_b, std::uint32_t t_us);
  /// The current levels, without counting. Start-up only, before edges are delivered.
  using PresetFunction = void (*)(void* context, bool level_a, bool level_b);

  EdgeFunction edge = nullptr;
  PresetFunction preset = nullptr;
  void* context = nullptr;

  void on_edge(bool level_a, bool level_b, std::uint32_t t_us) const {
    edge(context, level_a, level_b, t_us);
  }
  void reset(bool level_a, bool level_b) const { preset(context, level_a, level_b); }
};

}  // namespace odocal::hal
