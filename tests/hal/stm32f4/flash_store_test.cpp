// The STM32F4 flash store against the model of the flash rules: every operation follows the
// unlock / BSY / error / lock sequence, flash only clears bits, failures become device_error and
// leave the controller locked, and the parameter store works on top of it.

#include <array>
#include <cstdint>

#include <gtest/gtest.h>

#include "flash_model.hpp"
#include "odocal/hal/stm32f4/flash_registers.hpp"
#include "odocal/hal/stm32f4/flash_store.hpp"
#include "odocal/params/param_store.hpp"

namespace odocal::test {
namespace {

namespace f4 = hal::stm32f4;
using hal::StoreStatus;

constexpr std::uintptr_t store_base = 0x0800'4000u;  // sector 1

struct Fixture : ::testing::Test {
  FlashModel model;
  SteppingClock clock;
  ModelFlashStore store{model, clock, 1u, 2u};
};

TEST_F(Fixture, UsesSectorsOneAndTwoOf16KiB) {
  EXPECT_TRUE(store.valid());
  EXPECT_EQ(store.sector_size(), 16u * 1024u);
  EXPECT_EQ(store.sector_count(), 2u);
  EXPECT_EQ(store.program_granularity(), 4u);
  EXPECT_EQ(store.base_address(), store_base);
}

TEST(FlashStoreLayout, RefusesSectorZeroMixedSizesAndMissingSectors) {
  FlashModel model;
  SteppingClock clock;
  EXPECT_FALSE((ModelFlashStore{model, clock, 0u, 2u}.valid()));   // the vector table
  EXPECT_FALSE((ModelFlashStore{model, clock, 3u, 2u}.valid()));   // 16 KiB + 64 KiB
  EXPECT_FALSE((ModelFlashStore{model, clock, 11u, 2u}.valid()));  // there is no sector 12
  EXPECT_TRUE((ModelFlashStore{model, clock, 10u, 2u}.valid()));   // two 128 KiB sectors
  ModelFlashStore invalid{model, clock, 0u, 2u};
  EXPECT_EQ(invalid.erase(0u), StoreStatus::out_of_range);
  EXPECT_EQ(model.erases(), 0u);
}

TEST_F(Fixture, EraseProgramReadRoundTripAndLocksAfterEachOperation) {
  ASSERT_EQ(store.erase(1u), StoreStatus::ok);
  EXPECT_TRUE(model.locked());
  const std::array<std::uint8_t, 8> data{1, 2, 3, 4, 0xA5, 0x5A, 0x00, 0x7F};
  ASSERT_EQ(store.program(16u * 1024u + 8u, data.data(), data.size()), StoreStatus::ok);
  EXPECT_TRUE(model.locked());
  std::array<std::uint8_t, 8> back{};
  ASSERT_EQ(store.read(16u * 1024u + 8u, back.data(), back.size()), StoreStatus::ok);
  EXPECT_EQ(back, data);
  EXPECT_EQ(model.byte(0x0800'8000u + 8u), 1u);  // sector 2 holds store sector 1
  // Unaligned reads work byte-wise.
  std::array<std::uint8_t, 3> middle{};
  ASSERT_EQ(store.read(16u * 1024u + 9u, middle.data(), middle.size()), StoreStatus::ok);
  EXPECT_EQ(middle, (std::array<std::uint8_t, 3>{2, 3, 4}));
  EXPECT_EQ(model.violations(), 0u);
  EXPECT_EQ(model.raise_attempts(), 0u);
}

TEST_F(Fixture, EraseTouchesOnlyItsSectorAndFlushesTheDataCache) {
  model.poke(0x0800'3FFCu, 0x12u);  // last word of sector 0 (the vectors)
  model.poke(0x0800'4000u, 0x00u);  // store sector 0
  model.poke(0x0800'C000u, 0x34u);  // sector 3 (the program)
  model.write32(f4::flash::acr.address, f4::flash::acr_dcen.mask() | f4::flash::acr_icen.mask());
  ASSERT_EQ(store.erase(0u), StoreStatus::ok);
  EXPECT_EQ(model.byte(0x0800'4000u), 0xFFu);
  EXPECT_EQ(model.byte(0x0800'3FFCu), 0x12u);
  EXPECT_EQ(model.byte(0x0800'C000u), 0x34u);
  EXPECT_EQ(model.cache_resets(), 1u);
  EXPECT_NE(model.read32(f4::flash::acr.address) & f4::flash::acr_dcen.mask(), 0u);
  EXPECT_EQ(model.violations(), 0u);
}

TEST_F(Fixture, ProgramNeedingAZeroToOneIsRefusedAndWritesNothing) {
  ASSERT_EQ(store.erase(0u), StoreStatus::ok);
  const std::array<std::uint8_t, 8> first{0x0F, 0xFF, 0xFF, 0xFF, 0x00, 0x00, 0x00, 0x00};
  ASSERT_EQ(store.program(0u, first.data(), first.size()), StoreStatus::ok);
  const std::uint32_t words = model.words_programmed();
  // Word 0 would need bits 4..7 back to 1: refused before anything is written (word 1 included).
  const std::array<std::uint8_t, 8> second{0xF0, 0xFF, 0xFF, 0xFF, 0x00, 0x00, 0x00, 0x00};
  EXPECT_EQ(store.program(0u, second.data(), second.size()), StoreStatus::not_erased);
  EXPECT_EQ(model.words_programmed(), words);
  EXPECT_EQ(model.byte(store_base), 0x0Fu);
  // Clearing more bits of a programmed word is what flash can do.
  const std::array<std::uint8_t, 4> more{0x03, 0xFF, 0xFF, 0xFF};
  EXPECT_EQ(store.program(0u, more.data(), more.size()), StoreStatus::ok);
  EXPECT_EQ(model.byte(store_base), 0x03u);
  EXPECT_EQ(model.raise_attempts(), 0u);
  EXPECT_TRUE(model.locked());
}

TEST_F(Fixture, MisalignedProgramIsRefusedByTheInterface) {
  const std::array<std::uint8_t, 4> data{0, 0, 0, 0};
  EXPECT_EQ(store.program(2u, data.data(), data.size()), StoreStatus::out_of_range);
  EXPECT_EQ(store.program(0u, data.data(), 3u), StoreStatus::out_of_range);
  EXPECT_EQ(store.program(2u * 16u * 1024u, data.data(), 4u), StoreStatus::out_of_range);
  EXPECT_EQ(model.words_programmed(), 0u);
}

TEST_F(Fixture, StaleErrorFlagsAreClearedBeforeAnOperation) {
  // An error left by someone else (e.g. a debugger) must not fail the next operation.
  model.fail_next(f4::flash::sr_pgserr.mask());
  const std::array<std::uint8_t, 4> data{0, 0, 0, 0};
  EXPECT_EQ(store.program(0u, data.data(), data.size()), StoreStatus::device_error);
  EXPECT_NE(store.last_error_flags() & f4::flash::sr_pgserr.mask(), 0u);
  EXPECT_EQ(model.sr_bits() & f4::flash::sr_errors, 0u);  // the store cleared what it saw
  EXPECT_EQ(store.program(0u, data.data(), data.size()), StoreStatus::ok);
  EXPECT_TRUE(model.locked());
}

TEST_F(Fixture, WriteProtectedSectorGivesDeviceErrorAndStaysLocked) {
  model.protect(2u);
  EXPECT_EQ(store.erase(1u), StoreStatus::device_error);
  EXPECT_NE(store.last_error_flags() & f4::flash::sr_wrperr.mask(), 0u);
  EXPECT_TRUE(model.locked());
  EXPECT_EQ(store.erase(0u), StoreStatus::ok);  // the other sector still works
  EXPECT_EQ(model.violations(), 0u);
}

TEST_F(Fixture, InjectedEraseErrorIsReported) {
  model.fail_next(f4::flash::sr_operr.mask());
  EXPECT_EQ(store.erase(0u), StoreStatus::device_error);
  EXPECT_TRUE(model.locked());
  EXPECT_EQ(model.violations(), 0u);
}

TEST_F(Fixture, HungControllerTimesOutInsteadOfHanging) {
  model.stick_busy();
  EXPECT_EQ(store.erase(0u), StoreStatus::device_error);
  const std::array<std::uint8_t, 4> data{0, 0, 0, 0};
  EXPECT_EQ(store.program(0u, data.data(), data.size()), StoreStatus::device_error);
  EXPECT_EQ(model.erases(), 0u);
}

TEST_F(Fixture, ControllerLockedUntilResetIsReportedNotForced) {
  model.write32(f4::flash::keyr.address, 0x1234u);  // a wrong key: locked until reset
  ASSERT_TRUE(model.hard_locked());
  EXPECT_EQ(store.erase(0u), StoreStatus::device_error);
  EXPECT_EQ(model.erases(), 0u);
}

TEST_F(Fixture, ErasedWordsAreNotProgrammed) {
  ASSERT_EQ(store.erase(0u), StoreStatus::ok);
  std::array<std::uint8_t, 256> data{};
  data.fill(0xFFu);
  data[0] = 0x00u;
  ASSERT_EQ(store.program(0u, data.data(), data.size()), StoreStatus::ok);
  EXPECT_EQ(model.words_programmed(), 1u);  // 63 all-ones words left erased
}

TEST_F(Fixture, ParameterStoreSavesAndReloadsThroughTheFlashBackend) {
  params::ParamStore param_store{store};
  params::ParamSet set = params::default_params();
  set.set(params::ParamId::c_l, 1.01f);
  params::StoreInfo info;
  ASSERT_EQ(param_store.save(set, info), params::StoreResult::ok);
  for (int i = 0; i < 200; ++i) {  // enough saves to wrap from sector A to B and back
    ASSERT_EQ(param_store.save(set, info), params::StoreResult::ok) << "save " << i;
  }
  params::ParamSet loaded{};
  params::StoreInfo loaded_info;
  ASSERT_EQ(param_store.load(loaded, loaded_info), params::StoreResult::ok);
  EXPECT_EQ(loaded_info.record.sequence, info.record.sequence);
  EXPECT_FLOAT_EQ(loaded.get(params::ParamId::c_l), 1.01f);
  EXPECT_GE(model.erases(), 3u);
  EXPECT_EQ(model.violations(), 0u);
  EXPECT_EQ(model.raise_attempts(), 0u);
  EXPECT_TRUE(model.locked());
}

}  // namespace
}  // namespace odocal::test
