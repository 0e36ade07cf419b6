// The wall sensor backend (AdcWallSensor) on fake registers: the emitter through its BSRR bits
// alone, start-up clocking and switching on ADC1, a reading's register sequence (SMPR, SQR1, SQR3,
// SWSTART, EOC, DR), the bounded EOC wait, read_lit_counts against a receiver that only sees the
// emitter once it settled, the settle wait on the cycle counter (running, wrapping, standing
// still), and the usual mouse's table of firmware/stm32f4. Every address and bit is RM0090's.

#include "odocal/hal/stm32f4/adc_wall_sensor.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <initializer_list>

#include "board_wall_sensors.hpp"
#include "register_fake.hpp"

namespace odocal::test {
namespace {

namespace f4 = hal::stm32f4;
using f4::gpio::Pin;
using f4::gpio::Port;

// RM0090 register map: section 13.13.17 (ADC), 6.3 / 7.3 (RCC), 8.4 (GPIO); ARMv7-M (DWT).
constexpr std::uintptr_t adc1_sr = 0x4001'2000u;
constexpr std::uintptr_t adc1_cr1 = 0x4001'2004u;
constexpr std::uintptr_t adc1_cr2 = 0x4001'2008u;
constexpr std::uintptr_t adc1_smpr1 = 0x4001'200Cu;
constexpr std::uintptr_t adc1_smpr2 = 0x4001'2010u;
constexpr std::uintptr_t adc1_sqr1 = 0x4001'202Cu;
constexpr std::uintptr_t adc1_sqr3 = 0x4001'2034u;
constexpr std::uintptr_t adc1_dr = 0x4001'204Cu;
constexpr std::uintptr_t adc_ccr = 0x4001'2304u;
constexpr std::uintptr_t rcc_ahb1enr = 0x4002'3830u;
constexpr std::uintptr_t rcc_apb2enr = 0x4002'3844u;
constexpr std::uintptr_t gpioa_moder = 0x4002'0000u;
constexpr std::uintptr_t gpioa_pupdr = 0x4002'000Cu;
constexpr std::uintptr_t gpioc_moder = 0x4002'0800u;
constexpr std::uintptr_t gpioc_otyper = 0x4002'0804u;
constexpr std::uintptr_t gpioc_bsrr = 0x4002'0818u;
constexpr std::uintptr_t dwt_ctrl = 0xE000'1000u;
constexpr std::uintptr_t dwt_cyccnt = 0xE000'1004u;
constexpr std::uintptr_t demcr = 0xE000'EDFCu;
constexpr std::uint32_t sr_eoc = 1u << 1;
constexpr std::uint32_t cr2_adon = 1u << 0;
constexpr std::uint32_t cr2_swstart = 1u << 30;

// The robot's clock tree (configure_clock): SYSCLK 168 MHz, APB1 42 MHz, APB2 84 MHz.
constexpr f4::ClockReport clock_168{f4::ClockSource::hse_pll, 168'000'000u, 42'000'000u,
                                    84'000'000u};
// Emitter PC7, receiver ADC1_IN2 = PA2, 30 µs to settle, 84-cycle sampling (SMP code 0b100).
constexpr f4::WallSensorWiring wiring{Pin{Port::c, 7u}, 2u, 30u, f4::adc::SampleTime::cycles_84};
constexpr std::uint32_t settle_cycles_168 = 30u * 168u;  // 30 µs of the 168 MHz core

/// ADC1, the GPIO ports and the DWT cycle counter behind a register bus, over a RegisterFake that
/// logs every access except CYCCNT's (counted instead):
/// - time passes in busy loops only: each CYCCNT read returns the count and advances it by
///   `cycles_per_read`, unless `counter_runs` is false (QEMU's DWT, which reads 0 for ever);
/// - the emitter's level follows BSRR writes to its pin (bit n sets, bit n + 16 resets);
/// - writing CR2 with SWSTART starts a conversion (SWSTART reads back 0, as hardware clears it);
///   EOC rises at the `polls_to_eoc`-th SR read after, never with `eoc_never`, and DR then holds
///   `ambient_counts`, plus `lit_counts` if the emitter had been on for `receiver_settle_cycles`
///   when the conversion started (a receiver lags its emitter); reading DR clears EOC, and SR's
///   flags are cleared by writing 0 (rc_w0: a 1 leaves a flag as it is).
class AdcBusFake {
 public:
  explicit AdcBusFake(Pin emitter) : emitter_(emitter) {}

