#include "runtime.hpp"

#include <cstddef>
#include <new>

#include "board.hpp"
#include "odocal/hal/stm32f4/cortex_m4.hpp"
#include "odocal/hal/stm32f4/interrupts.hpp"
#include "odocal/hal/stm32f4/usart_stream.hpp"
#include "odocal/name_list.hpp"

namespace odocal::firmware {
namespace {

const char* kind_name(FaultKind kind) {
  // In FaultKind's order (name_list.hpp: one string instead of a table of pointers).
  static constexpr char names[] =
      "hard\0memmanage\0bus\0usage\0nmi\0exception\0irq\0heap\0pure-virtual";
  static_assert(nul_count(names) == static_cast<std::size_t>(FaultKind::pure_virtual) + 1u,
                "one name per FaultKind, in its order");
  const auto n = static_cast<unsigned>(kind);
  return name_at(names, n <= static_cast<unsigned>(FaultKind::pure_virtual)
                            ? n
                            : static_cast<unsigned>(FaultKind::pure_virtual));
}

}  // namespace

void format_hex32(std::uint32_t value, char* out) {
  static constexpr char hex[] = "0123456789abcdef";
  for (int i = 7; i >= 0; --i) {
    out[i] = hex[value & 0xFu];
    value >>= 4;
  }
  out[8] = '\0';
}

void report_fault_and_stop(FaultKind kind, std::uint32_t pc, std::uint32_t lr) {
  static_cast<void>(hal::stm32f4::disable_interrupts());
  board_park_motors();  // first: whatever happens next, the wheels stop
  namespace scb = hal::stm32f4::scb;
  // Written piece by piece as it is formatted: no line buffer on a stack that may be in trouble.
  const hal::stm32f4::Block usart = board_info().console_usart;
  const auto write = [usart](const char* text) {
    hal::stm32f4::UsartStream::emergency_write(usart, text);
  };
  write("\r\nFAULT ");
  write(kind_name(kind));
  static constexpr const char* keys[] = {" pc=0x",   " lr=0x",    " cfsr=0x",
                                         " hfsr=0x", " mmfar=0x", " bfar=0x"};
  const std::uint32_t values[] = {
      pc, lr, scb::cfsr.read(), scb::hfsr.read(), scb::mmfar.read(), scb::bfar.read()};
  for (std::size_t i = 0u; i < sizeof(values) / sizeof(values[0]); ++i) {
    char digits[9];
    format_hex32(values[i], digits);
    write(keys[i]);
    write(digits);
  }
  write("\r\n");
  board_exit(3);
}

extern "C" [[gnu::used]] void fault_report(const std::uint32_t* frame, std::uint32_t exception) {
  // Stacked frame: r0 r1 r2 r3 r12 lr pc xpsr.
  FaultKind kind = FaultKind::hard_fault;
  switch (exception) {
    case 4u:
      kind = FaultKind::mem_manage;
      break;
    case 5u:
      kind = FaultKind::bus_fault;
      break;
    case 6u:
      kind = FaultKind::usage_fault;
      break;
    default:
      break;
  }
  report_fault_and_stop(kind, frame[6], frame[5]);
}

extern "C" __attribute__((naked)) void fault_entry() {
  // r0 = the stack the fault frame was pushed on (EXC_RETURN bit 2), r1 = exception number.
  __asm volatile(
      "tst lr, #4\n"
      "ite eq\n"
      "mrseq r0, msp\n"
      "mrsne r0, psp\n"
      "mrs r1, ipsr\n"
      "b fault_report\n");
}

extern "C" void unexpected_exception() {
  report_fault_and_stop(FaultKind::unexpected_exception, 0u, 0u);
}

void exit_program(int status) {
  board_exit(status);
}

void semihosting_exit(int status) {
  // SYS_EXIT_EXTENDED (0x20) with ADP_Stopped_ApplicationExit (0x20026) and the status.
  const std::uint32_t block[2] = {0x20026u, static_cast<std::uint32_t>(status)};
  register std::uint32_t operation __asm("r0") = 0x20u;
  register const std::uint32_t* argument __asm("r1") = block;
  __asm volatile("bkpt 0xab" : "+r"(operation) : "r"(argument) : "memory");
  for (;;) {
    hal::stm32f4::wait_for_interrupt();
  }
}

}  // namespace odocal::firmware

extern "C" void unhandled_interrupt(std::uint32_t exception) {
  odocal::firmware::report_fault_and_stop(odocal::firmware::FaultKind::unhandled_interrupt,
                                          exception, 0u);
}

// No heap in this image: any allocation is a bug that must show at once, not later.
void* operator new(std::size_t) {
  odocal::firmware::report_fault_and_stop(odocal::firmware::FaultKind::heap_use, 0u, 0u);
}
void* operator new[](std::size_t) {
  odocal::firmware::report_fault_and_stop(odocal::firmware::FaultKind::heap_use, 0u, 0u);
}
void operator delete(void*) noexcept {}
void operator delete(void*, std::size_t) noexcept {}
void operator delete[](void*) noexcept {}
void operator delete[](void*, std::size_t) noexcept {}

extern "C" void __cxa_pure_virtual() {
  odocal::firmware::report_fault_and_stop(odocal::firmware::FaultKind::pure_virtual, 0u, 0u);
}
