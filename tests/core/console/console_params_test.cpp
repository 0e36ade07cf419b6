// The console's parameters and store (params, get, set, save, load, defaults, the banner) and a
// target's own options (status pairs, defaults).

#include "odocal/console/console.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <regex>
#include <set>
#include <sstream>

#include "alloc_counter.hpp"
#include "console_rig.hpp"
#include "odocal/calib/umbmark.hpp"
#include "odocal/console/version.hpp"
#include "odocal/params/crc32.hpp"

namespace odocal::test {
namespace {

using console::ConsoleOptions;
using console::EchoMode;

std::size_t target_pairs(void* context, char* out, std::size_t capacity) {
  const char* text = static_cast<const char*>(context);
  std::size_t n = 0;
  while (text[n] != '\0' && n < capacity) {
    out[n] = text[n];
    ++n;
  }
  return n;
}

TEST(Console, ParamsListsValueUnitRangeOfEveryParameter) {
  auto rig = make_rig();
  const auto lines = rig->send("params");
  ASSERT_EQ(lines.size(), params::param_count + 1);
  for (std::size_t i = 0; i < params::param_count; ++i) {
    const auto id = static_cast<params::ParamId>(i);
    const params::ParamInfo& info = params::param_info(id);
    const std::string& line = lines[i];
    SCOPED_TRACE(line);
    ASSERT_EQ(line.rfind(std::string("# ") + info.name + "=", 0), 0u);
    EXPECT_NEAR(number(value_of(line.substr(2), info.name)),
                static_cast<double>(params::default_value(id)), kPrinted);
    EXPECT_EQ(value_of(line, "unit"), info.unit);
    EXPECT_NEAR(number(value_of(line, "min")), static_cast<double>(info.min), kPrinted);
    EXPECT_NEAR(number(value_of(line, "max")), static_cast<double>(info.max), kPrinted);
  }
  EXPECT_EQ(lines.back(), "ok params=23 unsaved=0");
}

TEST(Console, GetShowsTheDefaults) {
  auto rig = make_rig();
  EXPECT_EQ(rig->reply("get c_l"), "ok c_l=1.000000");
  EXPECT_EQ(rig->reply("get wheelbase_mm"), "ok wheelbase_mm=150.000000");
  for (std::size_t i = 0; i < params::param_count; ++i) {
    const auto id = static_cast<params::ParamId>(i);
    const std::string name = params::param_info(id).name;
    const std::string line = rig->reply("get " + name);
    EXPECT_NEAR(number(value_of(line, name)), static_cast<double>(params::default_value(id)),
                kPrinted)
        << line;
  }
}

TEST(Console, SetChangesTheParameterAndTheDriveConfiguration) {
  auto rig = make_rig();
  EXPECT_EQ(rig->reply("set c_l 0.995"), "ok c_l=0.995000");
  EXPECT_EQ(rig->reply("get c_l"), "ok c_l=0.995000");
  EXPECT_FLOAT_EQ(rig->loop.config().c_l, 0.995f);
  EXPECT_EQ(rig->reply("set max_illegal 32"), "ok max_illegal=32.000000");
  EXPECT_EQ(rig->loop.config().max_illegal, 32u);
  EXPECT_EQ(rig->reply("set kp 5e-2"), "ok kp=0.050000");
  EXPECT_TRUE(rig->console.unsaved());
  // Range ends are accepted (closed ranges).
  EXPECT_EQ(rig->reply("set c_r 2"), "ok c_r=2.000000");
  EXPECT_EQ(rig->reply("set c_r 0.5"), "ok c_r=0.500000");
}

TEST(Console, SaveThenReloadAfterARestart) {
  RigFlash flash;
  {
    auto rig = make_rig(Rig::quiet(), &flash);
    EXPECT_EQ(rig->reply("set c_l 0.99"), "ok c_l=0.990000");
    EXPECT_EQ(rig->reply("set wheelbase_mm 152.5"), "ok wheelbase_mm=152.500000");
    const std::string saved = rig->reply("save");
    EXPECT_EQ(value_of(saved, "sequence"), "1") << saved;
    EXPECT_FALSE(rig->console.unsaved());
    EXPECT_EQ(rig->reply("set c_l 1.2"), "ok c_l=1.200000");
    const std::string loaded = rig->reply("load");
    EXPECT_EQ(loaded, "ok sequence=1 version=2 migrated=0");
    EXPECT_EQ(rig->reply("get c_l"), "ok c_l=0.990000");
    EXPECT_FLOAT_EQ(rig->loop.config().c_l, 0.99f);
  }
  // Restart: a new console and loop over the same flash come up with the saved values.
  ConsoleOptions with_banner = Rig::quiet();
  with_banner.banner = true;
  auto rebooted = std::make_unique<Rig>(with_banner, &flash);
  EXPECT_EQ(rebooted->console.start(rebooted->now_us), params::StoreResult::ok);
  rebooted->settle();
  EXPECT_TRUE(rebooted->split_lines(0).empty());  // the banner waits for the first command
  const auto banner = rebooted->send("get c_l");
  ASSERT_EQ(banner.size(), 2u);
  EXPECT_EQ(banner[0].rfind("# odocal ", 0), 0u);
  EXPECT_EQ(value_of(banner[0], "params"), "loaded");
  EXPECT_EQ(banner[1], "ok c_l=0.990000");
  EXPECT_EQ(rebooted->reply("get wheelbase_mm"), "ok wheelbase_mm=152.500000");
  EXPECT_FLOAT_EQ(rebooted->loop.config().wheelbase_mm, 152.5f);
}

TEST(Console, BannerSaysWhyTheDefaultsAreInForce) {
  ConsoleOptions with_banner = Rig::quiet();
  with_banner.banner = true;
  auto rig = std::make_unique<Rig>(with_banner);
  EXPECT_EQ(rig->console.start(rig->now_us), params::StoreResult::empty);
  rig->settle();
  EXPECT_TRUE(rig->split_lines(0).empty());
  const auto lines = rig->send("version");
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], std::string("# odocal ") + console::project_version +
                          " console params=defaults store=empty");
  EXPECT_EQ(lines[1].rfind("ok name=odocal ", 0), 0u) << lines[1];
  // Once: the next command gets its reply alone.
  EXPECT_EQ(rig->send("version").size(), 1u);
}

