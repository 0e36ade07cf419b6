#pragma once
/// @file
/// The analog-to-digital converters (RM0090 section 13) as typed register descriptions: ADC1's
/// registers, the registers the three ADCs share, and ADC1's input pins (STM32F405/407
/// datasheet, pin definitions). ADCCLK = PCLK2 / prescaler, at most 36 MHz (VDDA 2.4..3.6 V).

#include <cstdint>

#include "odocal/hal/stm32f4/gpio.hpp"
#include "odocal/hal/stm32f4/mmio.hpp"

namespace odocal::hal::stm32f4::adc {

/// ADC1 (ADC2 at 0x100 above it, ADC3 at 0x200); all three on APB2.
inline constexpr Block adc1{0x4001'2000u};

/// Status. Flags are cleared by writing 0 (a 1 leaves them); EOC also by reading DR.
[[nodiscard]] constexpr Register sr(Block a) {
  return a.at(0x00);
}
inline constexpr Field sr_eoc = bit(1);   ///< end of conversion (of the regular sequence)
inline constexpr Field sr_strt = bit(4);  ///< a regular conversion started
[[nodiscard]] constexpr Register cr1(Block a) {
  return a.at(0x04);
}
inline constexpr Field cr1_res = {24, 2};  ///< resolution: 0 = 12 bits (15 ADC cycles)
[[nodiscard]] constexpr Register cr2(Block a) {
  return a.at(0x08);
}
inline constexpr Field cr2_adon = bit(0);      ///< converter on (t_STAB, 3 µs, before converting)
inline constexpr Field cr2_cont = bit(1);      ///< continuous conversion; 0 = single
inline constexpr Field cr2_align = bit(11);    ///< 0 = right-aligned data
inline constexpr Field cr2_exten = {28, 2};    ///< external trigger; 0 = software only
inline constexpr Field cr2_swstart = bit(30);  ///< starts the regular sequence; hardware clears it
/// Sample time registers: SMPR2 holds channels 0..9, SMPR1 channels 10..18, three bits each.
[[nodiscard]] constexpr Register smpr(Block a, std::uint8_t channel) {
  return a.at(channel < 10u ? 0x10 : 0x0C);
}
/// The sample time field of `channel` (0..18) in its SMPR register.
[[nodiscard]] constexpr Field smp_field(std::uint8_t channel) {
  return Field{static_cast<std::uint8_t>(3u * (channel % 10u)), 3u};
}
/// Regular sequence: SQR1 holds its length L (conversions - 1), SQR3 its first channel SQ1.
[[nodiscard]] constexpr Register sqr1(Block a) {
  return a.at(0x2C);
}
inline constexpr Field sqr1_l = {20, 4};
[[nodiscard]] constexpr Register sqr3(Block a) {
  return a.at(0x34);
}
inline constexpr Field sqr3_sq1 = {0, 5};
/// Regular data: the last conversion, right-aligned in bits 11..0 at 12-bit resolution.
[[nodiscard]] constexpr Register dr(Block a) {
  return a.at(0x4C);
}
inline constexpr std::uint32_t dr_12_bits = 0x0FFFu;

/// Registers the three ADCs share, from 0x40012300.
inline constexpr Block common{0x4001'2300u};
inline constexpr Register ccr = common.at(0x04);
inline constexpr Field ccr_adcpre = {16, 2};  ///< ADCCLK = PCLK2 / (2 · (code + 1))

/// Highest ADC clock, Hz (datasheet, VDDA 2.4..3.6 V).
inline constexpr std::uint32_t max_adc_hz = 36'000'000u;

/// The ADCPRE code of the fastest ADC clock within `max_adc_hz` from `pclk2_hz`: PCLK2 / 2, 4, 6
/// or 8 (84 MHz: /4, 21 MHz; the 16 MHz HSI fallback: /2, 8 MHz). /8 if none fits.
[[nodiscard]] constexpr std::uint32_t prescaler_code(std::uint32_t pclk2_hz) {
  std::uint32_t code = 0u;
  while (code < 3u && pclk2_hz / (2u * (code + 1u)) > max_adc_hz) {
    ++code;
  }
  return code;
}
/// PCLK2 cycles per ADC clock cycle for an ADCPRE code.
[[nodiscard]] constexpr std::uint32_t prescaler_divisor(std::uint32_t code) {
  return 2u * (code + 1u);
}
static_assert(prescaler_code(84'000'000u) == 1u && prescaler_code(16'000'000u) == 0u,
              "168 MHz: PCLK2 84 MHz / 4 = 21 MHz; HSI: 16 MHz / 2");

/// Sample times (SMPx codes): ADC clock cycles the input is sampled for, before the 12 cycles of
/// a 12-bit conversion. A slow source (a receiver's load resistor of tens of kΩ) needs the longer
/// ones: the datasheet's R_AIN bound grows with the sample time.
enum class SampleTime : std::uint32_t {
  cycles_3 = 0b000,
  cycles_15 = 0b001,
  cycles_28 = 0b010,
  cycles_56 = 0b011,
  cycles_84 = 0b100,
  cycles_112 = 0b101,
  cycles_144 = 0b110,
  cycles_480 = 0b111,
};

/// ADC clock cycles of `time`.
[[nodiscard]] constexpr std::uint32_t sample_cycles(SampleTime time) {
  constexpr std::uint32_t cycles[] = {3u, 15u, 28u, 56u, 84u, 112u, 144u, 480u};
  return cycles[static_cast<std::uint32_t>(time) & 7u];
}
/// ADC clock cycles of a 12-bit conversion after its sample time.
inline constexpr std::uint32_t conversion_cycles_12_bit = 12u;

/// The external input channels of ADC1 (and ADC2), 0..15.
inline constexpr std::uint8_t external_channels = 16u;

/// The pin of ADC1's external input `channel`: IN0..7 = PA0..PA7, IN8..9 = PB0..PB1,
/// IN10..15 = PC0..PC5 (ADC3's IN4..9 are elsewhere). Only for `channel` < `external_channels`:
/// the internal ones (16..18) have no pin, and the result for them (PA0) means nothing.
[[nodiscard]] constexpr gpio::Pin channel_pin(std::uint8_t channel) {
  if (channel < 8u) {
    return gpio::Pin{gpio::Port::a, channel};
  }
  if (channel < 10u) {
    return gpio::Pin{gpio::Port::b, static_cast<std::uint8_t>(channel - 8u)};
  }
  if (channel < external_channels) {
    return gpio::Pin{gpio::Port::c, static_cast<std::uint8_t>(channel - 10u)};
  }
  return gpio::Pin{gpio::Port::a, 0u};
}

}  // namespace odocal::hal::stm32f4::adc
