// The console's motion commands and what they refuse while the robot moves (odom, run, drive,
// stop, faults, status), the guided UMBmark, and the odom stream.

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

TEST(Console, OdomReportsThePoseAndResetZeroesIt) {
  auto rig = make_rig();
  const std::string line = rig->reply("odom");
  EXPECT_TRUE(std::regex_match(
      line,
      std::regex(
          R"(ok x_mm=-?[0-9]+\.[0-9]{3} y_mm=-?[0-9]+\.[0-9]{3} theta_deg=-?[0-9]+\.[0-9]{3})")))
      << line;
  // Turn the left wheel forward by feeding its decoder one revolution of edges (x4 quadrature).
  const std::uint8_t sequence[4][2] = {{1, 0}, {1, 1}, {0, 1}, {0, 0}};
  rig->tick(2);  // the first ticks take the encoder baseline
  rig->loop.left_decoder().reset(false, false);
  for (int i = 0; i < 1440; ++i) {
    rig->loop.left_decoder().on_edge(sequence[i % 4][0] != 0, sequence[i % 4][1] != 0,
                                     rig->now_us + static_cast<std::uint32_t>(i));
  }
  rig->tick(3);
  const std::string moved = rig->reply("odom");
  // One revolution of a 60 mm wheel: the centre moves pi*60/2 along an arc of the left wheel
  // about the right one (b = 150 mm), so the robot has moved and turned right.
  const double x = number(value_of(moved, "x_mm"));
  const double theta = number(value_of(moved, "theta_deg"));
  const double arc_mm = 3.14159265358979 * 60.0;  // left wheel travel
  const double turn_deg = -arc_mm / 150.0 * 180.0 / 3.14159265358979;
  EXPECT_NEAR(std::fabs(theta), std::fabs(turn_deg), 0.5) << moved;
  EXPECT_GT(std::fabs(x), 10.0) << moved;
  EXPECT_EQ(rig->reply("odom reset"), "ok x_mm=0.000 y_mm=0.000 theta_deg=0.000");
  rig->tick(2);
  EXPECT_EQ(rig->reply("odom"), "ok x_mm=0.000 y_mm=0.000 theta_deg=0.000");
}

TEST(Console, RunStartsAPathWithoutBlockingAndStatusReportsIt) {
  auto rig = make_rig();
  const std::string started = rig->reply("run umbmark-cw 4");
  EXPECT_EQ(value_of(started, "path"), "umbmark-cw") << started;
  EXPECT_EQ(value_of(started, "segments"), "8");
  rig->tick(5);
  const std::string status = rig->reply("status");
  EXPECT_EQ(value_of(status, "mode"), "path") << status;
  EXPECT_EQ(value_of(status, "path"), "umbmark-cw");
  EXPECT_EQ(value_of(status, "faults"), "none");
  for (const char* key : {"segment", "ticks", "tick_us_avg", "tick_us_max", "illegal_l",
                          "illegal_r", "stream_dropped", "rx_dropped", "unsaved"}) {
    EXPECT_NE(value_of(status, key), "") << key << " missing from " << status;
  }
  EXPECT_EQ(error_code(rig->reply("run line 1")), "busy");  // one path at a time
  EXPECT_EQ(rig->reply("stop"), "ok mode=idle");
  rig->tick(2);
  EXPECT_EQ(value_of(rig->reply("status"), "mode"), "idle");
}

TEST(Console, TickTimingIsReported) {
  auto rig = make_rig();
  rig->loop.note_tick_duration_us(12.0f);
  rig->loop.note_tick_duration_us(30.0f);
  const std::string status = rig->reply("status");
  EXPECT_NEAR(number(value_of(status, "tick_us_max")), 30.0, 1e-3);
  EXPECT_GT(number(value_of(status, "tick_us_avg")), 0.0);
}

