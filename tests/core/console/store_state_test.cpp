// A store whose every record is damaged is named as such (banner, `load`, `status`), kept for
// inspection until the next `save`, and told apart from a new, empty store.

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "console_rig.hpp"
#include "odocal/console/version.hpp"

namespace odocal::test {
namespace {

std::string pair_value(const std::string& line, const std::string& key) {
  const std::string needle = " " + key + "=";
  const std::size_t at = line.find(needle);
  if (at == std::string::npos) {
    return "(missing)";
  }
  const std::size_t start = at + needle.size();
  return line.substr(start, line.find(' ', start) - start);
}

// Two saved records, then one bit cleared inside each (a flash fault, not a power cut).
void damage_every_record(RigFlash& flash) {
  for (std::size_t slot = 0; slot < 2; ++slot) {
    std::uint8_t* byte = flash.memory() + slot * params::record_slot_size + 100;
    while (*byte == 0u) {
      ++byte;  // flash can lose a 1 only where there is one
    }
    *byte &= static_cast<std::uint8_t>(*byte - 1u);  // clears the lowest set bit
  }
}

TEST(ConsoleStore, EveryRecordDamagedIsCorruptNotEmpty) {
  RigFlash flash;
  {
    Rig rig(Rig::quiet(), &flash);
    (void)rig.console.start(rig.now_us);
    ASSERT_EQ(rig.reply("set c_l 0.99"), "ok c_l=0.990000");
    ASSERT_EQ(pair_value(rig.reply("save"), "sequence"), "1");
    ASSERT_EQ(rig.reply("set c_l 0.98"), "ok c_l=0.980000");
    ASSERT_EQ(pair_value(rig.reply("save"), "sequence"), "2");
  }
  damage_every_record(flash);
  const std::vector<std::uint8_t> damaged(flash.memory(), flash.memory() + 4096);

  console::ConsoleOptions with_banner = Rig::quiet();
  with_banner.banner = true;
  Rig rig(with_banner, &flash);
  EXPECT_EQ(rig.console.start(rig.now_us), params::StoreResult::corrupt);
  rig.settle();
  const auto banner = rig.send("get c_l");  // the banner comes before the first reply
  ASSERT_EQ(banner.size(), 2u);
  EXPECT_EQ(banner[0], std::string("# odocal ") + console::project_version +
                           " console params=defaults store=corrupt");
  // The defaults are in force, and `status` says why for as long as it lasts.
  EXPECT_EQ(banner[1], "ok c_l=1.000000");
  EXPECT_EQ(pair_value(rig.reply("status"), "store"), "corrupt");
  // `load` is refused with its own code, naming how many slots are damaged; nothing changes.
  EXPECT_EQ(rig.reply("set c_l 1.01"), "ok c_l=1.010000");
  const std::string load = rig.reply("load");
  EXPECT_EQ(load.rfind("err store_corrupt every stored record is damaged (2 slots)", 0), 0u)
      << load;
  EXPECT_EQ(rig.reply("get c_l"), "ok c_l=1.010000");
  EXPECT_EQ(pair_value(rig.reply("status"), "unsaved"), "1");
  // Nothing was erased or written: the image is there to inspect until the next save.
  EXPECT_TRUE(std::equal(damaged.begin(), damaged.end(), flash.memory()));
  // A save starts again: the store is ok, and a reboot loads the new record.
  const std::string saved = rig.reply("save");
  EXPECT_EQ(saved.rfind("ok sequence=1 ", 0), 0u) << saved;
  EXPECT_EQ(pair_value(rig.reply("status"), "store"), "ok");
  EXPECT_EQ(rig.reply("load"), "ok sequence=1 version=2 migrated=0");
}

TEST(ConsoleStore, NewStoreIsEmptyAndStatusSaysSo) {
  auto rig = std::make_unique<Rig>();
  EXPECT_EQ(rig->console.start(rig->now_us), params::StoreResult::empty);
  EXPECT_EQ(pair_value(rig->reply("status"), "store"), "empty");
  EXPECT_EQ(rig->reply("load").rfind("err store_empty ", 0), 0u);
}

TEST(ConsoleStore, StoreCorruptIsDocumented) {
  const char* source = std::getenv("ODOCAL_SOURCE_DIR");
  ASSERT_NE(source, nullptr) << "run through ctest";
  std::ifstream file(std::string(source) + "/docs/console.md");
  std::stringstream text;
  text << file.rdbuf();
  EXPECT_NE(text.str().find("| `store_corrupt` |"), std::string::npos);
  EXPECT_NE(text.str().find("store=corrupt"), std::string::npos);
}

}  // namespace
}  // namespace odocal::test
