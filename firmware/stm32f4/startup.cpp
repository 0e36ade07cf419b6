// Reset handler and vector table of the STM32F405/407 (RM0090 table 61: 16 system exceptions,
// 82 device interrupts). Every device interrupt and SysTick go through the HAL's dispatch table,
// except EXTI lines 0..3, which the board serves straight from their vectors (board.hpp).

#include <array>
#include <cstdint>

#include "board.hpp"
#include "odocal/hal/stm32f4/cortex_m4.hpp"
#include "odocal/hal/stm32f4/interrupts.hpp"
#include "odocal/hal/stm32f4/irq.hpp"
#include "runtime.hpp"

extern "C" {
// Linker script symbols.
extern std::uint32_t __data_start[];
extern std::uint32_t __data_end[];
extern const std::uint32_t __data_load[];
extern std::uint32_t __bss_start[];
extern std::uint32_t __bss_end[];
extern std::uint32_t __stack_top[];
using InitFunction = void (*)();
extern const InitFunction __init_array_start[];
extern const InitFunction __init_array_end[];

int main();
[[noreturn]] void reset_handler();
}

namespace {

using Vector = void (*)();

void nmi_handler() {
  odocal::firmware::report_fault_and_stop(odocal::firmware::FaultKind::nmi, 0u, 0u);
}

}  // namespace

extern "C" [[noreturn]] __attribute__((section(".text.reset_handler"))) void reset_handler() {
  namespace scb = odocal::hal::stm32f4::scb;
  // FPU on before any float instruction can run (static constructors included): CP10 and CP11
  // to full access (0b11 each) in one write: PM0214 wants the two fields set alike.
  scb::cpacr.set(scb::cpacr_cp10.mask() | scb::cpacr_cp11.mask());
  __asm volatile("dsb\n isb" ::: "memory");

  // Word copies written as volatile loops so the compiler does not turn them into library calls
  // that might run before their own data exists.
  volatile std::uint32_t* dst = __data_start;
  const volatile std::uint32_t* src = __data_load;
  while (dst < __data_end) {
    *dst++ = *src++;
  }
  for (volatile std::uint32_t* p = __bss_start; p < __bss_end; ++p) {
    *p = 0u;
  }
  // Static constructors: __libc_init_array is not linked under -nostartfiles.
  for (const InitFunction* f = __init_array_start; f < __init_array_end; ++f) {
    (*f)();
  }
  const int status = main();
  odocal::firmware::exit_program(status);
}

namespace {

constexpr std::uint32_t handler_count = 15u + odocal::hal::stm32f4::irq::count;

// Exceptions 1..15, then every device interrupt through the dispatch table.
constexpr std::array<Vector, handler_count> make_handlers() {
  std::array<Vector, handler_count> h{};
  h[0] = reset_handler;
  h[1] = nmi_handler;
  h[2] = odocal::firmware::fault_entry;            // HardFault
  h[3] = odocal::firmware::fault_entry;            // MemManage
  h[4] = odocal::firmware::fault_entry;            // BusFault
  h[5] = odocal::firmware::fault_entry;            // UsageFault
  h[10] = odocal::firmware::unexpected_exception;  // SVCall
  h[11] = odocal::firmware::unexpected_exception;  // DebugMonitor
  h[13] = odocal::firmware::unexpected_exception;  // PendSV
  for (std::uint32_t i = 14u; i < handler_count; ++i) {
    h[i] = odocal::hal::stm32f4::dispatch_interrupt;  // SysTick and IRQ 0..81
  }
  namespace irq = odocal::hal::stm32f4::irq;
  h[15u + irq::exti0] = board_exti01_vector;
  h[15u + irq::exti1] = board_exti01_vector;
  h[15u + irq::exti2] = board_exti23_vector;
  h[15u + irq::exti3] = board_exti23_vector;
  return h;
}

/// What the core reads at address 0: the initial stack pointer, then the handlers.
struct VectorTable {
  std::uint32_t* initial_stack;
  std::array<Vector, handler_count> handlers;
};

}  // namespace

extern "C" __attribute__((section(".isr_vector"), used))
const VectorTable vector_table{__stack_top, make_handlers()};

static_assert(sizeof(VectorTable) == 4u * (16u + odocal::hal::stm32f4::irq::count),
              "one word per exception");