  RegisterFake registers;
  std::uint32_t cycles_per_read = 6u;
  bool counter_runs = true;
  bool eoc_never = false;
  std::uint32_t polls_to_eoc = 3u;
  std::uint32_t ambient_counts = 0u;
  std::uint32_t lit_counts = 0u;
  std::uint32_t receiver_settle_cycles = 0u;

  std::uint32_t now_cycles = 0u;  ///< CYCCNT
  std::uint32_t cyccnt_reads = 0u;
  std::uint32_t sr_reads = 0u;
  std::uint32_t conversions = 0u;
  std::uint32_t adon_written_at = 0u;  ///< CYCCNT when CR2 was last written without SWSTART
  bool emitter_on = false;
  std::uint32_t lit_for_cycles = 0u;      ///< how long the emitter had been on at the last start
  std::uint32_t converted_channel = 99u;  ///< SQR3's SQ1 at the last start

  std::uint32_t read32(std::uintptr_t address) {
    if (address == dwt_cyccnt) {
      ++cyccnt_reads;
      const std::uint32_t value = now_cycles;
      now_cycles += counter_runs ? cycles_per_read : 0u;
      return value;
    }
    if (address == adc1_sr) {
      ++sr_reads;
      if (converting_ && !eoc_never && ++polls_ >= polls_to_eoc) {
        converting_ = false;
        registers.set(adc1_dr, result_);
        registers.set(adc1_sr, registers.peek(adc1_sr) | sr_eoc);
      }
    }
    const std::uint32_t value = registers.read32(address);
    if (address == adc1_dr) {
      registers.set(adc1_sr, registers.peek(adc1_sr) & ~sr_eoc);
    }
    return value;
  }

  void write32(std::uintptr_t address, std::uint32_t value) {
    const std::uint32_t before = registers.peek(address);
    registers.write32(address, value);
    if (address == adc1_sr) {
      registers.set(adc1_sr, before & value);
    } else if (address == f4::gpio::bsrr(emitter_.port).address) {
      if ((value & (1u << emitter_.number)) != 0u) {
        emitter_on = true;
        emitter_on_at_ = now_cycles;
      } else if ((value & (1u << (emitter_.number + 16u))) != 0u) {
        emitter_on = false;
      }
      registers.set(address, 0u);  // BSRR reads 0
    } else if (address == adc1_cr2) {
      if ((value & cr2_swstart) == 0u) {
        adon_written_at = now_cycles;
        return;
      }
      registers.set(adc1_cr2, value & ~cr2_swstart);
      converting_ = true;
      polls_ = 0u;
      ++conversions;
      lit_for_cycles = emitter_on ? now_cycles - emitter_on_at_ : 0u;
      const bool lit = emitter_on && lit_for_cycles >= receiver_settle_cycles;
      result_ = ambient_counts + (lit ? lit_counts : 0u);
      converted_channel = registers.peek(adc1_sqr3) & 0x1Fu;
    }
  }

