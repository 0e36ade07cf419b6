#include "odocal/params/param_store.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <vector>

#include "alloc_counter.hpp"
#include "odocal/params/crc32.hpp"
#include "odocal/sim/ram_block_store.hpp"

namespace odocal::params {
namespace {

// Small sectors (4 slots each) so the workloads below wrap between A and B many times.
using SmallFlash = sim::StaticRamBlockStore<1024, 4, 4>;

ParamSet random_set(std::mt19937& rng) {
  ParamSet set = default_params();
  for (std::size_t i = 0; i < param_count; ++i) {
    const auto id = static_cast<ParamId>(i);
    const ParamInfo& info = param_info(id);
    std::uniform_real_distribution<float> pick(info.min, info.max);
    float value = pick(rng);
    if (info.integer) {
      value = static_cast<float>(static_cast<std::uint32_t>(value));
    }
    set.set(id, value);
  }
  set.wheel.method = FactorMethod::umbmark;
  set.wheel.runs = static_cast<std::uint16_t>(rng() % 64u);
  set.wheel.date_unix_s = rng();
  set.wheel.quality_mm = static_cast<float>(rng() % 1000u) * 0.1f;
  set.lateral.method = FactorMethod::manual;
  return set;
}

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

TEST(ParamStore, BlankFlashIsEmptyAndATornFirstRecordIsCorrupt) {
  SmallFlash flash;
  ParamStore store(flash);
  ParamSet loaded;
  StoreInfo info;
  EXPECT_EQ(store.load(loaded, info), StoreResult::empty);
  EXPECT_EQ(info.damaged, 0u);
  // One programmed unit of a first save that never finished: written, but not a record.
  flash.cut_after(0, 1);
  EXPECT_EQ(store.save(default_params(), info), StoreResult::device_error);
  flash.power_on();
  EXPECT_EQ(store.load(loaded, info), StoreResult::corrupt);
  EXPECT_EQ(info.damaged, 1u);
}

TEST(ParamStore, EmptyFlashLoadsNothing) {
  SmallFlash flash;
  ParamStore store(flash);
  ParamSet out = default_params();
  out.set(ParamId::kp, 7.0f);
  StoreInfo info;
  EXPECT_EQ(store.load(out, info), StoreResult::empty);
  EXPECT_EQ(out.get(ParamId::kp), 7.0f);  // untouched
}

TEST(ParamStore, SaveThenLoadReturnsTheSameSet) {
  SmallFlash flash;
  std::mt19937 rng(1);
  const ParamSet saved = random_set(rng);
  {
    ParamStore store(flash);
    StoreInfo info;
    ASSERT_EQ(store.save(saved, info), StoreResult::ok);
    EXPECT_EQ(info.record.sequence, 1u);
  }
  ParamStore rebooted(flash);  // a new object over the same flash: a restart
  ParamSet loaded;
  StoreInfo info;
  ASSERT_EQ(rebooted.load(loaded, info), StoreResult::ok);
  EXPECT_TRUE(same(saved, loaded));
  EXPECT_EQ(info.record.version, record_format_version);
  EXPECT_FALSE(info.record.migrated);
}

TEST(ParamStore, EachSaveProgramsOneSlotAndErasesOnlyWhenASectorIsFull) {
  SmallFlash flash;
  ParamStore store(flash, 1);  // sectors 1 and 2
  ASSERT_EQ(store.slots_per_sector(), 4u);
  std::mt19937 rng(2);
  ParamSet last;
  for (int i = 0; i < 40; ++i) {
    last = random_set(rng);
    StoreInfo info;
    ASSERT_EQ(store.save(last, info), StoreResult::ok);
    EXPECT_EQ(info.record.sequence, static_cast<std::uint32_t>(i + 1));
  }
  // 40 saves, 4 slots per sector: the first 4 fill sector 1 (erased at the factory), then every
  // 4 saves erase the other sector once: 9 erases, alternating.
  EXPECT_EQ(flash.erase_count(0), 0u);
  EXPECT_EQ(flash.erase_count(3), 0u);
  EXPECT_EQ(flash.erase_count(1) + flash.erase_count(2), 9u);
  EXPECT_LE(flash.erase_count(1) > flash.erase_count(2)
                ? flash.erase_count(1) - flash.erase_count(2)
                : flash.erase_count(2) - flash.erase_count(1),
            1u);
  ParamSet loaded;
  StoreInfo info;
  ASSERT_EQ(store.load(loaded, info), StoreResult::ok);
  EXPECT_TRUE(same(last, loaded));
  EXPECT_EQ(info.record.sequence, 40u);
}

TEST(ParamStore, CorruptNewestRecordFallsBackToThePreviousOne) {
  SmallFlash flash;
  ParamStore store(flash);
  std::mt19937 rng(3);
  const ParamSet first = random_set(rng);
  const ParamSet second = random_set(rng);
  StoreInfo info;
  ASSERT_EQ(store.save(first, info), StoreResult::ok);
  ASSERT_EQ(store.save(second, info), StoreResult::ok);
  // Clear one bit inside the newest record's values (what a flash disturb could do).
  flash.memory()[info.sector * 1024 + info.slot * record_slot_size + 40] &= 0xFE;
  ParamSet loaded;
  ASSERT_EQ(store.load(loaded, info), StoreResult::ok);
  EXPECT_TRUE(same(first, loaded));
  EXPECT_EQ(info.record.sequence, 1u);
}

TEST(ParamStore, EveryRecordCorruptIsReportedAsCorruptNotEmpty) {
  SmallFlash flash;
  ParamStore store(flash);
  std::mt19937 rng(4);
  StoreInfo info;
  ASSERT_EQ(store.save(random_set(rng), info), StoreResult::ok);
  ASSERT_EQ(store.save(random_set(rng), info), StoreResult::ok);
  for (std::size_t slot = 0; slot < 2; ++slot) {
    flash.memory()[slot * record_slot_size + 200] ^= 0x10;  // inside the CRC-covered bytes
  }
  const std::vector<std::uint8_t> damaged(flash.memory(), flash.memory() + 4096);
  ParamSet loaded = default_params();
  const ParamSet untouched = loaded;
  EXPECT_EQ(store.load(loaded, info), StoreResult::corrupt);
  EXPECT_EQ(info.damaged, 2u);
  EXPECT_TRUE(same(loaded, untouched));
  EXPECT_STREQ(to_string(StoreResult::corrupt), "every stored record is damaged");
  // Loading again and again keeps the damaged image for inspection: load never writes.
  EXPECT_EQ(store.load(loaded, info), StoreResult::corrupt);
  EXPECT_TRUE(std::equal(damaged.begin(), damaged.end(), flash.memory()));
  EXPECT_EQ(flash.operations(), 2u);  // the two saves: nothing erased or programmed since
  // And the store is still usable: the damaged slots are skipped.
  const ParamSet next = random_set(rng);
  ASSERT_EQ(store.save(next, info), StoreResult::ok);
  ASSERT_EQ(store.load(loaded, info), StoreResult::ok);
  EXPECT_TRUE(same(next, loaded));
}

TEST(ParamStore, GarbageFlashIsNeverLoaded) {
  SmallFlash flash;
  std::mt19937 rng(5);
  for (std::size_t i = 0; i < 4096; ++i)
    flash.memory()[i] = static_cast<std::uint8_t>(rng());
  ParamStore store(flash);
  ParamSet loaded;
  StoreInfo info;
  EXPECT_EQ(store.load(loaded, info), StoreResult::corrupt);  // written, but nothing whole
  EXPECT_EQ(info.damaged, 8u);
  const ParamSet next = random_set(rng);
  ASSERT_EQ(store.save(next, info), StoreResult::ok);  // erases a sector, then writes
  ASSERT_EQ(store.load(loaded, info), StoreResult::ok);
  EXPECT_TRUE(same(next, loaded));
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

TEST(ParamStore, SequenceNumbersWrapAroundModulo2To32) {
  SmallFlash flash;
  ParamStore store(flash);
  std::array<std::uint8_t, record_slot_size> bytes{};
  ASSERT_GT(encode_record(default_params(), 0xFFFFFFFEu, bytes.data(), bytes.size()), 0u);
  ASSERT_EQ(flash.program(0, bytes.data(), bytes.size()), hal::StoreStatus::ok);
  std::mt19937 rng(7);
  const ParamSet a = random_set(rng);
  const ParamSet b = random_set(rng);
  StoreInfo info;
  ASSERT_EQ(store.save(a, info), StoreResult::ok);
  EXPECT_EQ(info.record.sequence, 0xFFFFFFFFu);
  ASSERT_EQ(store.save(b, info), StoreResult::ok);
  EXPECT_EQ(info.record.sequence, 0u);
  ParamSet loaded;
  ASSERT_EQ(store.load(loaded, info), StoreResult::ok);
  EXPECT_TRUE(same(b, loaded));
}

TEST(ParamStore, WorksWithCoarseProgramGranularity) {
  sim::StaticRamBlockStore<2048, 2, 32> flash;
  ParamStore store(flash);
  ASSERT_EQ(store.slots_per_sector(), 8u);
  std::mt19937 rng(8);
  ParamSet last;
  StoreInfo info;
  for (int i = 0; i < 20; ++i) {
    last = random_set(rng);
    ASSERT_EQ(store.save(last, info), StoreResult::ok);
  }
  ParamSet loaded;
  ASSERT_EQ(store.load(loaded, info), StoreResult::ok);
  EXPECT_TRUE(same(last, loaded));
}

TEST(ParamStore, RefusesAGeometryThatCannotHoldTwoSectors) {
  sim::StaticRamBlockStore<128, 4, 4> tiny_sectors;
  ParamStore a(tiny_sectors);
  ParamSet set = default_params();
  StoreInfo info;
  EXPECT_EQ(a.load(set, info), StoreResult::bad_geometry);
  EXPECT_EQ(a.save(set, info), StoreResult::bad_geometry);
  SmallFlash flash;
  ParamStore last_sector(flash, 3);  // needs sectors 3 and 4; there are 4 (0..3)
  EXPECT_EQ(last_sector.save(set, info), StoreResult::bad_geometry);
  sim::StaticRamBlockStore<1024, 2, 512> huge_granularity;
  ParamStore c(huge_granularity);
  EXPECT_EQ(c.save(set, info), StoreResult::bad_geometry);
}

TEST(ParamStore, DeviceErrorsAreReported) {
  SmallFlash flash;
  ParamStore store(flash);
  flash.cut_after(0);
  StoreInfo info;
  EXPECT_EQ(store.save(default_params(), info), StoreResult::device_error);
}

TEST(ParamStore, LoadAndSaveAllocateNothing) {
  SmallFlash flash;
  ParamStore store(flash);
  std::mt19937 rng(9);
  const ParamSet set = random_set(rng);
  test::AllocationWatch watch;
  StoreInfo info;
  ParamSet loaded;
  for (int i = 0; i < 10; ++i) {
    ASSERT_EQ(store.save(set, info), StoreResult::ok);
    ASSERT_EQ(store.load(loaded, info), StoreResult::ok);
  }
  EXPECT_EQ(watch.allocations(), 0u);
}

// ESP-IDF-style power-cut test. A long random workload of saves runs once without cuts, recording
// the flash image before every save. Then, for every erase/program operation k of the workload
// and four ways of dying (before the operation takes effect, half-way through it, half-way with
// the next unit's bits torn, after it completed but before it returned), the image before the save
// holding k is restored, power is cut at k, the device reboots, and the store must load a whole
// set: the one the interrupted save was writing, or the one saved before it. Finally the rebooted
// store must accept and return a new save (a cut never wedges it).
TEST(ParamStore, PowerCutAtEveryOperationOfALongWorkloadLeavesAWholeSet) {
  constexpr int kSaves = 3000;
  std::mt19937 rng(2024);
  std::vector<ParamSet> sets;
  std::vector<std::vector<std::uint8_t>> images;
  std::vector<std::size_t> ops_before;
  SmallFlash flash;
  {
    ParamStore store(flash);
    ParamSet current = default_params();
    for (int i = 0; i < kSaves; ++i) {
      // Between saves a user changes a few parameters (the "set" of the workload).
      const int changes = 1 + static_cast<int>(rng() % 3u);
      for (int c = 0; c < changes; ++c) {
        const auto id = static_cast<ParamId>(rng() % param_count);
        const ParamInfo& info = param_info(id);
        float value = std::uniform_real_distribution<float>(info.min, info.max)(rng);
        if (info.integer)
          value = static_cast<float>(static_cast<std::uint32_t>(value));
        current.set(id, value);
      }
      current.wheel.runs = static_cast<std::uint16_t>(i);
      sets.push_back(current);
      images.emplace_back(flash.memory(), flash.memory() + 4096);
      ops_before.push_back(flash.operations());
      StoreInfo info;
      ASSERT_EQ(store.save(current, info), StoreResult::ok) << i;
    }
  }
  const std::size_t total_ops = flash.operations();
  ops_before.push_back(total_ops);

  struct Mode {
    std::size_t partial_units;
    bool tear;
  };
  // Before the operation, mid-record (32 units of 4 bytes), mid-record with torn bits, and the
  // whole operation landing but power failing before it is acknowledged.
  const Mode modes[] = {{0, false}, {32, false}, {32, true}, {100000, false}};
  std::size_t cut_points = 0;
  std::size_t loaded_new = 0;
  std::size_t loaded_old = 0;
  std::size_t save_index = 0;
  for (std::size_t k = 0; k < total_ops; ++k) {
    while (ops_before[save_index + 1] <= k)
      ++save_index;
    for (const Mode& mode : modes) {
      SmallFlash victim;
      std::memcpy(victim.memory(), images[save_index].data(), 4096);
      {
        ParamStore store(victim);
        victim.cut_after(k - ops_before[save_index], mode.partial_units, mode.tear);
        StoreInfo info;
        EXPECT_EQ(store.save(sets[save_index], info), StoreResult::device_error);
        ASSERT_TRUE(victim.cut_happened());
      }
      victim.power_on();
      ParamStore rebooted(victim);
      ParamSet loaded;
      StoreInfo info;
      const StoreResult result = rebooted.load(loaded, info);
      ++cut_points;
      if (save_index == 0 && (result == StoreResult::empty || result == StoreResult::corrupt)) {
        // Nothing had been saved yet: empty is the previous state, and a torn first record is
        // written flash that holds no record.
        ++loaded_old;
      } else {
        ASSERT_EQ(result, StoreResult::ok) << "cut at op " << k;
        const bool is_new = same(loaded, sets[save_index]);
        const bool is_old = save_index > 0 && same(loaded, sets[save_index - 1]);
        ASSERT_TRUE(is_new || is_old) << "cut at op " << k << " loaded a mixed or stale set";
        (is_new ? loaded_new : loaded_old) += 1;
      }
      const ParamSet after = sets[(save_index + 7) % sets.size()];
      ASSERT_EQ(rebooted.save(after, info), StoreResult::ok) << "cut at op " << k;
      ASSERT_EQ(rebooted.load(loaded, info), StoreResult::ok);
      ASSERT_TRUE(same(after, loaded));
    }
  }
  std::printf(
      "power-cut test: %d saves, %zu operations, %zu cut points (%zu kept the new set, "
      "%zu the previous one)\n",
      kSaves, total_ops, cut_points, loaded_new, loaded_old);
  RecordProperty("cut_points", static_cast<int>(cut_points));
  EXPECT_EQ(cut_points, 4 * total_ops);
  EXPECT_GT(loaded_new, 0u);
  EXPECT_GT(loaded_old, 0u);
}

}  // namespace
}  // namespace odocal::params