TEST(Console, TheBannerRidesOnTheFirstOdocalReplyAndNeverFollowsABridgeLine) {
  ConsoleOptions with_banner = Rig::quiet();
  with_banner.banner = true;
  with_banner.banner_note = " board=test";
  {
    // A person (or an odocal host) first: the start-up line, with the target's note, comes
    // before the first reply, also when that line is refused.
    auto rig = std::make_unique<Rig>(with_banner);
    (void)rig->console.start(rig->now_us);
    const auto lines = rig->send("frobnicate");
    ASSERT_EQ(lines.size(), 2u);
    EXPECT_EQ(lines[0], std::string("# odocal ") + console::project_version +
                            " console params=defaults store=empty board=test");
    EXPECT_EQ(error_code(lines[1]), "unknown_command");
  }
  // A ROSArduinoBridge client first: never a banner, not even at a later odocal line.
  auto rig = std::make_unique<Rig>(with_banner);
  (void)rig->console.start(rig->now_us);
  EXPECT_EQ(rig->send("e"), std::vector<std::string>{"0 0"});
  EXPECT_EQ(rig->send("get c_l"), std::vector<std::string>{"ok c_l=1.000000"});
}

TEST(Console, DefaultsRestoreEveryValueButAreNotSavedUntilSave) {
  RigFlash flash;
  {
    auto rig = make_rig(Rig::quiet(), &flash);
    rig->reply("set kp 0.2");
    rig->reply("set c_r 1.1");
    rig->reply("save");
    EXPECT_EQ(rig->reply("defaults"), "ok params=23 unsaved=1");
    EXPECT_EQ(rig->reply("get kp"), "ok kp=0.050000");
    EXPECT_EQ(rig->reply("get c_r"), "ok c_r=1.000000");
    EXPECT_TRUE(params::same(rig->console.params(), params::default_params()));
  }
  auto rebooted = make_rig(Rig::quiet(), &flash);
  EXPECT_EQ(rebooted->reply("get kp"), "ok kp=0.200000");
}

// A robot whose store has never held a set starts on its defaults: after `defaults` a restart
// brings the same values, so nothing is unsaved (and `status` says so); once it has saved, the
// defaults differ from what a restart brings until they are saved.
TEST(Console, DefaultsOnARobotThatNeverSavedLeaveNothingUnsaved) {
  RigFlash flash;
  auto rig = make_rig(Rig::quiet(), &flash);
  EXPECT_EQ(rig->reply("set c_r 1.1"), "ok c_r=1.100000");
  EXPECT_EQ(value_of(rig->reply("status"), "unsaved"), "1");
  EXPECT_EQ(rig->reply("defaults"), "ok params=23 unsaved=0");
  EXPECT_EQ(value_of(rig->reply("status"), "unsaved"), "0");
  EXPECT_EQ(value_of(rig->reply("status"), "store"), "empty");
  EXPECT_TRUE(params::same(rig->console.params(), params::default_params()));
  EXPECT_EQ(rig->reply("save").rfind("ok ", 0), 0u);
  EXPECT_EQ(rig->reply("defaults"), "ok params=23 unsaved=1");
  EXPECT_EQ(value_of(rig->reply("status"), "unsaved"), "1");
}

