#pragma once
/// @file
/// The wall sensors a board can carry, as wiring tables for hal::stm32f4::AdcWallSensor: the usual
/// maze mouse's four. The mouse image (board_robot.cpp with ODOCAL_MOUSE_BOARD=1) builds one
/// AdcWallSensor per entry from the clock it reached, starts each, and passes them to the console
/// (ConsoleOptions::wall_sensors); the robot image has not the flash for them and the console's
/// reading loop (docs/stm32f4.md): its `walls` answers `err no_sensors`.

#include <array>
#include <cstddef>

#include "odocal/hal/stm32f4/adc.hpp"
#include "odocal/hal/stm32f4/adc_wall_sensor.hpp"
#include "odocal/hal/stm32f4/gpio.hpp"

namespace odocal::firmware {

/// The usual mouse's sensors in the console's order (ConsoleOptions::wall_sensors): left front,
/// left diagonal, right diagonal, right front. Receivers on ADC1_IN0..3 (PA0..PA3), emitters on
/// PC6..PC9 (high = on, through each emitter's driver transistor): pins the robot board leaves
/// free (docs/wiring.md). Settle 30 µs: the simulator's 20 µs (sim::SimWallSensor) with room for a
/// slower phototransistor; measure a real receiver's rise and set it here. Sample time 84 ADC
/// cycles (4 µs at 21 MHz) for a receiver's load resistor of tens of kΩ.
inline constexpr std::array<hal::stm32f4::WallSensorWiring, 4> usual_mouse_wall_sensors{{
    {{hal::stm32f4::gpio::Port::c, 6u}, 0u, 30u, hal::stm32f4::adc::SampleTime::cycles_84},
    {{hal::stm32f4::gpio::Port::c, 7u}, 1u, 30u, hal::stm32f4::adc::SampleTime::cycles_84},
    {{hal::stm32f4::gpio::Port::c, 8u}, 2u, 30u, hal::stm32f4::adc::SampleTime::cycles_84},
    {{hal::stm32f4::gpio::Port::c, 9u}, 3u, 30u, hal::stm32f4::adc::SampleTime::cycles_84},
}};

/// True when every sensor of `sensors` is wired validly, on a channel and an emitter pin of its
/// own, and no sensor's emitter sits on another's receiver.
template <std::size_t count>
[[nodiscard]] constexpr bool distinct_wall_sensors(
    const std::array<hal::stm32f4::WallSensorWiring, count>& sensors) {
  for (std::size_t i = 0u; i < count; ++i) {
    if (!hal::stm32f4::valid_wiring(sensors[i])) {
      return false;
    }
    for (std::size_t j = 0u; j < count; ++j) {
      const hal::stm32f4::gpio::Pin receiver_j = hal::stm32f4::adc::channel_pin(sensors[j].channel);
      const bool on_receiver = sensors[i].emitter.port == receiver_j.port &&
                               sensors[i].emitter.number == receiver_j.number;
      const bool same_emitter = sensors[i].emitter.port == sensors[j].emitter.port &&
                                sensors[i].emitter.number == sensors[j].emitter.number;
      if (on_receiver || (i != j && (same_emitter || sensors[i].channel == sensors[j].channel))) {
        return false;
      }
    }
  }
  return true;
}

static_assert(distinct_wall_sensors(usual_mouse_wall_sensors),
              "each sensor on its own channel and emitter pin");

}  // namespace odocal::firmware
