// The parameter store: save and load, sectors filling and wrapping, corrupt and garbage records,
// sequence numbers, device geometries and errors, no allocation, and power cuts at every
// operation of a long workload (the record format: param_store_format_test.cpp).
#include "odocal/params/param_store.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <random>
#include <vector>

#include "alloc_counter.hpp"
#include "odocal/sim/ram_block_store.hpp"
#include "param_sets.hpp"

namespace odocal::params {
namespace {

using test_sets::random_set;
using test_sets::SmallFlash;

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
