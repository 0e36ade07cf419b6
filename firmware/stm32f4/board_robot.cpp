// Board: the robot. An STM32F405/407 at 168 MHz from an 8 MHz crystal, two H-bridges
// (PWM + direction, one shared enable), two quadrature encoders on EXTI lines, the console on
// USART1, the parameters in flash sectors 1 and 2. docs/wiring.md draws it. Built with
// ODOCAL_MOUSE_BOARD=1 (odocal-fw-mouse) it is a maze mouse: the same board with the usual
// mouse's four wall sensors (board_wall_sensors.hpp), which `walls` reads.

#ifndef ODOCAL_MOUSE_BOARD
#define ODOCAL_MOUSE_BOARD 0
#endif

#include <cstddef>
#include <cstdint>
#include <initializer_list>

#include "board.hpp"
#include "board_wall_sensors.hpp"
#include "built_once.hpp"
#include "odocal/hal/stm32f4/adc_wall_sensor.hpp"
#include "odocal/hal/stm32f4/cortex_m4.hpp"
#include "odocal/hal/stm32f4/encoder_edge.hpp"
#include "odocal/hal/stm32f4/flash_store.hpp"
#include "odocal/hal/stm32f4/gpio_pins.hpp"
#include "odocal/hal/stm32f4/irq.hpp"
#include "odocal/hal/stm32f4/microsecond_timer.hpp"
#include "odocal/hal/stm32f4/rcc.hpp"
#include "odocal/hal/stm32f4/tim.hpp"
#include "odocal/hal/stm32f4/timer_pwm.hpp"
#include "odocal/hal/stm32f4/usart.hpp"
#include "odocal/hal/stm32f4/usart_stream.hpp"

