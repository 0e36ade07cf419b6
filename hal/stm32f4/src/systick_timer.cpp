#include "odocal/hal/stm32f4/systick_timer.hpp"

#include "odocal/hal/stm32f4/cortex_m4.hpp"
#include "odocal/hal/stm32f4/interrupts.hpp"

namespace odocal::hal::stm32f4 {

SysTickTimer::SysTickTimer(std::uint32_t core_hz, std::uint8_t priority)
    : core_hz_(core_hz), cycles_per_us_(core_hz / 1'000'000u), priority_(priority) {}

std::uint32_t SysTickTimer::do_start(std::uint32_t rate_hz, TickHandler handler, void* context) {
  do_stop();
  std::uint32_t cycles = (core_hz_ + rate_hz / 2u) / rate_hz;
  if (cycles > systick::max_reload + 1u) {
    cycles = systick::max_reload + 1u;  // slowest SysTick can go: ~10 Hz at 168 MHz
  }
  period_cycles_ = cycles;
  handler_ = handler;
  context_ = context;
  attach_interrupt(systick_exception, &SysTickTimer::on_interrupt, this);
  set_systick_priority(priority_);
  systick::load.write(cycles - 1u);
  systick::val.write(0u);
  systick::ctrl.write(systick::ctrl_enable.mask() | systick::ctrl_tickint.mask() |
                      systick::ctrl_clksource_core.mask());
  return (core_hz_ + cycles / 2u) / cycles;
}

void SysTickTimer::do_stop() {
  systick::ctrl.write(0u);
  scb::icsr.write(scb::icsr_pendstclr.mask());
}

void SysTickTimer::on_interrupt(void* self) {
  auto& timer = *static_cast<SysTickTimer*>(self);
  std::uint32_t rem = timer.base_rem_cycles_.load(std::memory_order_relaxed) + timer.period_cycles_;
  const std::uint32_t whole_us = rem / timer.cycles_per_us_;
  rem -= whole_us * timer.cycles_per_us_;
  timer.base_rem_cycles_.store(rem, std::memory_order_relaxed);
  timer.base_us_.store(timer.base_us_.load(std::memory_order_relaxed) + whole_us,
                       std::memory_order_release);
  timer.ticks_.fetch_add(1u, std::memory_order_relaxed);
  if (timer.handler_ != nullptr) {
    timer.handler_(timer.context_);
  }
}

std::uint32_t SysTickTimer::cycles_into_period() const {
  return systick::load.read() - systick::val.read();
}

std::uint32_t SysTickTimer::microseconds() const {
  std::uint32_t base = 0u;
  std::uint32_t rem = 0u;
  std::uint32_t value = 0u;
  bool pending = false;
  for (;;) {
    base = base_us_.load(std::memory_order_acquire);
    rem = base_rem_cycles_.load(std::memory_order_relaxed);
    const bool pending_before = scb::icsr.get(scb::icsr_pendstset) != 0u;
    value = systick::val.read();
    pending = scb::icsr.get(scb::icsr_pendstset) != 0u;
    // A changed base means the interrupt ran meanwhile; a changed pending flag means the counter
    // wrapped between the reads. Either way read again (at most once more in practice).
    if (pending == pending_before && base == base_us_.load(std::memory_order_acquire)) {
      break;
    }
  }
  // The counter runs down from LOAD; a pending wrap (seen from a context that masks SysTick)
  // adds the period that the interrupt has not yet accounted for.
  std::uint32_t cycles = rem + (systick::load.read() - value);
  if (pending) {
    cycles += period_cycles_;
  }
  return base + cycles / cycles_per_us_;
}

}  // namespace odocal::hal::stm32f4
