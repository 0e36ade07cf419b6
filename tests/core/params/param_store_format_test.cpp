// The parameter store's record format: the CRC, records of older formats (migrated) and newer
// ones (refused), values out of range, truncated records.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <random>
#include <vector>

#include "odocal/params/crc32.hpp"
#include "odocal/params/param_store.hpp"
#include "param_sets.hpp"

namespace odocal::params {
namespace {

using test_sets::random_set;
using test_sets::SmallFlash;

void put32(std::uint8_t* p, std::uint32_t v) {
  for (int i = 0; i < 4; ++i)
    p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}
void put16(std::uint8_t* p, std::uint16_t v) {
  p[0] = static_cast<std::uint8_t>(v);
  p[1] = static_cast<std::uint8_t>(v >> 8);
}

// A version-1 record (the 13 DESIGN parameters, positional, no provenance), written by hand from
// the layout in docs/parameters.md.
std::vector<std::uint8_t> version1_record(std::uint32_t sequence, const float (&values)[13]) {
  std::vector<std::uint8_t> bytes(record_slot_size, 0xFF);
  const std::uint16_t length = 16 + 13 * 4;
  put32(&bytes[0], record_magic);
  put16(&bytes[4], 1);
  put16(&bytes[6], length);
  put32(&bytes[8], sequence);
  put16(&bytes[12], 13);
  put16(&bytes[14], 0);
  for (int i = 0; i < 13; ++i) {
    std::uint32_t bits;
    std::memcpy(&bits, &values[i], 4);
    put32(&bytes[16 + 4 * i], bits);
  }
  put32(&bytes[length], crc32(bytes.data(), length));
  return bytes;
}

void write_raw(sim::RamBlockStore& flash, std::size_t address, const std::vector<std::uint8_t>& b) {
  ASSERT_EQ(flash.program(address, b.data(), b.size()), hal::StoreStatus::ok);
}

TEST(Crc32, MatchesTheStandardCheckValue) {
  const char* text = "123456789";
  EXPECT_EQ(crc32(reinterpret_cast<const std::uint8_t*>(text), 9), 0xCBF43926u);
  // Piecewise equals whole.
  const std::uint32_t first = crc32(reinterpret_cast<const std::uint8_t*>(text), 4);
  EXPECT_EQ(crc32(reinterpret_cast<const std::uint8_t*>(text) + 4, 5, first), 0xCBF43926u);
}

TEST(ParamStore, MigratesVersion1Records) {
  SmallFlash flash;
  // c_l c_r wheelbase_mm wheel_diameter_mm f_lat f_lon counts_per_rev control_hz kp ki kff
  // max_wheel_radps cmd_timeout_ms
  const float old_values[13] = {0.99f,  1.01f, 152.0f, 61.0f, 1.02f, 0.98f, 2048.0f,
                                500.0f, 0.06f, 1.5f,   0.04f, 20.0f, 300.0f};
  write_raw(flash, 0, version1_record(7, old_values));
  ParamStore store(flash);
  ParamSet loaded;
  StoreInfo info;
  ASSERT_EQ(store.load(loaded, info), StoreResult::ok);
  EXPECT_EQ(info.record.version, 1u);
  EXPECT_TRUE(info.record.migrated);
  EXPECT_EQ(loaded.get(ParamId::c_l), 0.99f);
  EXPECT_EQ(loaded.get(ParamId::c_r), 1.01f);
  EXPECT_EQ(loaded.get(ParamId::wheelbase_mm), 152.0f);
  EXPECT_EQ(loaded.get(ParamId::wheel_diameter_mm), 61.0f);
  EXPECT_EQ(loaded.get(ParamId::f_lat), 1.02f);
  EXPECT_EQ(loaded.get(ParamId::f_lon), 0.98f);
  EXPECT_EQ(loaded.get(ParamId::counts_per_rev), 2048.0f);
  EXPECT_EQ(loaded.get(ParamId::cmd_timeout_ms), 300.0f);
  // Parameters version 1 did not have take their defaults.
  EXPECT_EQ(loaded.get(ParamId::v_max_mps), default_value(ParamId::v_max_mps));
  EXPECT_EQ(loaded.get(ParamId::max_illegal), default_value(ParamId::max_illegal));
  EXPECT_EQ(loaded.wheel.method, FactorMethod::migrated);
  // The next save writes the current format after it, with the next sequence number.
  ASSERT_EQ(store.save(loaded, info), StoreResult::ok);
  EXPECT_EQ(info.record.sequence, 8u);
  ParamSet again;
  ASSERT_EQ(store.load(again, info), StoreResult::ok);
  EXPECT_EQ(info.record.version, record_format_version);
  EXPECT_TRUE(same(loaded, again));
}

// A version-2 record saved by firmware from before wheelbase_arc_mm (ids 0-20, written by hand
// from the layout in docs/parameters.md) loads with the arc wheelbase at its default, 0 (one
// wheelbase: the robot drives as it did), every stored value and the provenance kept.
TEST(ParamStore, MigratesARecordFromBeforeTheArcWheelbase) {
  SmallFlash flash;
  constexpr std::uint16_t old_count = 21;
  static_assert(static_cast<std::size_t>(ParamId::wheelbase_arc_mm) == old_count);
  ParamSet old = default_params();
  old.set(ParamId::wheelbase_mm, 201.5f);
  old.set(ParamId::c_l, 0.998f);
  std::vector<std::uint8_t> bytes(record_slot_size, 0xFF);
  const std::uint16_t length = 16 + old_count * 8 + 24;
  put32(&bytes[0], record_magic);
  put16(&bytes[4], 2);
  put16(&bytes[6], length);
  put32(&bytes[8], 41);
  put16(&bytes[12], old_count);
  put16(&bytes[14], 0);
  for (std::uint16_t i = 0; i < old_count; ++i) {
    std::uint32_t bits;
    const float value = old.values[i];
    std::memcpy(&bits, &value, 4);
    put32(&bytes[16 + 8 * i], i);
    put32(&bytes[16 + 8 * i + 4], bits);
  }
  // Wheel provenance {fit, 0, 60 runs, date, quality 0}, lateral {defaults}.
  std::uint8_t* provenance = &bytes[16 + old_count * 8];
  provenance[0] = static_cast<std::uint8_t>(FactorMethod::fit);
  provenance[1] = 0;
  put16(provenance + 2, 60);
  put32(provenance + 4, 1767000000u);
  put32(provenance + 8, 0u);
  std::memset(provenance + 12, 0, 12);
  put32(&bytes[length], crc32(bytes.data(), length));
  write_raw(flash, 0, bytes);

  ParamStore store(flash);
  ParamSet loaded;
  StoreInfo info;
  ASSERT_EQ(store.load(loaded, info), StoreResult::ok);
  EXPECT_EQ(info.record.version, 2u);
  EXPECT_TRUE(info.record.migrated);
  EXPECT_EQ(loaded.get(ParamId::wheelbase_arc_mm), 0.0f);
  EXPECT_EQ(default_value(ParamId::wheelbase_arc_mm), 0.0f);
  EXPECT_EQ(loaded.get(ParamId::wheelbase_mm), 201.5f);
  EXPECT_EQ(loaded.get(ParamId::c_l), 0.998f);
  EXPECT_EQ(loaded.wheel.method, FactorMethod::fit);
  EXPECT_EQ(loaded.wheel.runs, 60u);
  EXPECT_EQ(loaded.wheel.date_unix_s, 1767000000u);
  // The drive takes it, and the arc wheelbase then changes nothing (see the kinematics tests).
  EXPECT_TRUE(drive::valid(to_drive_config(loaded)));
  // Saved again, it is a whole current record.
  ASSERT_EQ(store.save(loaded, info), StoreResult::ok);
  ParamSet again;
  ASSERT_EQ(store.load(again, info), StoreResult::ok);
  EXPECT_FALSE(info.record.migrated);
  EXPECT_TRUE(same(loaded, again));
}

TEST(ParamStore, RefusesANewerRecordFormatWithoutFallingBack) {
  SmallFlash flash;
  ParamStore store(flash);
  std::mt19937 rng(6);
  StoreInfo info;
  ASSERT_EQ(store.save(random_set(rng), info), StoreResult::ok);
  // A version-3 record (from a newer firmware) with a valid CRC after it.
  std::vector<std::uint8_t> bytes(record_slot_size, 0xFF);
  put32(&bytes[0], record_magic);
  put16(&bytes[4], 3);
  put16(&bytes[6], 40);
  put32(&bytes[8], 2);
  put16(&bytes[12], 0);
  for (int i = 14; i < 40; ++i)
    bytes[i] = 0x11;
  put32(&bytes[40], crc32(bytes.data(), 40));
  write_raw(flash, record_slot_size, bytes);
  ParamSet loaded = default_params();
  loaded.set(ParamId::kp, 3.0f);
  EXPECT_EQ(store.load(loaded, info), StoreResult::newer_version);
  EXPECT_EQ(info.record.version, 3u);
  EXPECT_EQ(loaded.get(ParamId::kp), 3.0f);  // untouched: neither garbage nor the older set
  EXPECT_STRNE(to_string(StoreResult::newer_version), "");
}

TEST(ParamStore, RecordWithAnOutOfRangeValueIsRefused) {
  std::array<std::uint8_t, record_slot_size> bytes{};
  ParamSet set = default_params();
  set.set(ParamId::c_l, 5.0f);  // outside [0.5, 2]
  ASSERT_GT(encode_record(set, 1, bytes.data(), bytes.size()), 0u);
  ParamSet out;
  RecordInfo info;
  EXPECT_EQ(decode_record(bytes.data(), bytes.size(), out, info), DecodeStatus::corrupt);
  // And save refuses to store what load would refuse.
  SmallFlash flash;
  ParamStore store(flash);
  StoreInfo store_info;
  EXPECT_EQ(store.save(set, store_info), StoreResult::device_error);
  EXPECT_EQ(flash.operations(), 0u);
}

TEST(ParamStore, DecodeRejectsEveryTruncation) {
  std::array<std::uint8_t, record_slot_size> bytes{};
  const std::size_t length = encode_record(default_params(), 9, bytes.data(), bytes.size());
  ASSERT_GT(length, 0u);
  ParamSet out;
  RecordInfo info;
  ASSERT_EQ(decode_record(bytes.data(), bytes.size(), out, info), DecodeStatus::ok);
  for (std::size_t size = 0; size < length; ++size) {
    EXPECT_EQ(decode_record(bytes.data(), size, out, info), DecodeStatus::corrupt) << size;
  }
  EXPECT_EQ(decode_record(nullptr, 256, out, info), DecodeStatus::corrupt);
  std::array<std::uint8_t, record_slot_size> blank;
  blank.fill(0xFF);
  EXPECT_EQ(decode_record(blank.data(), blank.size(), out, info), DecodeStatus::blank);
}

}  // namespace
}  // namespace odocal::params
