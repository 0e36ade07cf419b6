// Board: QEMU netduinoplus2 (an STM32F405 model). QEMU 7.2 models the USARTs, TIM2..5, SysTick,
// EXTI and SYSCFG, but no GPIO, RCC, flash controller, IWDG or DWT (reads 0, writes ignored).
// So this image skips the clock set-up (QEMU's core clock is 168 MHz), keeps the parameter store
// in RAM, and makes the encoder edges with the simulated plant of hal/sim, advanced in a TIM2
// interrupt and wired to the real decoders. Which robot the plant is, and the wall sensors it
// carries, comes from the twin file linked beside this one (qemu_twin.hpp). Everything else is the
// robot image.

#include <cstdint>

#include "board.hpp"
#include "odocal/hal/stm32f4/interrupts.hpp"
#include "odocal/hal/stm32f4/irq.hpp"
#include "odocal/hal/stm32f4/microsecond_timer.hpp"
#include "odocal/hal/stm32f4/rcc.hpp"
#include "odocal/hal/stm32f4/tim.hpp"
#include "odocal/hal/stm32f4/usart.hpp"
#include "odocal/hal/stm32f4/usart_stream.hpp"
#include "odocal/sim/encoder_wiring.hpp"
#include "odocal/sim/plant.hpp"
#include "odocal/sim/ram_block_store.hpp"
#include "qemu_twin.hpp"
#include "runtime.hpp"