TEST(Console, SetDuringARunningPathIsRefusedAndWorksAfterStop) {
  auto rig = make_rig();
  ASSERT_EQ(value_of(rig->reply("run line 2"), "path"), "line");
  expect_refused_without_change(*rig, "set c_l 1.01", "busy");  // before the loop's next tick
  rig->tick(10);
  ASSERT_EQ(value_of(rig->reply("status"), "mode"), "path");
  expect_refused_without_change(*rig, "set c_l 1.01", "busy");
  expect_refused_without_change(*rig, "set kp 0.1", "busy");
  expect_refused_without_change(*rig, "defaults", "busy");
  expect_refused_without_change(*rig, "load", "busy");
  expect_refused_without_change(*rig, "save", "busy");
  expect_refused_without_change(*rig, "odom reset", "busy");
  EXPECT_EQ(rig->reply("get c_l"), "ok c_l=1.000000");
  EXPECT_EQ(rig->reply("stop"), "ok mode=idle");
  EXPECT_EQ(rig->reply("set c_l 1.01"), "ok c_l=1.010000");  // even before the next tick
  rig->tick(2);
  EXPECT_FLOAT_EQ(rig->loop.config().c_l, 1.01f);
}

TEST(Console, SetWhileDrivingIsAllowedButSaveWaits) {
  auto rig = make_rig();
  EXPECT_EQ(rig->reply("drive 0.1 0 1000"), "ok v_mps=0.100 w_radps=0.000 ms=1000");
  rig->tick(5);
  EXPECT_EQ(value_of(rig->reply("status"), "mode"), "drive");
  EXPECT_EQ(rig->reply("set kp 0.08"), "ok kp=0.080000");  // live gain tuning
  expect_refused_without_change(*rig, "save", "busy");
  rig->reply("stop");
  rig->tick(2);
  EXPECT_EQ(value_of(rig->reply("save"), "sequence"), "1");
}

TEST(Console, FaultsRefuseMotionUntilStop) {
  auto rig = make_rig();
  // More illegal transitions (both channels at once) than max_illegal trips the encoder fault.
  rig->tick(2);  // the first ticks take the encoder baseline
  for (int i = 0; i < 40; ++i) {
    rig->loop.left_decoder().on_edge(i % 2 == 0, i % 2 == 0, rig->now_us);
  }
  rig->tick(3);
  const std::string status = rig->reply("status");
  EXPECT_EQ(value_of(status, "faults"), "encoder_left") << status;
  EXPECT_GE(number(value_of(status, "illegal_l")), 17.0);
  expect_refused_without_change(*rig, "run line 1", "fault");
  expect_refused_without_change(*rig, "drive 0.1 0", "fault");
  EXPECT_EQ(rig->reply("stop"), "ok mode=idle");
  rig->tick(2);
  EXPECT_EQ(value_of(rig->reply("status"), "faults"), "none");
  EXPECT_EQ(value_of(rig->reply("run line 1"), "path"), "line");
}

