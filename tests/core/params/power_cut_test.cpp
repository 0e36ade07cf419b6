// Power cuts and flash damage against the parameter store on the RAM flash and on the file store
// (hal/posix): every bit of a record and of its erase, cuts during the recovery save, and a long
// workload on one flash whose damage accumulates. Then each guard of the store (CRC, read-back,
// sequence number) is switched off in turn and the same workload must fail: none is redundant.
// The STM32F4 driver runs the same harness in tests/stm32f4/flash_power_cut_test.cpp.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <memory>
#include <string>

#include "odocal/posix/file_block_store.hpp"
#include "odocal/sim/ram_block_store.hpp"
#include "power_cut_harness.hpp"

namespace odocal::test {
namespace {

using params::ParamSet;
using params::StoreGuards;

// 1 KiB sectors of 4 slots: a save wraps to the other sector every 4 saves.
using Ram = sim::StaticRamBlockStore<1024, 2, 4>;

struct RamBackend {
  Ram ram;
  FaultyFlash flash{&ram};
  Backend backend{"ram", &flash, [] {}};  // RAM keeps its content; the store is rebuilt
};

struct FileBackend {
  explicit FileBackend(const std::string& name)
      : path(::testing::TempDir() + "odocal_power_cut_" + name + ".bin") {
    std::remove(path.c_str());
    reboot();
    backend = Backend{"file", &flash, [this] { reboot(); }};
  }
  ~FileBackend() { std::remove(path.c_str()); }
  void reboot() {
    file = std::make_unique<posix::FileBlockStore>(path, 1024u, 2u, 4u);
    std::string error;
    EXPECT_TRUE(file->open(error)) << error;
    flash.retarget(file.get());
  }
  std::string path;
  std::unique_ptr<posix::FileBlockStore> file;
  FaultyFlash flash{nullptr};
  Backend backend;
};

// Images with k saves made, the sets saved, and the next two sets.
struct History {
  std::vector<std::vector<std::uint8_t>> images;
  std::vector<ParamSet> sets;
};

History build_history(Backend& b, int saves) {
  History h;
  std::mt19937 rng(77);
  ParamSet current = params::default_params();
  params::ParamStore store(*b.flash);
  for (int i = 0; i < saves + 2; ++i) {
    h.images.push_back(b.flash->snapshot());
    current = random_change(current, rng, static_cast<std::uint16_t>(i));
    h.sets.push_back(current);
    params::StoreInfo info;
    EXPECT_EQ(store.save(current, info), params::StoreResult::ok);
  }
  return h;
}

// Every bit of the record (both orders) and 512 places of the erase, from the states where the
// next save programs a slot (k = 2), wraps with an erase of the empty sector (k = 4) and wraps
// over older records (k = 8); every 16th cut gets cuts at every byte of the recovery save.
Outcome every_bit(Backend& b, std::size_t stride, std::size_t recovery_every,
                  std::size_t erase_places) {
  const History h = build_history(b, 10);
  Outcome total;
  for (const int k : {2, 4, 8}) {
    const Outcome o =
        exhaustive_cuts(b, h.images[k], k > 0 ? &h.sets[k - 1] : nullptr, h.sets[k], h.sets[k + 1],
                        stride, recovery_every, StoreGuards{}, erase_places);
    total.cuts += o.cuts;
    total.recovery_cuts += o.recovery_cuts;
    if (total.violations == 0u) {
      total.first_violation = o.first_violation;
    }
    total.violations += o.violations;
  }
  // The very first save, cut anywhere: blank or a torn record, never a set.
  const Outcome first = exhaustive_cuts(b, h.images[0], nullptr, h.sets[0], h.sets[1], stride,
                                        recovery_every, StoreGuards{}, erase_places);
  total.cuts += first.cuts;
  total.violations += first.violations;
  return total;
}

TEST(PowerCut, RamEveryBitOfARecordAnEraseAndTheRecoverySave) {
  RamBackend r;
  const Outcome o = every_bit(r.backend, 1u, 64u, 512u);
  EXPECT_EQ(o.violations, 0u) << o.first_violation;
  // 3 states x (2049 record bits + 513 erase places where the save erases) x 2 orders, + first.
  EXPECT_GT(o.cuts, 14000u);
  EXPECT_GT(o.recovery_cuts, 50000u);
  std::printf("ram: %zu cuts, %zu cuts in recovery saves\n", o.cuts, o.recovery_cuts);
}

TEST(PowerCut, FileStoreEveryByteOfARecordAndTheRecoverySave) {
  FileBackend f("bits");
  // Each operation of the file store is an fsync'd rename (milliseconds): every 16th byte of a
  // record, 32 places of an erase, recovery cuts (every 16th byte) after every 64th cut.
  const Outcome o = every_bit(f.backend, 128u, 64u, 32u);
  EXPECT_EQ(o.violations, 0u) << o.first_violation;
  EXPECT_GT(o.cuts, 200u);
  std::printf("file: %zu cuts, %zu cuts in recovery saves\n", o.cuts, o.recovery_cuts);
}

TEST(PowerCut, RamLongWorkloadWithAccumulatingDamage) {
  RamBackend r;
  const Outcome o = random_workload(r.backend, 1u, 20000, StoreGuards{}, 0.3, 0.05, 0.05);
  EXPECT_EQ(o.violations, 0u) << o.first_violation;
  EXPECT_GT(o.cuts, 2000u);
  EXPECT_GT(o.recovery_cuts, 1000u);
  EXPECT_GT(o.weak_programs, 500u);
  EXPECT_GT(o.lost_bits, 200u);
  std::printf(
      "ram workload: %zu saves, %zu cuts, %zu in recovery, %zu weak programs, %zu lost "
      "bits\n",
      o.saves, o.cuts, o.recovery_cuts, o.weak_programs, o.lost_bits);
}

TEST(PowerCut, FileStoreLongWorkloadWithAccumulatingDamage) {
  FileBackend f("workload");
  const Outcome o = random_workload(f.backend, 2u, 600, StoreGuards{}, 0.3, 0.05, 0.05);
  std::printf("file workload: %zu saves, %zu cuts, %zu in recovery, %zu weak, %zu lost bits\n",
              o.saves, o.cuts, o.recovery_cuts, o.weak_programs, o.lost_bits);
  EXPECT_EQ(o.violations, 0u) << o.first_violation;
  EXPECT_GT(o.cuts, 50u);
  EXPECT_GT(o.recovery_cuts, 30u);
}

// Each guard, switched off alone, lets the workload break a promise.
Outcome without(StoreGuards guards, double cut_rate, double weak_rate, double lost_rate) {
  RamBackend r;
  return random_workload(r.backend, 3u, 3000, guards, cut_rate, weak_rate, lost_rate);
}

TEST(PowerCutGuards, WithoutTheCrcALostBitOrATornRecordLoadsASetNeverSaved) {
  StoreGuards guards;
  guards.crc = false;
  const Outcome lost = without(guards, 0.0, 0.0, 0.5);
  EXPECT_GT(lost.violations, 0u);
  EXPECT_NE(lost.first_violation.find("never saved"), std::string::npos) << lost.first_violation;
  // And cuts alone: a record torn in its last value decodes whole without its CRC.
  RamBackend r;
  const History h = build_history(r.backend, 4);
  const Outcome torn = exhaustive_cuts(r.backend, h.images[2], &h.sets[1], h.sets[2], h.sets[3], 1u,
                                       1000000u, guards);
  EXPECT_GT(torn.violations, 0u);
  // The same damage with the CRC on: no violation (the control).
  EXPECT_EQ(without(StoreGuards{}, 0.0, 0.0, 0.5).violations, 0u);
}

TEST(PowerCutGuards, WithoutTheReadBackAWeakCellLosesASaveThatSaidOk) {
  StoreGuards guards;
  guards.read_back = false;
  const Outcome o = without(guards, 0.0, 0.2, 0.0);
  EXPECT_GT(o.violations, 0u);
  EXPECT_NE(o.first_violation.find("save said ok"), std::string::npos) << o.first_violation;
  EXPECT_EQ(without(StoreGuards{}, 0.0, 0.2, 0.0).violations, 0u);
}

TEST(PowerCutGuards, WithoutTheSequenceNumberAWrapLoadsAnOlderSet) {
  StoreGuards guards;
  guards.sequence = false;
  const Outcome o = without(guards, 0.0, 0.0, 0.0);
  EXPECT_GT(o.violations, 0u);
  EXPECT_NE(o.first_violation.find("save said ok"), std::string::npos) << o.first_violation;
  EXPECT_EQ(without(StoreGuards{}, 0.0, 0.0, 0.0).violations, 0u);
}

}  // namespace
}  // namespace odocal::test
