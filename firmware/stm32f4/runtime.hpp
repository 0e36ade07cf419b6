#pragma once
/// @file
/// The bare-metal runtime around main(): fault reporting, program exit, semihosting.

#include <cstdint>

namespace odocal::firmware {

/// Why the program stopped abnormally.
enum class FaultKind : std::uint8_t {
  hard_fault,
  mem_manage,
  bus_fault,
  usage_fault,
  nmi,
  unexpected_exception,  ///< SVCall, PendSV, DebugMonitor: never used here
  unhandled_interrupt,   ///< a device interrupt fired with nothing attached
  heap_use,              ///< operator new was called
  pure_virtual,
};

/// Parks the motors, prints `FAULT <kind> pc=… lr=… cfsr=… hfsr=… mmfar=… bfar=…` on the console
/// by polling (interrupts off), then ends the program: semihosting exit status 3 in QEMU, a
/// system reset on the robot (after the report has left the UART). Any context.
[[noreturn]] void report_fault_and_stop(FaultKind kind, std::uint32_t pc, std::uint32_t lr);

/// Entry of HardFault, MemManage, BusFault, UsageFault: finds the stacked frame and reports.
extern "C" void fault_entry();
/// Entry of the exceptions the firmware never uses.
extern "C" void unexpected_exception();

/// Ends the program with `status` (0 = success): the board decides how (QEMU: semihosting exit;
/// robot: motors parked and a system reset).
[[noreturn]] void exit_program(int status);

/// Semihosting SYS_EXIT_EXTENDED: QEMU exits with `status`. Only with a debugger or QEMU
/// attached: on a bare board the BKPT instruction faults.
[[noreturn]] void semihosting_exit(int status);

/// Writes `value` as 8 hex digits into `out` (9 bytes with the terminating NUL).
void format_hex32(std::uint32_t value, char* out);

}  // namespace odocal::firmware