namespace odocal::firmware {
namespace {

namespace f4 = hal::stm32f4;

// --- constants of this board ---
constexpr std::uint32_t core_hz = 168'000'000u;
/// The plant's interrupt: TIM2's vector at edge priority, pended by software from the tick.
/// (QEMU 7.2's STM32 timer cannot raise a periodic interrupt: it arms each alarm at
/// 2·now + ARR, so the periods grow without bound; with PSC != 0 it hangs. Its timers count at
/// 1 GHz with PSC = 0. So the plant is triggered from SysTick, which QEMU models correctly.)
constexpr std::uint32_t plant_irq = f4::irq::tim2;
/// Deterministic floor: the same seed every boot.
constexpr std::uint64_t plant_seed = 1u;
/// RAM store: two 4 KiB sectors (the parameter store's A and B), word granularity like the F4.
constexpr std::size_t store_sector_bytes = 4096u;

// QEMU's first serial port (-serial stdio) is USART1. The baud rate has no effect there.
constexpr f4::UsartConfig console_config{f4::usart::usart1, f4::irq::usart1, core_hz / 2u, 115200u,
                                         f4::irq::priority_console};

const BoardInfo info{twin_name,
                     f4::ClockReport{f4::ClockSource::hse_pll, core_hz, core_hz / 4u, core_hz / 2u},
                     f4::usart::usart1};

f4::UsartStream console{console_config};
sim::StaticRamBlockStore<store_sector_bytes, 2u, 4u> store;
sim::Plant plant{twin_robot_model(), plant_seed};

/// Plant time follows the firmware clock: 64-bit ns built from wrapping µs differences.
struct PlantDriver {
  hal::MonotonicClock* clock = nullptr;
  std::uint32_t last_us = 0u;
  std::uint64_t t_ns = 0u;
};
PlantDriver driver;

/// Ticks seen, TIM2 time and application-clock (TIM5) time elapsed from the first tick to the
/// last (for the tick-rate and clock-rate checks).
struct Session {
  std::uint32_t ticks = 0u;
  std::uint32_t last_count = 0u;
  std::uint64_t timer_ns = 0u;
  std::uint32_t first_clock_us = 0u;
  std::uint32_t last_clock_us = 0u;
  bool started = false;
};
Session session;

void format_decimal(std::uint32_t value, char* out) {
  char digits[10];
  std::size_t n = 0u;
  do {
    digits[n++] = static_cast<char>('0' + value % 10u);
    value /= 10u;
  } while (value != 0u);
  for (std::size_t i = 0u; i < n; ++i) {
    out[i] = digits[n - 1u - i];
  }
  out[n] = '\0';
}

void on_plant_timer(void* context) {
  auto& d = *static_cast<PlantDriver*>(context);
  const std::uint32_t now = d.clock->now_us();
  d.t_ns += static_cast<std::uint64_t>(now - d.last_us) * 1000u;
  d.last_us = now;
  plant.advance_to_ns(d.t_ns);  // edges reach the decoders from inside this call
}

}  // namespace

const bool board_has_cycle_counter = false;
const bool board_ends_session = true;
const bool board_has_wall_sensors = twin_has_wall_sensors;

const BoardInfo& board_info() {
  return info;
}

BoardParts board_init() {
  console.start();
  return BoardParts{console,
                    store,
                    plant.left().pwm(),
                    plant.left().forward(),
                    plant.right().pwm(),
                    plant.right().forward(),
                    twin_wall_sensors(plant)};
}

extern "C" void board_exti01_vector() {
  f4::dispatch_interrupt();  // no EXTI lines here: unattached, so reported as unexpected
}
extern "C" void board_exti23_vector() {
  f4::dispatch_interrupt();
}

hal::MonotonicClock& board_clock(f4::SysTickTimer& /*systick*/) {
  // The robot's clock class on the same TIM5: QEMU's timers count at 1 GHz, so a "1 GHz timer
  // clock" makes PSC = 999 and the count 1 MHz, as on the robot with PSC = 83.
  static f4::MicrosecondTimer clock{f4::tim::tim5, f4::rcc::apb1enr_tim5};
  clock.start(1'000'000'000u);
  driver.clock = &clock;
  return clock;
}

void board_start_encoders(drive::QuadratureDecoder& left, drive::QuadratureDecoder& right) {
  // The decoders take the plant's clock, which the plant sets to each edge's crossing instant.
  static sim::EncoderWiring left_wiring{plant.left().channel_a(), plant.left().channel_b(),
                                        plant.clock(), drive::edge_sink(left)};
  static sim::EncoderWiring right_wiring{plant.right().channel_a(), plant.right().channel_b(),
                                         plant.clock(), drive::edge_sink(right)};
  // Plant time = firmware time (same epoch), so edge stamps and tick stamps compare directly.
  driver.last_us = driver.clock->now_us();
  driver.t_ns = static_cast<std::uint64_t>(driver.last_us) * 1000u;
  plant.advance_to_ns(driver.t_ns);
  left_wiring.attach();
  right_wiring.attach();

  f4::attach_interrupt(f4::exception_of_irq(plant_irq), &on_plant_timer, &driver);
  f4::enable_irq(plant_irq, f4::irq::priority_edges);

  f4::rcc::apb1enr.set(f4::rcc::apb1enr_tim2.mask());
  f4::tim::psc(f4::tim::tim2).write(0u);
  f4::tim::cr1(f4::tim::tim2).write(f4::tim::cr1_cen.mask());
}

void board_before_tick() {
  // An independent clock for the tick-rate check: TIM2's counter, which QEMU derives from its
  // virtual clock at 1 GHz (PSC = 0; reading it is exact, only its alarms are broken).
  // Counted from the first tick on: periods between ticks against TIM2 time.
  const std::uint32_t count = f4::tim::cnt(f4::tim::tim2).read();
  const std::uint32_t clock_us = driver.clock->now_us();
  if (session.started) {
    session.timer_ns += count - session.last_count;
    ++session.ticks;
  } else {
    session.first_clock_us = clock_us;
  }
  session.started = true;
  session.last_count = count;
  session.last_clock_us = clock_us;
  // Pending a more urgent interrupt from the tick preempts it at once: the plant (and its
  // edges) catch up to now before the control tick samples the decoders.
  f4::pend_irq(plant_irq);
  __asm volatile("dsb\n isb" ::: "memory");  // taken here, not a few instructions later
}

void board_park_motors() {
  plant.left().pwm().set_duty(0.0f);
  plant.right().pwm().set_duty(0.0f);
}

void board_exit(int status) {
  // The session's tick count and the application clock's time against TIM2's time: the test
  // checks that the tick kept its rate and that the µs clock (TIM5, prescaled) counts µs.
  char ticks[11];
  char micros[11];
  char clock[11];
  format_decimal(session.ticks, ticks);
  format_decimal(static_cast<std::uint32_t>(session.timer_ns / 1000u), micros);
  format_decimal(session.last_clock_us - session.first_clock_us, clock);
  f4::UsartStream::emergency_write(f4::usart::usart1, "# qemu-session ticks=");
  f4::UsartStream::emergency_write(f4::usart::usart1, ticks);
  f4::UsartStream::emergency_write(f4::usart::usart1, " timer_us=");
  f4::UsartStream::emergency_write(f4::usart::usart1, micros);
  f4::UsartStream::emergency_write(f4::usart::usart1, " clock_us=");
  f4::UsartStream::emergency_write(f4::usart::usart1, clock);
  f4::UsartStream::emergency_write(f4::usart::usart1, "\r\n");
  semihosting_exit(status);
}

}  // namespace odocal::firmware
