#include "odocal/hal/stm32f4/systick_timer.hpp"

#include "odocal/hal/stm32f4/cortex_m4.hpp"
#include "odocal/hal/stm32f4/interrupts.hpp"

namespace odocal::hal::stm32f4 {

SysTickTimer::SysTickTimer(std::uint32_t core_hz, std::uint8_t priority)
    : core_hz_(core_hz), priority_(priority) {}

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
  timer.ticks_.fetch_add(1u, std::memory_order_relaxed);
  if (timer.handler_ != nullptr) {
    timer.handler_(timer.context_);
  }
}

std::uint32_t SysTickTimer::cycles_into_period() const {
  return systick::load.read() - systick::val.read();
}

}  // namespace odocal::hal::stm32f4
