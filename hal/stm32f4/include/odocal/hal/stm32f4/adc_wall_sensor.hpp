#pragma once
/// @file
/// The STM32F4 backend of hal::WallSensor: the emitter on a GPIO output, the receiver on an ADC1
/// input converted once per reading (software trigger, polled), the settle time busy-waited on the
/// DWT cycle counter. Written against a register bus given as a template argument, as the flash
/// store and the encoder edge are: `MemoryBus` on the MCU, fakes in the host tests.

#include <atomic>
#include <cstdint>

#include "odocal/hal/stm32f4/adc.hpp"
#include "odocal/hal/stm32f4/clock.hpp"
#include "odocal/hal/stm32f4/cortex_m4.hpp"
#include "odocal/hal/stm32f4/gpio.hpp"
#include "odocal/hal/stm32f4/mmio.hpp"
#include "odocal/hal/stm32f4/rcc.hpp"
#include "odocal/hal/wall_sensor.hpp"

namespace odocal::hal::stm32f4 {

/// Where one wall sensor is wired and how it is read.
struct WallSensorWiring {
  gpio::Pin emitter;        ///< push-pull output; high = emitter on (through its driver transistor)
  std::uint8_t channel;     ///< ADC1 external input, 0..15 (its pin: adc::channel_pin)
  std::uint32_t settle_us;  ///< the receiver's rise after the emitter switches on, µs
  adc::SampleTime sample_time;  ///< the input's sample time (its source impedance's need)
};

/// The longest settle time a wiring may ask for, µs: the wait is a busy loop, in any context.
inline constexpr std::uint32_t max_settle_us = 1'000u;

/// True when `wiring` can be used: emitter pin 0..15, an external channel, a settle time within
/// `max_settle_us`, and the emitter not on the receiver's own pin.
[[nodiscard]] constexpr bool valid_wiring(const WallSensorWiring& wiring) {
  if (wiring.emitter.number >= 16u || wiring.channel >= adc::external_channels ||
      wiring.settle_us > max_settle_us) {
    return false;
  }
  const gpio::Pin receiver = adc::channel_pin(wiring.channel);
  return receiver.port != wiring.emitter.port || receiver.number != wiring.emitter.number;
}

/// One reflective wall sensor on ADC1. Every sensor of a board shares ADC1, which they own: no
/// other code may use ADC1, and the sensors must be read from one context at a time (a reading
/// reprograms the ADC's sequence). `read_counts` and `set_emitter` are ISR-safe in that sense:
/// bounded, no lock.
///
/// A reading clears SR, writes its channel's sample time (SMPR), a sequence of one conversion
/// (SQR1 L = 0) of its channel (SQR3 SQ1), starts it (CR2 SWSTART), polls SR's EOC a bounded
/// number of times and returns DR's 12 bits (reading DR clears EOC). The poll limit is twice the
/// conversion's length in core cycles: a poll takes at least one, so it never gives up on a
/// conversion still running. A conversion whose EOC never comes (ADC1 unclocked, or broken) reads
/// `timeout_counts`, full scale, as a wall touching the sensor would: a robot then believes itself
/// blocked rather than drive into a wall it could not see; `timeouts()` counts them.
///
/// The settle wait reads DWT CYCCNT until `settle_us` of core cycles have passed, and makes at
/// most that many reads: where the counter does not run (QEMU) it still ends, after at least as
/// long (each pass takes a cycle or more), never hangs.
template <typename Bus>
class AdcWallSensor final : public hal::WallSensor {
 public:
  /// What a reading whose conversion never ends returns.
  static constexpr std::uint16_t timeout_counts = full_scale_counts;
  /// The ADC's stabilisation time after ADON (datasheet t_STAB), µs: `start` waits it.
  static constexpr std::uint32_t stabilisation_us = 3u;

  /// @param bus kept by reference; @param clock the clock tree reached (`configure_clock`): the
  /// core clock times the settle wait, PCLK2 sets the ADC prescaler (ADCCLK within 36 MHz).
  constexpr AdcWallSensor(Bus& bus, const WallSensorWiring& wiring, const ClockReport& clock)
      : bus_(bus),
        wiring_(wiring),
        core_cycles_per_us_(clock.sysclk_hz / 1'000'000u),
        prescaler_code_(adc::prescaler_code(clock.pclk2_hz)),
        valid_(valid_wiring(wiring) && clock.sysclk_hz >= 1'000'000u && clock.pclk2_hz > 0u &&
               clock.pclk2_hz <= clock.sysclk_hz) {
    if (valid_) {
      settle_cycles_ = wiring.settle_us * core_cycles_per_us_;
      const std::uint32_t conversion_adc_cycles =
          adc::sample_cycles(wiring.sample_time) + adc::conversion_cycles_12_bit;
      const std::uint32_t core_per_adc_cycle =
          (clock.sysclk_hz / clock.pclk2_hz) * adc::prescaler_divisor(prescaler_code_);
      eoc_poll_limit_ = 2u * conversion_adc_cycles * core_per_adc_cycle;
    }
  }

  /// False for a wiring `valid_wiring` refuses or a clock report below 1 MHz: such a sensor
  /// touches no register, its emitter stays as it was and every reading is `timeout_counts`.
  [[nodiscard]] bool valid() const { return valid_; }
  /// Core cycles of the settle wait.
  [[nodiscard]] std::uint32_t settle_cycles() const { return settle_cycles_; }
  /// Polls of EOC before a reading gives up.
  [[nodiscard]] std::uint32_t eoc_poll_limit() const { return eoc_poll_limit_; }
  /// Readings whose conversion never ended, modulo 2^32. Any context.
  [[nodiscard]] std::uint32_t timeouts() const { return timeouts_.load(std::memory_order_relaxed); }