TEST(Console, GuidedUmbmarkSolvesAppliesAndRecordsProvenance) {
  RigFlash flash;
  auto rig = make_rig(Rig::quiet(), &flash);
  // A robot whose right wheel is 0.4 % larger and whose wheelbase is 2 % wider than told:
  // its return errors from the exact square geometry (no measurement noise).
  const double e_d = 1.004;
  const double e_b = 1.02;
  const double side_mm = 4000.0;
  const calib::ReturnError cw = calib::square_return_error(side_mm, 150.0, e_d, e_b, true);
  const calib::ReturnError ccw = calib::square_return_error(side_mm, 150.0, e_d, e_b, false);
  EXPECT_EQ(rig->reply("umbmark side 4"), "ok side_mm=4000.000");
  for (int run = 0; run < 5; ++run) {
    const double jitter = run % 2 == 0 ? 0.5 : -0.5;  // scatter that averages out
    std::ostringstream a, b;
    a.precision(10);
    b.precision(10);
    a << "umbmark add cw " << cw.x_mm + (run == 4 ? 0.0 : jitter) << " " << cw.y_mm;
    b << "umbmark add ccw " << ccw.x_mm + (run == 4 ? 0.0 : jitter) << " " << ccw.y_mm;
    EXPECT_EQ(value_of(rig->reply(a.str()), "cw"), std::to_string(run + 1));
    EXPECT_EQ(value_of(rig->reply(b.str()), "ccw"), std::to_string(run + 1));
  }
  const std::string solved = rig->reply("umbmark solve exact");
  ASSERT_EQ(solved.rfind("ok ", 0), 0u) << solved;
  EXPECT_NEAR(number(value_of(solved, "e_d")), e_d, 1e-5) << solved;
  EXPECT_NEAR(number(value_of(solved, "e_b")), e_b, 1e-5) << solved;
  EXPECT_EQ(value_of(solved, "runs"), "10");
  // DESIGN: c_L = 2/(E_d + 1), c_R = 2/(1/E_d + 1); b_new = E_b * b.
  const std::string applied = rig->reply("umbmark apply 1700000000");
  ASSERT_EQ(applied.rfind("ok ", 0), 0u) << applied;
  EXPECT_NEAR(number(value_of(applied, "c_l")), 2.0 / (e_d + 1.0), 2e-5);
  EXPECT_NEAR(number(value_of(applied, "c_r")), 2.0 / (1.0 / e_d + 1.0), 2e-5);
  EXPECT_NEAR(number(value_of(applied, "wheelbase_mm")), e_b * 150.0, 2e-3);
  EXPECT_FLOAT_EQ(rig->loop.config().c_l, rig->console.params().get(params::ParamId::c_l));
  const std::string provenance = rig->reply("provenance");
  EXPECT_EQ(value_of(provenance, "wheel_method"), "umbmark-exact");
  EXPECT_EQ(value_of(provenance, "wheel_runs"), "10");
  EXPECT_EQ(value_of(provenance, "wheel_date"), "1700000000");
  EXPECT_EQ(value_of(provenance, "lateral_method"), "defaults");
  // Applying clears the runs: the same result cannot be applied twice.
  EXPECT_EQ(error_code(rig->reply("umbmark apply")), "not_solved");
  rig->reply("save");
  auto rebooted = make_rig(Rig::quiet(), &flash);
  EXPECT_EQ(rebooted->reply("provenance"), provenance);
  // A manual set of a wheel factor says so.
  rebooted->reply("set c_l 1");
  EXPECT_EQ(value_of(rebooted->reply("provenance"), "wheel_method"), "manual");
}

TEST(Console, UmbmarkRefusals) {
  auto rig = make_rig();
  rig->reply("umbmark add cw 10 10");
  EXPECT_EQ(error_code(rig->reply("umbmark solve")), "umbmark_failed");  // too few runs
  for (int i = 1; i < 16; ++i)
    rig->reply("umbmark add cw 10 10");
  expect_refused_without_change(*rig, "umbmark add cw 1 1", "umbmark_full");
  EXPECT_EQ(rig->reply("umbmark add ccw 1 1"), "ok cw=16 ccw=1");
  EXPECT_EQ(rig->reply("umbmark clear"), "ok cw=0 ccw=0");
  expect_refused_without_change(*rig, "umbmark add cw 1", "wrong_arity");
  expect_refused_without_change(*rig, "umbmark add cw x 1", "bad_number");
  expect_refused_without_change(*rig, "umbmark add cw 1 1e7", "out_of_range");
  expect_refused_without_change(*rig, "umbmark", "wrong_arity");
}

TEST(Console, StreamPrintsOdomLinesAtTheRequestedRate) {
  auto rig = make_rig();
  EXPECT_EQ(rig->reply("stream odom 50"), "ok stream=odom hz=50.000");
  const std::size_t mark = rig->stream.output_size;
  for (int i = 0; i < 10000; ++i) {  // one second in 100 µs polls
    rig->now_us += 100;
    rig->console.poll(rig->now_us);
  }
  int stream_lines = 0;
  for (const auto& line : rig->split_lines(mark)) {
    ASSERT_EQ(line.rfind("# odom t_ms=", 0), 0u) << line;
    EXPECT_NE(value_of(line, "x_mm"), "");
    ++stream_lines;
  }
  EXPECT_NEAR(stream_lines, 50, 1);
  EXPECT_EQ(rig->reply("stream off"), "ok stream=off");
  const std::size_t after = rig->stream.output_size;
  for (int i = 0; i < 1000; ++i) {
    rig->now_us += 1000;
    rig->console.poll(rig->now_us);
  }
  EXPECT_EQ(rig->stream.output_size, after);
}

}  // namespace
}  // namespace odocal::test
