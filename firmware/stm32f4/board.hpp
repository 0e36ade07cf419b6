#pragma once
/// @file
/// What the application needs from a board. One board file per image implements these:
/// board_robot.cpp (the real robot) and board_qemu.cpp (QEMU netduinoplus2, with the robot it
/// simulates from qemu_twin_robot.cpp or qemu_twin_mouse.cpp). The image is chosen by which one
/// is linked.

#include <array>
#include <cstdint>

#include "odocal/console/console.hpp"
#include "odocal/drive/quadrature_decoder.hpp"
#include "odocal/hal/block_store.hpp"
#include "odocal/hal/byte_stream.hpp"
#include "odocal/hal/digital_output.hpp"
#include "odocal/hal/monotonic_clock.hpp"
#include "odocal/hal/pwm_output.hpp"
#include "odocal/hal/stm32f4/clock.hpp"
#include "odocal/hal/stm32f4/mmio.hpp"
#include "odocal/hal/stm32f4/systick_timer.hpp"
#include "odocal/hal/wall_sensor.hpp"

/// The vectors of EXTI lines 0 and 1 (one function for both) and of lines 2 and 3, which the
/// board serves itself (the vector table points at them, not at the HAL's dispatch table): the
/// robot's encoder edges, a wheel's two channels on a pair of lines, so an edge costs no table
/// lookup and no indirect call. A board without such lines forwards them to
/// `hal::stm32f4::dispatch_interrupt`.
extern "C" {
void board_exti01_vector();
void board_exti23_vector();
}

namespace odocal::firmware {

/// Constants the application reads from the board.
struct BoardInfo {
  const char* name;                   ///< "robot", "qemu" or "qemu-mouse"
  hal::stm32f4::ClockReport clock;    ///< after `board_init`
  hal::stm32f4::Block console_usart;  ///< for fault reports by polling
};

/// DWT->CYCCNT counts (not in QEMU). A constant of the board, so the link folds the other branch
/// of every test of it away.
extern const bool board_has_cycle_counter;
/// Ctrl-D (0x04) on the console ends the program (`board_exit(0)`): the QEMU image's session
/// end. The robot has none: a 0x04 is a control byte like any other there (`err non_ascii`).
/// A constant of the board, as above.
extern const bool board_ends_session;

/// The board has wall sensors (BoardParts::wall_sensors holds one at least). A constant of the
/// board, as above: the robot image links no copy of the empty table.
extern const bool board_has_wall_sensors;

/// A board's wall sensors in the console's order (ConsoleOptions::wall_sensors).
using BoardWallSensors = std::array<hal::WallSensor*, console::wall_sensor_slots>;

/// The board's HAL objects, for the application to wire into the core.
struct BoardParts {
  hal::ByteStream& console;
  hal::BlockStore& store;
  hal::PwmOutput& left_pwm;
  hal::DigitalOutput& left_forward;
  hal::PwmOutput& right_pwm;
  hal::DigitalOutput& right_forward;
  /// The wall sensors `walls` reads (ConsoleOptions::wall_sensors), nullptr where there is none:
  /// the robot board has none (docs/stm32f4.md), the mouse image four on ADC1, the QEMU mouse twin
  /// four simulated.
  BoardWallSensors wall_sensors{};
};

/// Clock tree, pins, console, PWM, store. Interrupts still disabled. Called once, first.
BoardParts board_init();
/// Info filled by `board_init`.
const BoardInfo& board_info();
/// The application's microsecond clock, started: what the tick, the console and the edge stamps
/// all read. Robot: TIM5 free-running at 1 MHz (one register load per edge); QEMU: `systick`'s
/// own clock (QEMU's timers count at a fixed 1 GHz whatever their prescaler). After `board_init`.
hal::MonotonicClock& board_clock(hal::stm32f4::SysTickTimer& systick);
/// Starts the encoder edges: every edge of a wheel's A or B line feeds that wheel's decoder from
/// the edge interrupt, stamped with `board_clock`'s time. Robot: EXTI lines 0..3; QEMU: the
/// simulated plant, advanced to the clock's time in a timer interrupt. Call after `board_clock`,
/// before interrupts are enabled.
void board_start_encoders(drive::QuadratureDecoder& left, drive::QuadratureDecoder& right);
/// Runs at the start of every control tick, before it samples the encoders (tick context).
/// QEMU: brings the simulated plant up to now; robot: nothing.
void board_before_tick();
/// Duty 0 on both H-bridges and the drivers disabled, with no dependency on the core or on
/// interrupts: the fault path. Any context.
void board_park_motors();
/// Ends the program (see exit_program).
[[noreturn]] void board_exit(int status);

}  // namespace odocal::firmware
