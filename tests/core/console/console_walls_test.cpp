// `walls`: the robot's wall sensors on its console (issue 48). Each present sensor's reflected
// light, ambient taken away, in the order of ConsoleOptions::wall_sensors; a robot with none
// refuses.

#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "console_rig.hpp"
#include "odocal/hal/wall_sensor.hpp"

namespace odocal::test {
namespace {

/// A wall sensor that reads `ambient` with its emitter off and `ambient + lit` with it on, and
/// counts its conversions.
class FakeWallSensor final : public hal::WallSensor {
 public:
  FakeWallSensor(std::uint16_t ambient, std::uint16_t lit) : ambient_(ambient), lit_(lit) {}
  bool emitter_on = false;
  int conversions = 0;

 private:
  void do_set_emitter(bool on) override { emitter_on = on; }
  std::uint16_t do_read_counts() override {
    ++conversions;
    return static_cast<std::uint16_t>(emitter_on ? ambient_ + lit_ : ambient_);
  }
  std::uint32_t do_settle_us() const override { return 0u; }
  void do_wait_settle() override {}

  std::uint16_t ambient_;
  std::uint16_t lit_;
};

console::ConsoleOptions with_walls(hal::WallSensor* left_front, hal::WallSensor* left_diagonal,
                                   hal::WallSensor* right_diagonal, hal::WallSensor* right_front) {
  console::ConsoleOptions options = Rig::quiet();
  options.wall_sensors = {left_front, left_diagonal, right_diagonal, right_front};
  return options;
}

TEST(ConsoleWalls, ReportsEachSensorsLitCountsInOrder) {
  FakeWallSensor left_front(100, 812), left_diagonal(90, 95), right_diagonal(120, 102),
      right_front(0, 790);
  auto rig = make_rig(with_walls(&left_front, &left_diagonal, &right_diagonal, &right_front));
  EXPECT_EQ(rig->reply("walls"),
            "ok left_front=812 left_diagonal=95 right_diagonal=102 right_front=790");
  // One dark and one lit conversion each, the emitters left off.
  for (const FakeWallSensor* sensor :
       {&left_front, &left_diagonal, &right_diagonal, &right_front}) {
    EXPECT_EQ(sensor->conversions, 2);
    EXPECT_FALSE(sensor->emitter_on);
  }
}

TEST(ConsoleWalls, LeavesOutAbsentSensors) {
  FakeWallSensor left_diagonal(100, 4095), right_front(100, 0);
  auto rig = make_rig(with_walls(nullptr, &left_diagonal, nullptr, &right_front));
  // A saturated receiver: full scale minus the ambient.
  EXPECT_EQ(rig->reply("walls"), "ok left_diagonal=3995 right_front=0");
}

TEST(ConsoleWalls, ARobotWithoutSensorsRefuses) {
  auto rig = make_rig();
  EXPECT_EQ(rig->reply("walls"), "err no_sensors this robot has no wall sensors");
  EXPECT_EQ(rig->console.counters().errors, 1u);
  EXPECT_EQ(error_code(rig->reply("walls now")), "wrong_arity");
}

TEST(ConsoleWalls, AnswersWhileTheRobotDrives) {
  FakeWallSensor front(50, 700);
  auto rig = make_rig(with_walls(&front, nullptr, nullptr, &front));
  ASSERT_EQ(rig->reply("drive 0.2 0 1000").rfind("ok", 0), 0u);
  rig->tick(20);
  EXPECT_EQ(rig->reply("walls"), "ok left_front=700 right_front=700");
  // A question: counted as one, and the drive goes on.
  EXPECT_EQ(rig->console.counters().questions, 1u);
  EXPECT_EQ(value_of(rig->reply("status"), "mode"), "drive");
}

}  // namespace
}  // namespace odocal::test
