// `selftest` on the console (docs/console.md): refused while the robot moves, only `stop` is
// taken while it runs (and ends it), and a robot whose wheels never count is told so. The
// faults of a miswired robot are in tests/host_sim/odocal_sim/odocal_sim_selftest_test.cpp
// (odocal-sim).

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "console_rig.hpp"

namespace odocal::test {
namespace {

std::unique_ptr<Rig> started_rig() {
  auto rig = std::make_unique<Rig>();
  (void)rig->console.start(rig->now_us);
  return rig;
}

/// Types `line` and polls a few times with ticks in between (no waiting for the self-test).
std::vector<std::string> type(Rig& rig, const std::string& line) {
  const std::size_t mark = rig.stream.output_size;
  rig.stream.type(line + "\n");
  for (int i = 0; i < 5; ++i) {
    rig.console.poll(rig.now_us);
    rig.tick(1);
  }
  return rig.split_lines(mark);
}

TEST(ConsoleSelftest, RefusedWhileTheRobotMoves) {
  auto rig = started_rig();
  ASSERT_EQ(rig->reply("drive 0.1 0").rfind("ok", 0), 0u);
  rig->tick(2);
  EXPECT_EQ(rig->reply("selftest").rfind("err busy", 0), 0u);
}

TEST(ConsoleSelftest, OnlyStopIsTakenWhileItRunsAndStopEndsItSafely) {
  auto rig = started_rig();
  EXPECT_TRUE(type(*rig, "selftest").empty());  // the reply comes when it is done
  EXPECT_TRUE(rig->console.selftest_running());
  const auto refused = type(*rig, "status");
  ASSERT_EQ(refused.size(), 1u);
  EXPECT_EQ(refused[0].rfind("err busy selftest running", 0), 0u) << refused[0];
  const auto stopped = type(*rig, "stop");
  ASSERT_EQ(stopped.size(), 2u);
  EXPECT_EQ(stopped[0].rfind("err busy selftest ended by stop", 0), 0u) << stopped[0];
  EXPECT_EQ(stopped[1], "ok mode=idle");
  rig->tick(2);
  EXPECT_EQ(rig->reply("status").rfind("ok mode=idle", 0), 0u);
  EXPECT_EQ(rig->pwm_left.duty, 0.0f);
}

TEST(ConsoleSelftest, WheelsThatNeverCountAreStillAndTheMotorsEndReleased) {
  // The rig's motors are fakes: no encoder edge ever comes.
  auto rig = started_rig();
  const std::size_t mark = rig->stream.output_size;
  rig->stream.type("selftest\n");
  for (int i = 0; i < 5000 && (!rig->stream.drained() || i < 5 || rig->console.selftest_running());
       ++i) {
    rig->console.poll(rig->now_us);
    rig->tick(1);
  }
  std::string reply;
  for (const auto& line : rig->split_lines(mark)) {
    if (line.rfind("ok", 0) == 0u || line.rfind("err", 0) == 0u) {
      reply = line;
    }
  }
  EXPECT_EQ(reply.rfind("ok faults=left_still,right_still ll=0 lr=0 rl=0 rr=0", 0), 0u) << reply;
  rig->tick(5);
  EXPECT_EQ(rig->pwm_left.duty, 0.0f);
  EXPECT_EQ(rig->pwm_right.duty, 0.0f);
}

}  // namespace
}  // namespace odocal::test
