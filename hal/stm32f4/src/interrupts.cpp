#include "odocal/hal/stm32f4/interrupts.hpp"

#include <array>
#include <cstddef>

#include "odocal/hal/stm32f4/cortex_m4.hpp"
#include "odocal/hal/stm32f4/irq.hpp"

namespace odocal::hal::stm32f4 {
namespace {

struct Slot {
  InterruptHandler handler = nullptr;
  void* context = nullptr;
};

// Exceptions 15 (SysTick) .. 16 + irq::count - 1 map to a slot through one byte each: the images
// attach 3 to 7 handlers, so 8 slots and a 42-byte map take 106 B instead of 336 B for a slot
// per exception.
constexpr std::uint32_t first_exception = systick_exception;
constexpr std::size_t max_attached = 8u;
std::array<Slot, max_attached> slots{};
std::array<std::uint8_t, 1u + irq::count> slot_of{};  // 0: none attached; k: slots[k - 1]
std::size_t attached = 0u;

}  // namespace

void attach_interrupt(std::uint32_t exception, InterruptHandler handler, void* context) {
  if (exception < first_exception || exception - first_exception >= slot_of.size()) {
    return;
  }
  std::uint8_t& k = slot_of[exception - first_exception];
  if (k == 0u) {
    if (attached == max_attached) {
      return;  // more handlers than any board attaches: the interrupt stays unhandled (reported)
    }
    k = static_cast<std::uint8_t>(++attached);
  }
  slots[k - 1u] = Slot{handler, context};
}

void enable_irq(std::uint32_t irq, std::uint8_t priority) {
  if (irq >= irq::count) {
    return;  // no vector in the table (irq.hpp): it must never fire
  }
  nvic::ipr(irq).modify(nvic::ipr_field(irq), priority);
  nvic::iser(irq).write(nvic::irq_bit(irq));
}

void disable_irq(std::uint32_t irq) {
  nvic::icer(irq).write(nvic::irq_bit(irq));
}

void pend_irq(std::uint32_t irq) {
  nvic::ispr(irq).write(nvic::irq_bit(irq));
}

void set_systick_priority(std::uint8_t priority) {
  scb::shpr3.modify(scb::shpr3_systick, priority);
}

void enable_interrupts() {
  __asm volatile("cpsie i" ::: "memory");
}

bool disable_interrupts() {
  std::uint32_t primask;
  __asm volatile("mrs %0, primask\n cpsid i" : "=r"(primask)::"memory");
  return (primask & 1u) == 0u;
}

void wait_for_interrupt() {
  __asm volatile("dsb\n wfi" ::: "memory");
}

extern "C" void dispatch_interrupt() {
  std::uint32_t exception;
  __asm volatile("mrs %0, ipsr" : "=r"(exception));
  exception &= 0x1FFu;
  const std::uint32_t index = exception - first_exception;
  if (index < slot_of.size()) {
    const std::uint32_t k = slot_of[index];
    if (k != 0u && slots[k - 1u].handler != nullptr) {
      slots[k - 1u].handler(slots[k - 1u].context);
      return;
    }
  }
  unhandled_interrupt(exception);
}

void InterruptCriticalSection::do_enter() {
  const bool enabled = disable_interrupts();
  if (depth_++ == 0u) {
    was_enabled_ = enabled;
  }
}

void InterruptCriticalSection::do_exit() {
  if (depth_ == 0u) {
    return;
  }
  if (--depth_ == 0u && was_enabled_) {
    enable_interrupts();
  }
}

}  // namespace odocal::hal::stm32f4
