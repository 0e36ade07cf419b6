// The RAM flash the store is tested on (and the QEMU image runs on) must behave like NOR flash,
// or the store tests prove nothing.
#include "odocal/sim/ram_block_store.hpp"

#include <gtest/gtest.h>

#include <array>

namespace odocal::sim {
namespace {

TEST(RamBlockStore, StartsErasedAndKeepsFlashRules) {
  StaticRamBlockStore<256, 4, 8> flash;
  EXPECT_EQ(flash.total_size(), 1024u);
  for (std::size_t i = 0; i < 1024; ++i)
    ASSERT_EQ(flash.memory()[i], 0xFF);
  std::array<std::uint8_t, 8> word{0x0F, 0xF0, 0x00, 0xFF, 0x12, 0x34, 0x56, 0x78};
  ASSERT_EQ(flash.program(256, word.data(), 8), hal::StoreStatus::ok);
  // 1 -> 0 only: setting a cleared bit again is refused and writes nothing.
  std::array<std::uint8_t, 8> back_up{0xFF, 0xF0, 0x00, 0xFF, 0x12, 0x34, 0x56, 0x78};
  EXPECT_EQ(flash.program(256, back_up.data(), 8), hal::StoreStatus::not_erased);
  EXPECT_EQ(flash.memory()[256], 0x0F);
  // Clearing more bits is allowed.
  std::array<std::uint8_t, 8> fewer{0x0E, 0xF0, 0x00, 0xFF, 0x12, 0x34, 0x56, 0x78};
  EXPECT_EQ(flash.program(256, fewer.data(), 8), hal::StoreStatus::ok);
  EXPECT_EQ(flash.memory()[256], 0x0E);
  // Granularity and bounds.
  EXPECT_EQ(flash.program(260, word.data(), 8), hal::StoreStatus::out_of_range);
  EXPECT_EQ(flash.program(256, word.data(), 4), hal::StoreStatus::out_of_range);
  EXPECT_EQ(flash.program(1024, word.data(), 8), hal::StoreStatus::out_of_range);
  EXPECT_EQ(flash.erase(4), hal::StoreStatus::out_of_range);
  // Erase is per sector and counted.
  ASSERT_EQ(flash.erase(1), hal::StoreStatus::ok);
  EXPECT_EQ(flash.memory()[256], 0xFF);
  EXPECT_EQ(flash.erase_count(1), 1u);
  EXPECT_EQ(flash.erase_count(0), 0u);
}

TEST(RamBlockStore, CutStopsAfterNOperationsMidProgramAndUntilPowerOn) {
  StaticRamBlockStore<256, 2, 4> flash;
  std::array<std::uint8_t, 16> zeros{};
  flash.cut_after(1, 2);  // the first operation succeeds, the second is cut after 2 units
  ASSERT_EQ(flash.program(0, zeros.data(), 16), hal::StoreStatus::ok);
  EXPECT_FALSE(flash.cut_happened());
  EXPECT_EQ(flash.program(16, zeros.data(), 16), hal::StoreStatus::device_error);
  EXPECT_TRUE(flash.cut_happened());
  for (int i = 16; i < 24; ++i)
    EXPECT_EQ(flash.memory()[i], 0x00) << i;  // 2 units landed
  for (int i = 24; i < 32; ++i)
    EXPECT_EQ(flash.memory()[i], 0xFF) << i;  // the rest did not
  // Powered off: nothing else happens until power_on.
  EXPECT_EQ(flash.erase(0), hal::StoreStatus::device_error);
  EXPECT_EQ(flash.memory()[0], 0x00);
  flash.power_on();
  EXPECT_EQ(flash.erase(0), hal::StoreStatus::ok);
  EXPECT_EQ(flash.memory()[0], 0xFF);
}

TEST(RamBlockStore, TornBitsAndPartialErase) {
  StaticRamBlockStore<256, 2, 4> flash;
  std::array<std::uint8_t, 8> zeros{};
  flash.cut_after(0, 1, true);  // one unit lands, the next is half-programmed
  EXPECT_EQ(flash.program(0, zeros.data(), 8), hal::StoreStatus::device_error);
  for (int i = 0; i < 4; ++i)
    EXPECT_EQ(flash.memory()[i], 0x00);
  for (int i = 4; i < 8; ++i)
    EXPECT_EQ(flash.memory()[i], 0xAA);  // some bits reached 0
  flash.power_on();
  std::array<std::uint8_t, 256> sector{};
  ASSERT_EQ(flash.program(256, sector.data(), 256), hal::StoreStatus::ok);
  flash.cut_after(0, 8);  // an erase cut after 8 units (32 bytes)
  EXPECT_EQ(flash.erase(1), hal::StoreStatus::device_error);
  EXPECT_EQ(flash.memory()[256 + 31], 0xFF);
  EXPECT_EQ(flash.memory()[256 + 32], 0x00);
}

}  // namespace
}  // namespace odocal::sim
