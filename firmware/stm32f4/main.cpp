// The firmware application, the same on every board: the control loop in the SysTick interrupt,
// encoder edges from the board, the console in the main loop, the watchdog fed by a healthy tick.

#include <atomic>
#include <cstdint>

#include "board.hpp"
#include "built_once.hpp"
#include "odocal/console/console.hpp"
#include "odocal/drive/control_loop.hpp"
#include "odocal/hal/stm32f4/interrupts.hpp"
#include "odocal/hal/stm32f4/irq.hpp"
#include "odocal/hal/stm32f4/systick_timer.hpp"
#include "odocal/hal/stm32f4/watchdog.hpp"
#include "odocal/params/param_store.hpp"
#include "runtime.hpp"
#include "session_stream.hpp"

namespace odocal::firmware {
namespace {

namespace f4 = hal::stm32f4;

/// Nominal watchdog timeout; the LSI spread makes it 1.4..3.8 s. Longer than a flash sector
/// erase (0.5 s max), during which nothing runs.
constexpr std::uint32_t watchdog_timeout_ms = 2000u;
/// The tick feeds the watchdog only while the main loop has run within this long.
constexpr std::uint32_t main_loop_deadline_us = 1'000'000u;

/// What the tick interrupt needs; lives in `run()`.
struct TickContext {
  drive::ControlLoop& loop;
  f4::SysTickTimer& timer;
  hal::MonotonicClock& clock;
  float cycles_per_us;
  std::atomic<std::uint32_t> main_alive_us{0u};
};

std::uint32_t cycles_now(const TickContext& context) {
  return board_has_cycle_counter ? f4::CycleCounter::now() : context.timer.cycles_into_period();
}

/// The control tick. Tick context (SysTick, priority above the console, below the edges).
void on_tick(void* raw) {
  auto& context = *static_cast<TickContext*>(raw);
  board_before_tick();
  const std::uint32_t start = cycles_now(context);
  const std::uint32_t now_us = context.clock.now_us();
  context.loop.tick(now_us);
  std::uint32_t cycles = cycles_now(context) - start;
  if (!board_has_cycle_counter && cycles > context.timer.period_cycles()) {
    cycles += context.timer.period_cycles();  // SysTick reloaded meanwhile (tick overran)
  }
  context.loop.note_tick_duration_us(static_cast<float>(cycles) / context.cycles_per_us);
  // Healthy: this tick ran (it is the only feeder) and the main loop is alive.
  if (now_us - context.main_alive_us.load(std::memory_order_relaxed) < main_loop_deadline_us) {
    f4::Watchdog::feed();
  }
}

/// The board's pairs the console's start-up line carries (ConsoleOptions::banner_note):
/// ` board=.. clock=.. reset=..`. Built once at start-up; the console keeps a pointer to it.
char boot_note[48];

/// Appends the NUL-ended `parts` to `boot_note` (cut at its end). Start-up only.
void write_boot_note(const char* const* parts, std::size_t count) {
  std::size_t at = 0u;
  for (std::size_t p = 0u; p < count; ++p) {
    for (const char* c = parts[p]; *c != '\0' && at + 1u < sizeof boot_note; ++c) {
      boot_note[at++] = *c;
    }
  }
  boot_note[at] = '\0';
}

/// Tick rate from the parameter (the console may change `control_hz`).
std::uint32_t tick_rate_hz(const drive::ControlLoop& loop) {
  return static_cast<std::uint32_t>(loop.config().control_hz + 0.5f);
}

/// (Re)starts the tick at the loop's `control_hz`. @return that rate. Main loop.
[[gnu::noinline]] std::uint32_t start_tick(TickContext& tick) {
  const std::uint32_t rate_hz = tick_rate_hz(tick.loop);
  static_cast<void>(tick.timer.start(rate_hz, &on_tick, &tick));
  return rate_hz;
}

// What run() builds once (BuiltOnce: no guard variables).
BuiltOnce<f4::SysTickTimer> timer_storage;
BuiltOnce<drive::ControlLoop> loop_storage;
BuiltOnce<TickContext> tick_storage;
BuiltOnce<SessionStream> session_storage;
BuiltOnce<params::ParamStore> store_storage;
BuiltOnce<console::Console> console_storage;

[[noreturn]] void run() {
  const bool watchdog_reset = f4::Watchdog::caused_last_reset();
  BoardParts parts = board_init();
  const BoardInfo& info = board_info();

  static f4::InterruptCriticalSection critical;
  f4::SysTickTimer& timer = timer_storage.make(info.clock.sysclk_hz, f4::irq::priority_tick);
  drive::ControlLoop& loop =
      loop_storage.make(drive::MotorChannel{parts.left_pwm, parts.left_forward},
                        drive::MotorChannel{parts.right_pwm, parts.right_forward}, critical);
  hal::MonotonicClock& clock = board_clock(timer);
  TickContext& tick =
      tick_storage.make(loop, timer, clock, static_cast<float>(info.clock.sysclk_hz) * 1.0e-6f);
  // The console reads through SessionStream only where Ctrl-D ends the program (QEMU).
  SessionStream* const session =
      board_ends_session ? &session_storage.make(parts.console) : nullptr;
  hal::ByteStream& console_stream =
      session != nullptr ? static_cast<hal::ByteStream&>(*session) : parts.console;
  params::ParamStore& store = store_storage.make(parts.store);
  // The board's pairs ride on the console's start-up line, which waits for the first odocal
  // command: nothing is printed at power-up that a ROSArduinoBridge client could read as a reply.
  const char* const boot[] = {" board=", info.name,
                              " clock=", f4::clock_source_name(info.clock.source),
                              watchdog_reset ? " reset=watchdog" : " reset=power"};
  write_boot_note(boot, sizeof(boot) / sizeof(boot[0]));
  // Echo switches itself on when a person types (picocom/screen send CR for Enter).
  console::ConsoleOptions options{console::EchoMode::automatic, true, true, boot_note};
  if (board_has_wall_sensors) {  // the robot image links no copy of the empty table
    options.wall_sensors = parts.wall_sensors;
  }
  console::Console& console = console_storage.make(console_stream, loop, store, options);

  if (board_has_cycle_counter) {
    f4::CycleCounter::start();
  }
  board_start_encoders(loop.left_decoder(), loop.right_decoder());
  f4::enable_interrupts();  // the console UART from here on; the tick starts below

  // Loads the saved parameters into the loop (the flash is read before the tick runs).
  static_cast<void>(console.start(clock.now_us()));
  std::uint32_t rate_hz = start_tick(tick);
  f4::Watchdog::start(watchdog_timeout_ms);

  std::uint32_t last_rate_check_us = clock.now_us();
  for (;;) {
    const std::uint32_t now_us = clock.now_us();
    tick.main_alive_us.store(now_us, std::memory_order_relaxed);
    console.poll(now_us);
    if (now_us - last_rate_check_us > 100'000u) {
      last_rate_check_us = now_us;
      if (tick_rate_hz(loop) != rate_hz) {  // `set control_hz` took effect in the loop: follow it
        rate_hz = start_tick(tick);
      }
    }
    const bool idle = console.idle();
    if (session != nullptr && session->end_requested() && idle) {
      loop.stop();
      board_exit(0);
    }
    if (idle) {
      f4::wait_for_interrupt();  // every interrupt wakes the loop: the tick at least each period
    }
  }
}

}  // namespace
}  // namespace odocal::firmware

int main() {
  odocal::firmware::run();
}
