// The power-cut harness of tests/core/params against the STM32F4 flash driver on the model of the
// flash controller: cuts at every byte of a record, across a 16 KiB sector erase and in the
// recovery save, and a long workload whose damage accumulates. A reboot is a new driver over the
// same flash (the model keeps its memory, as the chip does).

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>

#include "../../core/params/power_cut_harness.hpp"
#include "flash_model.hpp"
#include "odocal/hal/stm32f4/flash_store.hpp"

namespace odocal::test {
namespace {

struct Stm32Backend {
  Stm32Backend() {
    reboot();
    backend = Backend{"stm32f4", &flash, [this] { reboot(); }};
  }
  void reboot() {
    driver = std::make_unique<ModelFlashStore>(model, clock, 1u, 2u);
    ASSERT_TRUE(driver->valid());
    flash.retarget(driver.get());
  }
  FlashModel model;
  SteppingClock clock;
  std::unique_ptr<ModelFlashStore> driver;
  FaultyFlash flash{nullptr};
  Backend backend;
};

TEST(FlashPowerCut, EveryByteOfARecordAnEraseAndTheRecoverySave) {
  Stm32Backend s;
  std::mt19937 rng(5);
  params::ParamSet sets[67];
  params::ParamSet current = params::default_params();
  for (auto& set : sets) {
    current = random_change(current, rng, 1u);
    set = current;
  }
  // 64 slots per 16 KiB sector: after 2 saves the next one programs a slot, after 64 it erases
  // the other sector first.
  params::ParamStore store(s.flash);
  Outcome total;
  std::vector<std::uint8_t> image;
  for (int k = 0; k < 65; ++k) {
    if (k == 2 || k == 64) {
      image = s.flash.snapshot();
      const Outcome o = exhaustive_cuts(s.backend, image, &sets[k - 1], sets[k], sets[k + 1], 8u,
                                        128u, params::StoreGuards{}, 64u);
      total.cuts += o.cuts;
      total.recovery_cuts += o.recovery_cuts;
      total.violations += o.violations;
      EXPECT_EQ(o.violations, 0u) << o.first_violation;
      s.flash.restore(image);
    }
    params::StoreInfo info;
    ASSERT_EQ(store.save(sets[k], info), params::StoreResult::ok) << k;
  }
  std::printf("stm32f4: %zu cuts, %zu cuts in recovery saves\n", total.cuts, total.recovery_cuts);
  EXPECT_GT(total.cuts, 1000u);
  EXPECT_GT(total.recovery_cuts, 200u);
  EXPECT_EQ(s.model.violations(), 0u);      // the driver kept the controller's rules throughout
  EXPECT_EQ(s.model.raise_attempts(), 0u);  // and never asked flash for a 0 -> 1 change
}

TEST(FlashPowerCut, LongWorkloadWithAccumulatingDamage) {
  Stm32Backend s;
  const Outcome o = random_workload(s.backend, 9u, 1500, params::StoreGuards{}, 0.3, 0.05, 0.05);
  EXPECT_EQ(o.violations, 0u) << o.first_violation;
  std::printf("stm32f4 workload: %zu saves, %zu cuts, %zu in recovery, %zu weak, %zu lost bits\n",
              o.saves, o.cuts, o.recovery_cuts, o.weak_programs, o.lost_bits);
  EXPECT_GT(o.cuts, 100u);
  EXPECT_GT(o.recovery_cuts, 50u);
  EXPECT_GT(o.weak_programs, 30u);
  EXPECT_EQ(s.model.violations(), 0u);
  EXPECT_EQ(s.model.raise_attempts(), 0u);
}

}  // namespace
}  // namespace odocal::test