TEST(Console, StoreErrorsAreReported) {
  auto rig = make_rig();
  rig->flash.cut_after(0);
  expect_refused_without_change(*rig, "save", "store_error");
  EXPECT_FALSE(rig->console.unsaved());
  rig->flash.power_on();
  // A record from a newer firmware: load refuses it by version.
  std::vector<std::uint8_t> bytes(params::record_slot_size, 0xFF);
  const std::uint8_t header[] = {'O', 'D', 'C', 'L', 9, 0, 20, 0, 5, 0,
                                 0,   0,   0,   0,   0, 0, 1,  2, 3, 4};
  std::memcpy(bytes.data(), header, sizeof header);
  const std::uint32_t crc = params::crc32(bytes.data(), 20);
  for (int i = 0; i < 4; ++i)
    bytes[20 + i] = static_cast<std::uint8_t>(crc >> (8 * i));
  ASSERT_EQ(rig->flash.program(0, bytes.data(), bytes.size()), hal::StoreStatus::ok);
  rig->reply("set c_l 1.1");
  const std::string line = rig->reply("load");
  EXPECT_EQ(line, "err store_version record format 9 is newer than this firmware's 2");
  EXPECT_EQ(rig->reply("get c_l"), "ok c_l=1.100000");
}

TEST(Console, StatusCarriesTheTargetsOwnPairs) {
  console::ConsoleOptions options = Rig::quiet();
  static const char kPairs[] = " tick_rt=1 pwm=sysfs";
  options.status_pairs = target_pairs;
  options.status_context = const_cast<char*>(kPairs);
  Rig rig(options);
  (void)rig.console.start(rig.now_us);
  const std::string line = rig.reply("status");
  EXPECT_EQ(line.substr(0, 8), "ok mode=");
  EXPECT_EQ(line.substr(line.size() - (sizeof(kPairs) - 1)), kPairs);
}

TEST(Console, StatusPairsStopAtTheFirstNonPrintableByte) {
  console::ConsoleOptions options = Rig::quiet();
  static const char kPairs[] = " a=1\n err x";
  options.status_pairs = target_pairs;
  options.status_context = const_cast<char*>(kPairs);
  Rig rig(options);
  (void)rig.console.start(rig.now_us);
  const auto lines = rig.send("status");
  ASSERT_EQ(lines.size(), 1u);  // the newline in the target's text did not split the reply
  EXPECT_EQ(lines[0].substr(lines[0].size() - 4), " a=1");
}

TEST(Console, ATargetsOwnDefaultsAreUsedWithAnEmptyStoreAndRestoredByDefaults) {
  params::ParamSet mine = params::default_params();
  drive::DriveConfig told = params::to_drive_config(mine);
  told.wheel_diameter_mm = 72.5f;
  told.wheelbase_mm = 201.25f;
  params::from_drive_config(told, mine);
  console::ConsoleOptions options = Rig::quiet();
  options.defaults = &mine;
  Rig rig(options);
  (void)rig.console.start(rig.now_us);
  EXPECT_EQ(rig.reply("get wheel_diameter_mm"), "ok wheel_diameter_mm=72.500000");
  EXPECT_EQ(rig.reply("set wheelbase_mm 180"), "ok wheelbase_mm=180.000000");
  EXPECT_EQ(rig.reply("defaults").rfind("ok", 0), 0u);
  EXPECT_EQ(rig.reply("get wheelbase_mm"), "ok wheelbase_mm=201.250000");
  rig.tick(2);
  EXPECT_FLOAT_EQ(rig.loop.config().wheelbase_mm, 201.25f);
}

TEST(Console, InvalidTargetDefaultsFallBackToTheBuiltInOnes) {
  params::ParamSet bad = params::default_params();
  drive::DriveConfig told = params::to_drive_config(bad);
  told.wheel_diameter_mm = 900.0f;  // in range alone, but wider than 4x the wheelbase allows
  params::from_drive_config(told, bad);
  console::ConsoleOptions options = Rig::quiet();
  options.defaults = &bad;
  Rig rig(options);
  (void)rig.console.start(rig.now_us);
  EXPECT_EQ(rig.reply("get wheel_diameter_mm"), "ok wheel_diameter_mm=60.000000");
}

}  // namespace
}  // namespace odocal::test
