#include "odocal/hal/stm32f4/watchdog.hpp"

#include "odocal/hal/stm32f4/cortex_m4.hpp"
#include "odocal/hal/stm32f4/iwdg.hpp"
#include "odocal/hal/stm32f4/rcc.hpp"

namespace odocal::hal::stm32f4 {

void Watchdog::start(std::uint32_t timeout_ms) {
  // LSI 32 kHz / (4 << code): code 3 = /32 gives 1 count per ms, 4095 counts max.
  // Use the smallest prescaler that fits the timeout for the finest resolution.
  constexpr std::uint32_t lsi_hz = 32'000u;
  if (timeout_ms < 1u) {
    timeout_ms = 1u;
  } else if (timeout_ms > 100'000u) {
    timeout_ms = 100'000u;  // beyond the longest the IWDG counts (32.8 s); keeps t·8 in 32 bits
  }
  std::uint32_t code = 0u;
  std::uint32_t counts = 0u;
  for (; code <= 6u; ++code) {
    // t·lsi_hz / (1000·divider) = t·8 / 2^code exactly (32 kHz / 1000 / 4 = 8).
    static_assert(lsi_hz / 1000u / 4u == 8u, "the shift below assumes LSI = 32 kHz");
    counts = (timeout_ms * 8u) >> code;
    if (counts <= 4096u) {
      break;
    }
  }
  if (code > 6u) {
    code = 6u;
    counts = 4096u;
  }
  if (counts < 1u) {
    counts = 1u;
  }
  iwdg::kr.write(iwdg::key_start);  // also starts the LSI
  iwdg::kr.write(iwdg::key_unlock);
  iwdg::pr.write(code);
  iwdg::rlr.write(counts - 1u);
  // PVU/RVU stay set until the LSI domain took the values (QEMU: never modelled, reads 0).
  for (std::uint32_t i = 0u; i < 100'000u && iwdg::sr.read() != 0u; ++i) {
  }
  iwdg::kr.write(iwdg::key_reload);
}

void Watchdog::feed() {
  iwdg::kr.write(iwdg::key_reload);
}

bool Watchdog::caused_last_reset() {
  const bool watchdog = rcc::csr.get(rcc::csr_iwdgrstf) != 0u;
  rcc::csr.set(rcc::csr_rmvf.mask());
  return watchdog;
}

void CycleCounter::start() {
  dwt::demcr.set(dwt::demcr_trcena.mask());
  dwt::cyccnt.write(0u);
  dwt::ctrl.set(dwt::ctrl_cyccntena.mask());
}

std::uint32_t CycleCounter::now() {
  return dwt::cyccnt.read();
}

}  // namespace odocal::hal::stm32f4