 private:
  Pin emitter_;
  std::uint32_t emitter_on_at_ = 0u;
  bool converting_ = false;
  std::uint32_t polls_ = 0u;
  std::uint32_t result_ = 0u;
};

using Sensor = f4::AdcWallSensor<AdcBusFake>;

/// Index of the first logged write to `address` at or after `from`, or the log's size if none.
std::size_t first_write(RegisterFake& log, std::uintptr_t address, std::size_t from = 0u) {
  for (std::size_t i = from; i < log.access_count(); ++i) {
    if (log.access(i).write && log.access(i).address == address) {
      return i;
    }
  }
  return log.access_count();
}

TEST(AdcWallSensor, SwitchesTheEmitterWithOneBsrrWriteOfItsOwnSetOrResetBit) {
  AdcBusFake bus{wiring.emitter};
  Sensor sensor{bus, wiring, clock_168};
  bus.registers.set(gpioc_bsrr, 0u);
  sensor.set_emitter(true);
  ASSERT_EQ(bus.registers.access_count(), 1u);  // no read: nothing to race with
  EXPECT_TRUE(bus.registers.access(0u).write);
  EXPECT_EQ(bus.registers.access(0u).address, gpioc_bsrr);
  EXPECT_EQ(bus.registers.access(0u).value, 0x0000'0080u);  // BS7
  EXPECT_TRUE(bus.emitter_on);
  bus.registers.clear_log();
  sensor.set_emitter(false);
  ASSERT_EQ(bus.registers.access_count(), 1u);
  EXPECT_TRUE(bus.registers.access(0u).write);
  EXPECT_EQ(bus.registers.access(0u).address, gpioc_bsrr);
  EXPECT_EQ(bus.registers.access(0u).value, 0x0080'0000u);  // BR7 = bit 7 + 16
  EXPECT_FALSE(bus.emitter_on);
}

TEST(AdcWallSensor, StartClocksAndSwitchesOnAdc1AndSetsUpBothPins) {
  AdcBusFake bus{wiring.emitter};
  // What other code set before: kept.
  bus.registers.set(rcc_apb2enr, 1u << 4);                      // USART1
  bus.registers.set(rcc_ahb1enr, 1u << 1);                      // GPIOB
  bus.registers.set(gpioc_moder, 0b01u);                        // PC0 an output
  bus.registers.set(gpioc_otyper, 0xFFFFu);                     // every pin open-drain
  bus.registers.set(gpioa_moder, 0xA800'0000u);                 // PA13..15 SWD/JTAG (reset value)
  bus.registers.set(gpioa_pupdr, 0x6400'0000u | (0b01u << 4));  // reset value, PA2 pulled up
  bus.registers.set(adc_ccr, 0x0080'0000u);                     // TSVREFE
  bus.registers.set(dwt_ctrl, 0x4000'0000u);                    // NUMCOMP bits, counter off
  Sensor sensor{bus, wiring, clock_168};
  ASSERT_TRUE(sensor.valid());
  sensor.start();
  RegisterFake& r = bus.registers;
  EXPECT_EQ(r.peek(rcc_apb2enr), (1u << 4) | (1u << 8));              // + ADC1EN
  EXPECT_EQ(r.peek(rcc_ahb1enr), (1u << 1) | (1u << 0) | (1u << 2));  // + GPIOA, GPIOC
  EXPECT_EQ(r.peek(gpioc_moder), 0b01u | (0b01u << 14));              // PC7 general-purpose output
  EXPECT_EQ(r.peek(gpioc_otyper), 0xFFFFu & ~(1u << 7));              // PC7 push-pull
  EXPECT_EQ(r.peek(gpioa_moder), 0xA800'0000u | (0b11u << 4));        // PA2 analog
  EXPECT_EQ(r.peek(gpioa_pupdr), 0x6400'0000u);                       // PA2 no pull
  // ADCPRE (bits 17:16) = 01: PCLK2 / 4 = 21 MHz, the fastest within 36 MHz (/2 would be 42).
  EXPECT_EQ(r.peek(adc_ccr), 0x0080'0000u | (0b01u << 16));
  EXPECT_EQ(r.peek(adc1_cr1), 0u);        // RES = 00: 12 bits; no scan, no interrupt
  EXPECT_EQ(r.peek(adc1_cr2), cr2_adon);  // ADON; single, right-aligned, no external trigger
  EXPECT_EQ(r.peek(demcr) & (1u << 24), 1u << 24);          // TRCENA
  EXPECT_EQ(r.peek(dwt_ctrl), 0x4000'0001u);                // CYCCNTENA
  EXPECT_EQ(first_write(r, dwt_cyccnt), r.access_count());  // the count is not reset
  // The emitter is driven low before its pin becomes an output.
  const std::size_t reset = first_write(r, gpioc_bsrr);
  ASSERT_LT(reset, r.access_count());
  EXPECT_EQ(r.access(reset).value, 1u << (7 + 16));
  EXPECT_LT(reset, first_write(r, gpioc_moder));
  EXPECT_FALSE(bus.emitter_on);
  // t_STAB = 3 µs after ADON before start returns: 3 · 168 cycles.
  EXPECT_GE(bus.now_cycles - bus.adon_written_at, 3u * 168u);
  EXPECT_EQ(r.overflows(), 0u);
}

TEST(AdcWallSensor, OnTheHsiFallbackDividesPclk2ByTwoAndCountsTheSettleIn16MhzCycles) {
  constexpr f4::ClockReport hsi{f4::ClockSource::hsi, 16'000'000u, 16'000'000u, 16'000'000u};
  AdcBusFake bus{wiring.emitter};
  Sensor sensor{bus, wiring, hsi};
  sensor.start();
  EXPECT_EQ(bus.registers.peek(adc_ccr), 0b00u << 16);  // /2: 8 MHz
  EXPECT_EQ(sensor.settle_cycles(), 30u * 16u);
  // (84 + 12) ADC cycles of 2 core cycles each, twice over.
  EXPECT_EQ(sensor.eoc_poll_limit(), 2u * 96u * 2u);
}

TEST(AdcWallSensor, AReadingProgramsItsChannelAndSampleTimeStartsAndReturnsDr) {
  AdcBusFake bus{wiring.emitter};
  Sensor sensor{bus, wiring, clock_168};
  sensor.start();
  bus.registers.set(adc1_smpr2, 0b111u);        // channel 0: 480 cycles, kept
  bus.registers.set(adc1_sqr1, 0b0011u << 20);  // a sequence of 4 left from elsewhere
  bus.registers.set(adc1_sr, sr_eoc);           // a stale EOC
  bus.ambient_counts = 0x0ABCu;
  bus.registers.clear_log();
  const std::uint16_t counts = sensor.read_counts();
  EXPECT_EQ(counts, 0x0ABCu);
  RegisterFake& r = bus.registers;
  EXPECT_EQ(r.peek(adc1_smpr2), 0b111u | (0b100u << 6));  // SMP2 (bits 8:6) = 84 cycles
  EXPECT_EQ(r.peek(adc1_sqr1) & (0xFu << 20), 0u);        // L = 0: one conversion
  EXPECT_EQ(r.peek(adc1_sqr3), 2u);                       // SQ1 = channel 2
  EXPECT_EQ(bus.converted_channel, 2u);
  EXPECT_EQ(bus.conversions, 1u);
  // The stale EOC is cleared before the conversion starts, the channel set up before SWSTART.
  const std::size_t clear = first_write(r, adc1_sr);
  const std::size_t start = first_write(r, adc1_cr2);
  ASSERT_LT(start, r.access_count());
  EXPECT_EQ(r.access(clear).value & sr_eoc, 0u);
  EXPECT_LT(clear, start);
  EXPECT_LT(first_write(r, adc1_smpr2), start);
  EXPECT_LT(first_write(r, adc1_sqr1), start);
  EXPECT_LT(first_write(r, adc1_sqr3), start);
  EXPECT_EQ(r.access(start).value, cr2_swstart | cr2_adon);
  // Polled until the fake's EOC (third SR read), then DR once.
  EXPECT_EQ(bus.sr_reads, 3u);
  EXPECT_EQ(r.access(r.access_count() - 1u).address, adc1_dr);
  EXPECT_EQ(sensor.timeouts(), 0u);
}

TEST(AdcWallSensor, ChannelsTenAndAboveTakeTheirSampleTimeFromSmpr1) {
  constexpr f4::WallSensorWiring pc4{Pin{Port::c, 7u}, 14u, 30u, f4::adc::SampleTime::cycles_144};
  static_assert(f4::adc::channel_pin(14u).port == Port::c && f4::adc::channel_pin(14u).number == 4u,
                "ADC1_IN14 is PC4");
  AdcBusFake bus{pc4.emitter};
  Sensor sensor{bus, pc4, clock_168};
  sensor.start();
  bus.ambient_counts = 1234u;
  EXPECT_EQ(sensor.read_counts(), 1234u);
  EXPECT_EQ(bus.registers.peek(adc1_smpr1), 0b110u << 12);  // SMP14 (bits 14:12) = 144 cycles
  EXPECT_EQ(bus.registers.peek(adc1_smpr2), 0u);
  EXPECT_EQ(bus.registers.peek(adc1_sqr3), 14u);
  EXPECT_EQ(bus.registers.peek(gpioc_moder) & (0b11u << 8), 0b11u << 8);  // PC4 analog
}

TEST(AdcWallSensor, OnlyDrsTwelveBitsAreTheReading) {
  AdcBusFake bus{wiring.emitter};
  Sensor sensor{bus, wiring, clock_168};
  sensor.start();
  bus.ambient_counts = 0xFFFF'F123u;
  EXPECT_EQ(sensor.read_counts(), 0x123u);
}

TEST(AdcWallSensor, AnEocThatNeverComesEndsTheWaitAtItsLimitWithFullScale) {
  AdcBusFake bus{wiring.emitter};
  Sensor sensor{bus, wiring, clock_168};
  sensor.start();
  // (84 + 12) ADC cycles at 21 MHz, 8 core cycles each at 168 MHz: 768 cycles; twice that.
  ASSERT_EQ(sensor.eoc_poll_limit(), 2u * 96u * 8u);
  bus.eoc_never = true;
  bus.ambient_counts = 100u;
  EXPECT_EQ(sensor.read_counts(), 4095u);
  EXPECT_EQ(bus.sr_reads, 1536u);
  EXPECT_EQ(sensor.timeouts(), 1u);

  // The late conversion ends after the timeout; its EOC must not pass for the next reading's.
  bus.registers.set(adc1_sr, sr_eoc);
  bus.registers.set(adc1_dr, 100u);
  bus.eoc_never = false;
  bus.ambient_counts = 2500u;
  bus.sr_reads = 0u;
  EXPECT_EQ(sensor.read_counts(), 2500u);
  EXPECT_EQ(bus.sr_reads, 3u);
  EXPECT_EQ(sensor.timeouts(), 1u);
}

TEST(AdcWallSensor, ReadLitCountsIsLitMinusAmbientAfterTheSettleAndLeavesTheEmitterOff) {
  AdcBusFake bus{wiring.emitter};
  Sensor sensor{bus, wiring, clock_168};
  sensor.start();
  ASSERT_EQ(sensor.settle_us(), 30u);
  ASSERT_EQ(sensor.settle_cycles(), settle_cycles_168);
  bus.ambient_counts = 300u;
  bus.lit_counts = 1700u;
  // The receiver sees the emitter only 30 µs after it switched on: a reading taken sooner is
  // ambient alone, and the result would be 0.
  bus.receiver_settle_cycles = settle_cycles_168;
  sensor.set_emitter(true);  // left on by someone: the ambient reading must be dark
  bus.registers.clear_log();
  EXPECT_EQ(sensor.read_lit_counts(), 1700u);
  EXPECT_EQ(bus.conversions, 2u);
  EXPECT_FALSE(bus.emitter_on);
  // The lit conversion started once the settle time had passed, and not a read's pace later.
  EXPECT_GE(bus.lit_for_cycles, settle_cycles_168);
  EXPECT_LE(bus.lit_for_cycles, settle_cycles_168 + 2u * bus.cycles_per_read);
  // The last emitter write is its reset bit.
  std::size_t last_bsrr = bus.registers.access_count();
  for (std::size_t i = 0u; i < bus.registers.access_count(); ++i) {
    if (bus.registers.access(i).write && bus.registers.access(i).address == gpioc_bsrr) {
      last_bsrr = i;
    }
  }
  ASSERT_LT(last_bsrr, bus.registers.access_count());
  EXPECT_EQ(bus.registers.access(last_bsrr).value, 1u << (7 + 16));
  EXPECT_EQ(bus.registers.overflows(), 0u);
}

TEST(AdcWallSensor, ANearWallAboveAmbientAndAFarOneBelowIt) {
  AdcBusFake bus{wiring.emitter};
  Sensor sensor{bus, wiring, clock_168};
  sensor.start();
  bus.receiver_settle_cycles = settle_cycles_168;
  bus.ambient_counts = 4000u;  // bright ambient: little room left below full scale
  bus.lit_counts = 95u;
  EXPECT_EQ(sensor.read_lit_counts(), 95u);
  bus.ambient_counts = 0u;
  bus.lit_counts = 0u;
  EXPECT_EQ(sensor.read_lit_counts(), 0u);
}

TEST(AdcWallSensor, TheSettleWaitSpansTheCycleCounterWrap) {
  AdcBusFake bus{wiring.emitter};
  Sensor sensor{bus, wiring, clock_168};
  sensor.start();
  bus.now_cycles = 0xFFFF'FF00u;  // wraps 256 cycles into the wait
  bus.receiver_settle_cycles = settle_cycles_168;
  bus.ambient_counts = 10u;
  bus.lit_counts = 500u;
  EXPECT_EQ(sensor.read_lit_counts(), 500u);
  EXPECT_GE(bus.lit_for_cycles, settle_cycles_168);
  EXPECT_LE(bus.lit_for_cycles, settle_cycles_168 + 2u * bus.cycles_per_read);
}

TEST(AdcWallSensor, TheSettleWaitEndsWhereTheCycleCounterStandsStill) {
  AdcBusFake bus{wiring.emitter};
  Sensor sensor{bus, wiring, clock_168};
  bus.counter_runs = false;  // QEMU: DWT not modelled, CYCCNT reads 0
  sensor.start();
  bus.cyccnt_reads = 0u;
  static_cast<void>(sensor.read_lit_counts());
  // One read for the start, then at most one per settle cycle: each pass takes at least a cycle,
  // so the wait still lasts the settle time or more.
  EXPECT_EQ(bus.cyccnt_reads, 1u + settle_cycles_168);
  EXPECT_FALSE(bus.emitter_on);
}

TEST(AdcWallSensor, AWiringWithoutAnExternalChannelIsRefusedAndTouchesNothing) {
  constexpr f4::WallSensorWiring vbat{Pin{Port::c, 7u}, 18u, 30u, f4::adc::SampleTime::cycles_84};
  constexpr f4::WallSensorWiring on_itself{Pin{Port::a, 2u}, 2u, 30u,
                                           f4::adc::SampleTime::cycles_84};
  constexpr f4::WallSensorWiring slow{Pin{Port::c, 7u}, 2u, 1'001u, f4::adc::SampleTime::cycles_84};
  for (const f4::WallSensorWiring& bad : {vbat, on_itself, slow}) {
    AdcBusFake bus{bad.emitter};
    Sensor sensor{bus, bad, clock_168};
    EXPECT_FALSE(sensor.valid());
    sensor.start();
    sensor.set_emitter(true);
    EXPECT_EQ(sensor.read_counts(), 4095u);
    EXPECT_EQ(sensor.read_lit_counts(), 0u);
    EXPECT_EQ(bus.registers.access_count(), 0u);
    EXPECT_EQ(bus.cyccnt_reads, 0u);
  }
}

TEST(AdcWallSensor, TheUsualMousesFourSensorsEachSwitchTheirOwnEmitterAndConvertTheirOwnChannel) {
  const auto& table = firmware::usual_mouse_wall_sensors;
  for (std::size_t i = 0u; i < table.size(); ++i) {
    SCOPED_TRACE(testing::Message() << "sensor " << i);
    const f4::WallSensorWiring& w = table[i];
    EXPECT_GE(w.settle_us, 20u);  // the simulator's 20 µs or more
    EXPECT_LE(w.settle_us, 50u);
    AdcBusFake bus{w.emitter};
    Sensor sensor{bus, w, clock_168};
    ASSERT_TRUE(sensor.valid());
    sensor.start();
    // Receiver analog on ADC1_IN<channel> = PA<channel> (channels 0..3 of the table).
    ASSERT_LT(w.channel, 8u);
    EXPECT_EQ((bus.registers.peek(gpioa_moder) >> (2u * w.channel)) & 0b11u, 0b11u);
    bus.registers.clear_log();
    sensor.set_emitter(true);
    ASSERT_EQ(bus.registers.access_count(), 1u);
    EXPECT_EQ(bus.registers.access(0u).address, f4::gpio::bsrr(w.emitter.port).address);
    EXPECT_EQ(bus.registers.access(0u).value, 1u << w.emitter.number);
    sensor.set_emitter(false);
    bus.ambient_counts = 7u * (i + 1u);
    EXPECT_EQ(sensor.read_counts(), 7u * (i + 1u));
    EXPECT_EQ(bus.converted_channel, w.channel);
  }
}

}  // namespace
}  // namespace odocal::test
