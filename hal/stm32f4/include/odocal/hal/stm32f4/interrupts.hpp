#pragma once
/// @file
/// Interrupt plumbing: a dispatch table from exception number to (handler, context), NVIC enable
/// and priority, and the PRIMASK critical section.
///
/// Every device interrupt vector and SysTick point at `dispatch_interrupt()`, which reads the
/// active exception number and calls what a backend attached there. So a backend object receives
/// its interrupt through a pointer it registered itself: no global object, no per-peripheral
/// vector function.

#include <cstdint>

#include "odocal/hal/critical_section.hpp"

namespace odocal::hal::stm32f4 {

/// An interrupt service function: `handler(context)`.
using InterruptHandler = void (*)(void* context);

/// Exception number of SysTick (the dispatch table also serves it).
inline constexpr std::uint32_t systick_exception = 15u;
/// Exception number of device interrupt `irq`.
[[nodiscard]] constexpr std::uint32_t exception_of_irq(std::uint32_t irq) {
  return irq + 16u;
}

/// Attaches `handler(context)` to exception `exception` (15 = SysTick, 16 + n = IRQ n).
/// Not ISR-safe: call during start-up, before the interrupt is enabled.
void attach_interrupt(std::uint32_t exception, InterruptHandler handler, void* context);

/// Sets the priority of device interrupt `irq` (0 = most urgent, upper four bits used) and
/// enables it in the NVIC; nothing for `irq` >= irq::count (no vector). Not ISR-safe
/// (read-modify-write of a shared priority word).
void enable_irq(std::uint32_t irq, std::uint8_t priority);
/// Disables device interrupt `irq` in the NVIC. ISR-safe (single write).
void disable_irq(std::uint32_t irq);
/// Marks device interrupt `irq` pending, so its handler runs as soon as its priority allows.
/// ISR-safe (single write).
void pend_irq(std::uint32_t irq);
/// Sets SysTick's priority. Not ISR-safe.
void set_systick_priority(std::uint8_t priority);

/// Enables interrupts globally (clears PRIMASK).
void enable_interrupts();
/// Disables interrupts globally; returns whether they were enabled before.
[[nodiscard]] bool disable_interrupts();
/// Sleeps until an interrupt (WFI).
void wait_for_interrupt();

/// The vector of every attached exception: calls the attached handler, or
/// `unhandled_interrupt` when none is attached. Interrupt context only.
extern "C" void dispatch_interrupt();

/// Called for an exception that has nothing attached. Defined by the firmware (it reports and
/// parks the motors).
extern "C" [[noreturn]] void unhandled_interrupt(std::uint32_t exception);

/// Masks every maskable interrupt (PRIMASK) while entered. Nesting restores the outer state.
/// One instance serves the whole image; enter/exit are ISR-safe.
class InterruptCriticalSection final : public hal::CriticalSection {
 private:
  void do_enter() override;
  void do_exit() override;
  std::uint32_t depth_ = 0u;
  bool was_enabled_ = false;
};

}  // namespace odocal::hal::stm32f4
