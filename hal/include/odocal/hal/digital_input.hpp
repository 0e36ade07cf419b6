#pragma once
/// @file
/// Digital input line with an edge callback (encoder channels).

namespace odocal::hal {

/// Called on every edge of the line, from interrupt context (bare metal), the event thread
/// (Linux) or the simulator's event loop. Must only latch state and return.
using EdgeHandler = void (*)(void* context);

/// A digital input line that can report both edges.
class DigitalInput {
 public:
  /// Current level of the line. ISR-safe.
  bool read() { return do_read(); }

  /// Registers `handler(context)` to run on both edges; nullptr disables it. Not ISR-safe:
  /// call once during start-up, before interrupts are enabled.
  void on_edge(EdgeHandler handler, void* context) { do_on_edge(handler, context); }

 protected:
  ~DigitalInput() = default;

 private:
  virtual bool do_read() = 0;
  virtual void do_on_edge(EdgeHandler handler, void* context) = 0;
};

}  // namespace odocal::hal