  /// Clocks ADC1 and the two pins' ports; the emitter off, then a push-pull output; the receiver
  /// analog, no pull; the DWT cycle counter running (not reset); ADC1's clock (ADC_CCR ADCPRE),
  /// 12-bit right-aligned single conversions on a software trigger, ADON; then waits
  /// `stabilisation_us`. Repeating it for each sensor is harmless. Start-up only, not ISR-safe
  /// (read-modify-write of RCC, GPIO and ADC registers other code shares).
  void start();

 private:
  /// Single BSRR write: ISR-safe, no read-modify-write.
  void do_set_emitter(bool on) override;
  std::uint16_t do_read_counts() override;
  std::uint32_t do_settle_us() const override { return wiring_.settle_us; }
  void do_wait_settle() override { wait_cycles(settle_cycles_); }

  void set_bits(Register reg, std::uint32_t mask) {
    bus_.write32(reg.address, bus_.read32(reg.address) | mask);
  }
  void modify(Register reg, Field field, std::uint32_t value) {
    bus_.write32(reg.address, (bus_.read32(reg.address) & ~field.mask()) | field(value));
  }
  void wait_cycles(std::uint32_t cycles);

  Bus& bus_;
  WallSensorWiring wiring_;
  std::uint32_t core_cycles_per_us_;
  std::uint32_t prescaler_code_;
  std::uint32_t settle_cycles_ = 0u;
  std::uint32_t eoc_poll_limit_ = 0u;
  std::atomic<std::uint32_t> timeouts_{0u};
  bool valid_;
};

template <typename Bus>
void AdcWallSensor<Bus>::start() {
  if (!valid_) {
    return;
  }
  const gpio::Pin emitter = wiring_.emitter;
  const gpio::Pin receiver = adc::channel_pin(wiring_.channel);
  set_bits(rcc::apb2enr, rcc::apb2enr_adc1.mask());
  set_bits(rcc::ahb1enr, rcc::ahb1enr_gpio(static_cast<std::uint8_t>(emitter.port)).mask() |
                             rcc::ahb1enr_gpio(static_cast<std::uint8_t>(receiver.port)).mask());
  do_set_emitter(false);  // low from the moment the pin becomes an output
  bus_.write32(gpio::otyper(emitter.port).address,
               bus_.read32(gpio::otyper(emitter.port).address) & ~bit(emitter.number).mask());
  modify(gpio::moder(emitter.port), gpio::two_bits(emitter.number),
         static_cast<std::uint32_t>(gpio::Mode::output));
  modify(gpio::pupdr(receiver.port), gpio::two_bits(receiver.number),
         static_cast<std::uint32_t>(gpio::Pull::none));
  modify(gpio::moder(receiver.port), gpio::two_bits(receiver.number),
         static_cast<std::uint32_t>(gpio::Mode::analog));
  set_bits(dwt::demcr, dwt::demcr_trcena.mask());
  set_bits(dwt::ctrl, dwt::ctrl_cyccntena.mask());
  modify(adc::ccr, adc::ccr_adcpre, prescaler_code_);
  bus_.write32(adc::cr1(adc::adc1).address, adc::cr1_res(0u));  // 12 bits, no scan, no interrupt
  bus_.write32(adc::cr2(adc::adc1).address, adc::cr2_adon.mask());  // single, right, software
  wait_cycles(stabilisation_us * core_cycles_per_us_);
}

template <typename Bus>
void AdcWallSensor<Bus>::do_set_emitter(bool on) {
  if (!valid_) {
    return;
  }
  const std::uint32_t pin_bit = 1u << wiring_.emitter.number;
  bus_.write32(gpio::bsrr(wiring_.emitter.port).address, on ? pin_bit : pin_bit << 16);
}

template <typename Bus>
std::uint16_t AdcWallSensor<Bus>::do_read_counts() {
  if (!valid_) {
    return timeout_counts;
  }
  constexpr Block a = adc::adc1;
  const std::uint8_t channel = wiring_.channel;
  // Flags are cleared by writing 0: a stale EOC (a conversion that ended after an earlier timeout)
  // must not pass for this one's.
  bus_.write32(adc::sr(a).address, 0u);
  modify(adc::smpr(a, channel), adc::smp_field(channel),
         static_cast<std::uint32_t>(wiring_.sample_time));
  bus_.write32(adc::sqr1(a).address, adc::sqr1_l(0u));  // one conversion
  bus_.write32(adc::sqr3(a).address, adc::sqr3_sq1(channel));
  bus_.write32(adc::cr2(a).address, adc::cr2_adon.mask() | adc::cr2_swstart.mask());
  for (std::uint32_t poll = 0u; poll < eoc_poll_limit_; ++poll) {
    if ((bus_.read32(adc::sr(a).address) & adc::sr_eoc.mask()) != 0u) {
      return static_cast<std::uint16_t>(bus_.read32(adc::dr(a).address) & adc::dr_12_bits);
    }
  }
  timeouts_.fetch_add(1u, std::memory_order_relaxed);
  return timeout_counts;
}

template <typename Bus>
void AdcWallSensor<Bus>::wait_cycles(std::uint32_t cycles) {
  if (cycles == 0u) {
    return;
  }
  const std::uint32_t start = bus_.read32(dwt::cyccnt.address);
  for (std::uint32_t pass = 0u; pass < cycles; ++pass) {
    if (bus_.read32(dwt::cyccnt.address) - start >= cycles) {  // modular: CYCCNT wraps
      return;
    }
  }
}

/// Built once, in adc_wall_sensor.cpp (not linked into an image that does not use it).
extern template class AdcWallSensor<MemoryBus>;

}  // namespace odocal::hal::stm32f4
