#pragma once
/// @file
/// One reflective distance sensor of a maze robot: an infrared emitter the firmware switches and
/// a receiver (photodiode or phototransistor) read through a 12-bit ADC.

#include <cstdint>

namespace odocal::hal {

/// A wall sensor: the receiver sees the ambient light, and with the emitter on also the emitter's
/// light reflected by a wall, which grows as the wall comes closer. The backend owns the pins, the
/// ADC channel and how long the receiver takes to settle after the emitter switches on.
class WallSensor {
 public:
  /// The largest reading: a 12-bit ADC at full scale.
  static constexpr std::uint16_t full_scale_counts = 4095u;

  /// Switches the emitter on or off. ISR-safe.
  void set_emitter(bool on) { do_set_emitter(on); }

  /// One conversion of the receiver, raw ADC counts in [0, full_scale_counts] (a backend value
  /// above full scale is clamped). ISR-safe.
  [[nodiscard]] std::uint16_t read_counts() {
    const std::uint16_t counts = do_read_counts();
    return counts > full_scale_counts ? full_scale_counts : counts;
  }

  /// Time the receiver needs after the emitter switches on before its reading holds the reflected
  /// light, µs. ISR-safe.
  [[nodiscard]] std::uint32_t settle_us() const { return do_settle_us(); }

  /// One reading of the reflected light alone, counts: reads the ambient with the emitter off,
  /// switches the emitter on, waits `settle_us()`, reads again, switches the emitter off, and
  /// returns the second reading minus the first, 0 if it is lower (noise on a far wall). Leaves
  /// the emitter off. ISR-safe (it busy-waits the settle time, typically tens of µs, through the
  /// backend), but it must not interleave with another call on the same sensor.
  [[nodiscard]] std::uint16_t read_lit_counts() {
    set_emitter(false);
    const std::uint16_t ambient = read_counts();
    set_emitter(true);
    do_wait_settle();
    const std::uint16_t lit = read_counts();
    set_emitter(false);
    return lit > ambient ? static_cast<std::uint16_t>(lit - ambient) : std::uint16_t{0u};
  }

 protected:
  ~WallSensor() = default;

 private:
  virtual void do_set_emitter(bool on) = 0;
  virtual std::uint16_t do_read_counts() = 0;
  virtual std::uint32_t do_settle_us() const = 0;
  /// Returns `settle_us()` after being called (a busy wait on a bare-metal target; the simulator,
  /// whose time stands still inside a tick, returns at once).
  virtual void do_wait_settle() = 0;
};

}  // namespace odocal::hal