namespace odocal::firmware {
namespace {

namespace f4 = hal::stm32f4;
using f4::gpio::Pin;
using f4::gpio::Port;

// --- pin map (docs/wiring.md) ---
constexpr Pin console_tx{Port::a, 9u};   // USART1_TX, AF7
constexpr Pin console_rx{Port::a, 10u};  // USART1_RX, AF7
constexpr std::uint8_t af_usart1 = 7u;
constexpr Pin left_pwm_pin{Port::a, 6u};   // TIM3_CH1, AF2
constexpr Pin right_pwm_pin{Port::a, 7u};  // TIM3_CH2, AF2
constexpr std::uint8_t af_tim3 = 2u;
constexpr Pin left_dir_pin{Port::b, 0u};        // high = forward
constexpr Pin right_dir_pin{Port::b, 1u};       // high = forward
constexpr Pin driver_enable_pin{Port::b, 12u};  // high = H-bridges enabled (TB6612 STBY)
// Encoders: one EXTI line (and vector) per channel, all on port C so one IDR read samples both.
constexpr Port encoder_port = Port::c;
constexpr Pin left_a_pin{encoder_port, 0u};   // EXTI0
constexpr Pin left_b_pin{encoder_port, 1u};   // EXTI1
constexpr Pin right_a_pin{encoder_port, 2u};  // EXTI2
constexpr Pin right_b_pin{encoder_port, 3u};  // EXTI3

/// The usual mouse's wall sensors (board_wall_sensors.hpp, built in the mouse image): their pins
/// stay free of this map, and of SWD.
constexpr bool wall_sensor_pins_free() {
  const Pin used[] = {console_tx,       console_rx,    left_pwm_pin,      right_pwm_pin,
                      left_dir_pin,     right_dir_pin, driver_enable_pin, left_a_pin,
                      left_b_pin,       right_a_pin,   right_b_pin,       Pin{Port::a, 13u},
                      Pin{Port::a, 14u}};
  for (const hal::stm32f4::WallSensorWiring& sensor : usual_mouse_wall_sensors) {
    for (const Pin pin : {sensor.emitter, f4::adc::channel_pin(sensor.channel)}) {
      for (const Pin taken : used) {
        if (pin.port == taken.port && pin.number == taken.number) {
          return false;
        }
      }
    }
  }
  return true;
}
static_assert(wall_sensor_pins_free(), "the wall sensors' pins are taken by the robot's pin map");

// --- clocks and peripherals ---
constexpr f4::ClockPlan clock_plan{8'000'000u, 168'000'000u, 200'000u};
constexpr std::uint32_t pwm_carrier_hz = 20'000u;
constexpr std::uint8_t left_pwm_channel = 1u;
constexpr std::uint8_t right_pwm_channel = 2u;
constexpr std::size_t store_first_sector = 1u;  // sectors 1 and 2, 16 KiB each (linker script)
constexpr std::size_t store_sectors = 2u;

/// The mouse image: this board with the usual mouse's wall sensors. The robot image has no flash
/// for them and the console's reading loop (docs/stm32f4.md): its `walls` answers err no_sensors.
constexpr bool mouse = ODOCAL_MOUSE_BOARD != 0;

BoardInfo info{mouse ? "mouse" : "robot", f4::ClockReport{}, f4::usart::usart1};

f4::GpioOutput left_forward{left_dir_pin, true};
f4::GpioOutput right_forward{right_dir_pin, true};
f4::GpioOutput driver_enable{driver_enable_pin, false};
/// Register and flash-memory access: the flash store's, and the edge path's.
f4::MemoryBus memory_bus;

/// The application's clock: TIM5 counting microseconds, started first thing in board_init (the
/// flash store's timeouts read it too).
constexpr f4::Block us_timer = f4::tim::tim5;
f4::MicrosecondTimer us_clock{us_timer, f4::rcc::apb1enr_tim5};
f4::FlashStore store{memory_bus, us_clock, store_first_sector, store_sectors};

drive::QuadratureDecoder* left_decoder = nullptr;
drive::QuadratureDecoder* right_decoder = nullptr;

/// One wheel's edge, served straight from its EXTI vector (each vector is flattened: the decoder
/// is inlined, the whole edge path is one function without a call). Lines = pin numbers (port C,
/// EXTICR routes them); the stamp is TIM5's count.
template <std::uint8_t a_line, std::uint8_t b_line>
inline void serve_edge(drive::QuadratureDecoder& decoder) {
  f4::serve_encoder_edge<a_line, b_line>(memory_bus, encoder_port, us_timer, decoder);
}

// What board_init builds once, from the clock it reached (BuiltOnce: no guard variables).
BuiltOnce<f4::UsartStream> console_storage;
/// The mouse's wall sensors (the robot image links none of them).
using WallSensor = f4::AdcWallSensor<f4::MemoryBus>;
BuiltOnce<WallSensor> wall_sensor_storage[usual_mouse_wall_sensors.size()];
BuiltOnce<f4::TimerPwm> left_pwm_storage;
BuiltOnce<f4::TimerPwm> right_pwm_storage;

/// TIM3 and TIM5 input clock, from the clock actually reached: 2 · PCLK1 unless APB1 is
/// undivided (the 16 MHz HSI fallback, no PLL: the PWM is then coarser, 800 steps not 4200).
std::uint32_t apb1_timer_hz() {
  return info.clock.pclk1_hz == info.clock.sysclk_hz ? info.clock.pclk1_hz
                                                     : 2u * info.clock.pclk1_hz;
}

}  // namespace

extern "C" [[gnu::flatten]] void board_exti01_vector() {
  serve_edge<left_a_pin.number, left_b_pin.number>(*left_decoder);
}
extern "C" [[gnu::flatten]] void board_exti23_vector() {
  serve_edge<right_a_pin.number, right_b_pin.number>(*right_decoder);
}

const bool board_has_cycle_counter = true;
const bool board_ends_session = false;
const bool board_has_wall_sensors = mouse;

const BoardInfo& board_info() {
  return info;
}

BoardParts board_init() {
  info.clock = f4::configure_clock(clock_plan);
  us_clock.start(apb1_timer_hz());
  // Built from the clock actually reached: on the 16 MHz HSI fallback the baud rate is the same.
  f4::UsartStream& console = console_storage.make(f4::UsartConfig{
      f4::usart::usart1, f4::irq::usart1, info.clock.pclk2_hz, 115200u, f4::irq::priority_console});
  const f4::PwmTimerConfig pwm_timer{f4::tim::tim3, apb1_timer_hz(), pwm_carrier_hz};
  f4::TimerPwm& left_pwm = left_pwm_storage.make(pwm_timer, left_pwm_channel);
  f4::TimerPwm& right_pwm = right_pwm_storage.make(pwm_timer, right_pwm_channel);
  driver_enable.start();  // low: H-bridges off until the PWM runs at duty 0
  left_forward.start();
  right_forward.start();
  // Each group of pins set up by one call in a loop: a call site with its five arguments took
  // ~20 B of flash.
  for (const Pin pin : {console_tx, console_rx}) {
    f4::configure_pin(pin, f4::gpio::Mode::alternate, f4::gpio::Pull::up, f4::gpio::Speed::medium,
                      af_usart1);
  }
  f4::rcc::apb2enr.set(f4::rcc::apb2enr_usart1.mask());
  console.start();

  left_pwm.start();
  right_pwm.start();
  f4::start_pwm_timer(pwm_timer);
  for (const Pin pin : {left_pwm_pin, right_pwm_pin}) {
    f4::configure_pin(pin, f4::gpio::Mode::alternate, f4::gpio::Pull::none, f4::gpio::Speed::fast,
                      af_tim3);
  }
  driver_enable.set(true);
  BoardParts parts{console, store, left_pwm, left_forward, right_pwm, right_forward};
  if constexpr (mouse) {
    // Each sensor from the clock reached: its settle wait counts core cycles, its ADC prescaler
    // divides PCLK2.
    for (std::size_t i = 0u; i < usual_mouse_wall_sensors.size(); ++i) {
      WallSensor& sensor =
          wall_sensor_storage[i].make(memory_bus, usual_mouse_wall_sensors[i], info.clock);
      sensor.start();
      parts.wall_sensors[i] = &sensor;
    }
  }
  return parts;
}

hal::MonotonicClock& board_clock(f4::SysTickTimer& /*systick*/) {
  return us_clock;  // started by board_init
}

void board_start_encoders(drive::QuadratureDecoder& left, drive::QuadratureDecoder& right) {
  left_decoder = &left;
  right_decoder = &right;
  for (const Pin pin : {left_a_pin, left_b_pin, right_a_pin, right_b_pin}) {
    f4::start_exti_line(pin, f4::gpio::Pull::up, f4::irq::priority_edges);
  }
  // Levels as they are now, before the first edge interrupt.
  const std::uint32_t levels = f4::gpio::idr(encoder_port).read();
  left.reset(((levels >> left_a_pin.number) & 1u) != 0u,
             ((levels >> left_b_pin.number) & 1u) != 0u);
  right.reset(((levels >> right_a_pin.number) & 1u) != 0u,
              ((levels >> right_b_pin.number) & 1u) != 0u);
}

void board_before_tick() {}

void board_park_motors() {
  f4::force_pwm_zero(f4::tim::tim3, left_pwm_channel);
  f4::force_pwm_zero(f4::tim::tim3, right_pwm_channel);
  f4::gpio::bsrr(driver_enable_pin.port).write(1u << (driver_enable_pin.number + 16u));
}

void board_exit(int) {
  board_park_motors();
  // Let the last report leave the UART (about 90 µs per byte), then reset.
  for (std::uint32_t i = 0u; i < 2'000'000u; ++i) {
    if ((f4::usart::sr(f4::usart::usart1).read() & f4::usart::sr_tc.mask()) != 0u) {
      break;
    }
  }
  f4::scb::aircr.write(f4::scb::aircr_key | f4::scb::aircr_sysresetreq.mask());
  for (;;) {
  }
}

}  // namespace odocal::firmware
