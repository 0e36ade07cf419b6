#include "odocal/hal/stm32f4/clock.hpp"

#include "odocal/hal/stm32f4/flash_registers.hpp"
#include "odocal/hal/stm32f4/rcc.hpp"

namespace odocal::hal::stm32f4 {
namespace {

constexpr std::uint32_t hsi_hz = 16'000'000u;
constexpr std::uint32_t vco_input_hz = 2'000'000u;  // RM0090: 2 MHz limits PLL jitter
constexpr std::uint32_t pll_n = 168u;               // VCO = 336 MHz
constexpr std::uint32_t pll_p_code = 0u;            // /2 -> 168 MHz
constexpr std::uint32_t pll_q = 7u;                 // 48 MHz
constexpr std::uint32_t flash_wait_states = 5u;     // 150 < HCLK <= 168 MHz at 2.7..3.6 V

bool wait_until_set(Register reg, Field field, std::uint32_t polls) {
  for (std::uint32_t i = 0u; i < polls; ++i) {
    if (reg.get(field) != 0u) {
      return true;
    }
  }
  return false;
}

}  // namespace

const char* clock_source_name(ClockSource source) {
  switch (source) {
    case ClockSource::hse_pll:
      return "hse";
    case ClockSource::hsi_pll:
      return "hsi-pll";
    case ClockSource::hsi:
      break;
  }
  return "hsi";
}

ClockReport configure_clock(const ClockPlan& plan) {
  ClockReport report{};
  // Scale 1 regulator output, needed above 144 MHz.
  rcc::apb1enr.set(rcc::apb1enr_pwr.mask());
  pwr::cr.set(pwr::cr_vos.mask());

  rcc::cr.set(rcc::cr_hseon.mask());
  const bool hse_ok = plan.hse_hz >= 4'000'000u && plan.hse_hz % vco_input_hz == 0u &&
                      wait_until_set(rcc::cr, rcc::cr_hserdy, plan.ready_timeout_polls);
  if (!hse_ok) {
    rcc::cr.clear(rcc::cr_hseon.mask());
  }
  const std::uint32_t input_hz = hse_ok ? plan.hse_hz : hsi_hz;

  rcc::pllcfgr.write(rcc::pllcfgr_m(input_hz / vco_input_hz) | rcc::pllcfgr_n(pll_n) |
                     rcc::pllcfgr_p(pll_p_code) | rcc::pllcfgr_q(pll_q) |
                     (hse_ok ? rcc::pllcfgr_src_hse.mask() : 0u));
  rcc::cr.set(rcc::cr_pllon.mask());
  if (!wait_until_set(rcc::cr, rcc::cr_pllrdy, plan.ready_timeout_polls)) {
    rcc::cr.clear(rcc::cr_pllon.mask());
    return report;  // HSI, 16 MHz everywhere
  }

  // Wait states before the clock rises; the new latency must read back before switching.
  flash::acr.write(flash::acr_latency(flash_wait_states) | flash::acr_prften.mask() |
                   flash::acr_icen.mask() | flash::acr_dcen.mask());
  if (flash::acr.get(flash::acr_latency) != flash_wait_states) {
    return report;
  }
  rcc::cfgr.write(rcc::cfgr_hpre(0u) | rcc::cfgr_ppre1(rcc::apb_div4) |
                  rcc::cfgr_ppre2(rcc::apb_div2) |
                  rcc::cfgr_sw(static_cast<std::uint32_t>(rcc::SystemClock::pll)));
  for (std::uint32_t i = 0u; i < plan.ready_timeout_polls; ++i) {
    if (rcc::cfgr.get(rcc::cfgr_sws) == static_cast<std::uint32_t>(rcc::SystemClock::pll)) {
      report.source = hse_ok ? ClockSource::hse_pll : ClockSource::hsi_pll;
      report.sysclk_hz = plan.sysclk_hz;
      report.pclk1_hz = plan.sysclk_hz / 4u;
      report.pclk2_hz = plan.sysclk_hz / 2u;
      return report;
    }
  }
  // The switch did not happen: back to HSI with the prescalers at 1.
  rcc::cfgr.write(0u);
  return report;
}

}  // namespace odocal::hal::stm32f4
