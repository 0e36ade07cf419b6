// What a person at a terminal and a host logging runs see: echo from the first line typed, stream
// lines that never break the line being typed, the target's own defaults in `params`, a clipped
// `drive` that says so, and ranges that accept the documented bounds.

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "console_rig.hpp"
#include "odocal/console/text.hpp"

namespace odocal {
namespace {

using console::ConsoleOptions;
using console::EchoMode;
using test::Rig;
using test::value_of;

std::string output_since(const Rig& rig, std::size_t mark) {
  return std::string(rig.stream.output.data() + mark, rig.stream.output_size - mark);
}

ConsoleOptions automatic_echo() {
  ConsoleOptions options = Rig::quiet();
  options.echo = EchoMode::automatic;
  return options;
}

TEST(ConsoleTerminal, TheFirstLineTypedWithABareCrIsEchoedAndSoIsTheNext) {
  auto rig = std::make_unique<Rig>(automatic_echo());
  std::size_t mark = rig->stream.output_size;
  rig->stream.type("get c_l\r");  // Enter from picocom: a bare CR, nothing behind it
  rig->settle();
  EXPECT_EQ(output_since(*rig, mark), "get c_l\nok c_l=1.000000\n");
  EXPECT_TRUE(rig->console.echo_enabled());
  mark = rig->stream.output_size;
  rig->stream.type("get c_r\r");  // every character of the next line, the first included
  rig->settle();
  EXPECT_EQ(output_since(*rig, mark), "get c_r\nok c_r=1.000000\n");
}

TEST(ConsoleTerminal, ScriptedCrLfLinesStayUnechoed) {
  auto rig = std::make_unique<Rig>(automatic_echo());
  const std::size_t mark = rig->stream.output_size;
  rig->stream.type("get c_l\r\nget c_r\r\n");
  rig->settle();
  EXPECT_EQ(output_since(*rig, mark), "ok c_l=1.000000\nok c_r=1.000000\n");
  EXPECT_FALSE(rig->console.echo_enabled());
}

TEST(ConsoleTerminal, StreamLinesNeverLandInsideTheLineBeingTyped) {
  ConsoleOptions options = Rig::quiet();
  options.echo = EchoMode::on;
  auto rig = std::make_unique<Rig>(options);
  const auto started = rig->send("stream ticks 100");  // the echo, then the reply
  ASSERT_EQ(started.size(), 2u);
  EXPECT_EQ(started[1], "ok stream=ticks hz=100.000");
  const std::size_t mark = rig->stream.output_size;
  rig->stream.type("sta");  // typing, not finished
  for (int i = 0; i < 50; ++i) {
    rig->tick(1);
    rig->console.poll(rig->now_us);
  }
  const std::string out = output_since(*rig, mark);
  // Every stream line starts on a cleared line and the typed text is shown again after it.
  std::size_t streams = 0;
  for (std::size_t at = out.find("# ticks"); at != std::string::npos;
       at = out.find("# ticks", at + 1)) {
    ++streams;
    ASSERT_GE(at, 4u);
    EXPECT_EQ(out.substr(at - 4, 4), "\r\x1b[K") << "stream line " << streams;
    const std::size_t end = out.find('\n', at);
    ASSERT_NE(end, std::string::npos);
    EXPECT_EQ(out.substr(end + 1, 3), "sta") << "stream line " << streams;
  }
  EXPECT_GE(streams, 3u);
  rig->stream.type("tus\n");  // the command still completes as typed
  rig->settle();
  EXPECT_NE(rig->split_lines(mark).back().find("ok mode="), std::string::npos);
}

TEST(ConsoleTerminal, ParamsShowsTheTargetsOwnDefaults) {
  params::ParamSet own = params::default_params();
  own.set(params::ParamId::wheel_diameter_mm, 72.5f);
  ConsoleOptions options = Rig::quiet();
  options.defaults = &own;
  auto rig = std::make_unique<Rig>(options);
  rig->console.start(rig->now_us);
  bool seen = false;
  for (const auto& line : rig->send("params")) {
    if (line.rfind("# wheel_diameter_mm=", 0) == 0) {
      seen = true;
      EXPECT_EQ(value_of(line, "default"), "72.500000") << line;
    }
  }
  EXPECT_TRUE(seen);
  EXPECT_EQ(rig->reply("set wheel_diameter_mm 80"), "ok wheel_diameter_mm=80.000000");
  rig->reply("defaults");
  EXPECT_EQ(rig->reply("get wheel_diameter_mm"), "ok wheel_diameter_mm=72.500000");
}

TEST(ConsoleTerminal, ADriveBeyondTheWheelLimitSaysItIsClipped) {
  auto rig = std::make_unique<Rig>();
  // 0.2 m/s on 60 mm wheels is 6.67 rad/s per wheel: within max_wheel_radps (25).
  EXPECT_EQ(value_of(rig->reply("drive 0.2 0"), "clipped"), "");
  // 1.5 m/s is 50 rad/s: scaled by 25/50, curvature kept.
  const std::string line = rig->reply("drive 1.5 1");
  EXPECT_EQ(value_of(line, "clipped"), "1") << line;
  EXPECT_NEAR(std::stod(value_of(line, "v_clipped_mps")), 1.5 * 25.0 / (1.5 / 0.03 + 0.075 / 0.03),
              0.002)
      << line;
  EXPECT_NEAR(
      std::stod(value_of(line, "w_clipped_radps")) / std::stod(value_of(line, "v_clipped_mps")),
      1.0 / 1.5, 0.01);
}

TEST(ConsoleTerminal, TheDocumentedBoundsOfEveryParameterAreAccepted) {
  auto rig = std::make_unique<Rig>();
  EXPECT_EQ(rig->reply("set v_max_mps 0.001"), "ok v_max_mps=0.001000");
  EXPECT_EQ(rig->reply("set max_wheel_radps 0.1"), "ok max_wheel_radps=0.100000");
  EXPECT_EQ(rig->reply("set w_max_radps 0.01"), "ok w_max_radps=0.010000");
  EXPECT_EQ(test::error_code(rig->reply("set v_max_mps 0.000999")), "out_of_range");
  EXPECT_EQ(test::error_code(rig->reply("set c_l 2.0000001")), "out_of_range");
  // Whole numbers are judged as typed: 32.0000001 is no whole number, although the float
  // nearest to it is 32.
  EXPECT_EQ(test::error_code(rig->reply("set max_illegal 32.0000001")), "bad_number");
  EXPECT_EQ(rig->reply("set max_illegal 32.000"), "ok max_illegal=32.000000");
  EXPECT_EQ(test::error_code(rig->reply("drive 0.1 0 100.00001")), "bad_number");
}

TEST(ConsoleTerminal, HelpListsTheTrialAndLateralCommands) {
  auto rig = std::make_unique<Rig>();
  std::string all;
  for (const auto& line : rig->send("help")) {
    all += line + "\n";
  }
  for (const char* word : {"# trial [N]", "# trials", "# trials clear", "# stream ticks <hz>",
                           "# lateral add <x_mm> <y_mm>", "# lateral solve", "# lateral apply"}) {
    EXPECT_NE(all.find(word), std::string::npos) << word;
  }
}

TEST(ConsoleTerminal, TrialCommandsWithoutTrialsAnswerNoTrial) {
  auto rig = std::make_unique<Rig>();
  EXPECT_EQ(test::error_code(rig->reply("trial")), "no_trial");
  EXPECT_EQ(test::error_code(rig->reply("trial 1")), "no_trial");
  EXPECT_EQ(test::error_code(rig->reply("trial -1")), "bad_number");
  EXPECT_EQ(test::error_code(rig->reply("trials now")), "bad_argument");
  EXPECT_EQ(rig->reply("trials"), "ok trials=0");
  EXPECT_EQ(test::error_code(rig->reply("lateral add 1000 0")), "no_trial");
  EXPECT_EQ(test::error_code(rig->reply("lateral add 1000")), "wrong_arity");
  EXPECT_EQ(test::error_code(rig->reply("lateral add x 0")), "bad_number");
  EXPECT_EQ(test::error_code(rig->reply("lateral solve now")), "wrong_arity");
  EXPECT_EQ(test::error_code(rig->reply("lateral apply")), "not_solved");
  EXPECT_EQ(test::error_code(rig->reply("lateral redo")), "bad_argument");
  EXPECT_EQ(test::error_code(rig->reply("stream ticks 0")), "out_of_range");
  EXPECT_EQ(test::error_code(rig->reply("stream ticks")), "wrong_arity");
  EXPECT_EQ(test::error_code(rig->reply("stream ticks 50 sum")), "bad_argument");
  EXPECT_EQ(test::error_code(rig->reply("stream ticks 50 crc now")), "wrong_arity");
  EXPECT_EQ(test::error_code(rig->reply("stream ticks 0 crc")), "out_of_range");
}

// The check a `# ticks` line carries with `stream ticks <hz> crc`: CRC-16/CCITT-FALSE, whose
// standard check value (of "123456789") is 0x29B1; one flipped bit changes it.
TEST(ConsoleTerminal, TickLinesCarryTheirCrcWhenAskedFor) {
  EXPECT_EQ(odocal::console::crc16("123456789", 9u), 0x29B1u);
  EXPECT_NE(odocal::console::crc16("123456788", 9u), 0x29B1u);
  EXPECT_EQ(odocal::console::crc16("", 0u), 0xFFFFu);
  auto rig = std::make_unique<Rig>();
  EXPECT_EQ(rig->reply("stream ticks 100 crc"), "ok stream=ticks hz=100.000");
  const std::size_t mark = rig->stream.output_size;
  for (int i = 0; i < 35; ++i) {
    rig->tick(1);
    rig->console.poll(rig->now_us);
  }
  std::size_t checked = 0;
  for (const std::string& line : rig->split_lines(mark)) {
    if (line.rfind("# ticks t_ms=", 0) != 0u) {
      continue;
    }
    const std::size_t at = line.find(" crc=");
    ASSERT_NE(at, std::string::npos) << line;
    EXPECT_EQ(line.substr(at + 5), std::to_string(odocal::console::crc16(line.data(), at))) << line;
    ++checked;
  }
  EXPECT_EQ(checked, 3u);          // 35 ms at 100 Hz
  rig->reply("stream ticks 100");  // without: the contract's line
  const std::size_t plain_mark = rig->stream.output_size;
  for (int i = 0; i < 15; ++i) {
    rig->tick(1);
    rig->console.poll(rig->now_us);
  }
  const std::vector<std::string> plain = rig->split_lines(plain_mark);
  ASSERT_FALSE(plain.empty());
  EXPECT_EQ(plain.back().find(" crc="), std::string::npos) << plain.back();
}

}  // namespace
}  // namespace odocal

namespace odocal {
namespace {

TEST(ConsoleHostFactors, FitApplyAndLateralSetKeepTheirProvenance) {
  auto rig = std::make_unique<test::Rig>();
  rig->console.start(rig->now_us);
  EXPECT_EQ(rig->reply("fit apply 0.998 1.002 151.5 1700000000"),
            "ok c_l=0.998000 c_r=1.002000 wheelbase_mm=151.500000 wheelbase_arc_mm=0.000000 "
            "method=fit unsaved=1");
  EXPECT_EQ(rig->reply("lateral set 1.01 0.99"),
            "ok f_lat=1.010000 f_lon=0.990000 method=maddahi-bootstrap unsaved=1");
  const std::string provenance = rig->reply("provenance");
  EXPECT_EQ(test::value_of(provenance, "wheel_method"), "fit");
  EXPECT_EQ(test::value_of(provenance, "wheel_date"), "1700000000");
  EXPECT_EQ(test::value_of(provenance, "lateral_method"), "maddahi-bootstrap");
  // A refused line changes nothing: one value out of range, a bad date, a short line.
  for (const char* bad : {"fit apply 0.9 2.5 150", "fit apply 1 1 150 soon", "fit apply 1 1",
                          "fit do 1 1 150", "lateral set 1 0.1", "lateral set 1"}) {
    const params::ParamSet before = rig->console.params();
    EXPECT_EQ(rig->reply(bad).rfind("err ", 0), 0u) << bad;
    EXPECT_TRUE(params::same(before, rig->console.params())) << bad;
  }
  // Saved and reloaded, the methods stay (they are stored with the values).
  EXPECT_EQ(rig->reply("save").rfind("ok ", 0), 0u);
  EXPECT_EQ(rig->reply("defaults"), "ok params=23 unsaved=1");
  EXPECT_EQ(rig->reply("load").rfind("ok ", 0), 0u);
  EXPECT_EQ(test::value_of(rig->reply("provenance"), "wheel_method"), "fit");
}

// `fit apply` with the arc-wheelbase model's second wheelbase: `arc <mm>` after the rest; without
// it the arc wheelbase goes back to 0 (one wheelbase), as a one-wheelbase fit says.
TEST(ConsoleHostFactors, FitApplyTakesTheArcWheelbase) {
  auto rig = std::make_unique<test::Rig>();
  rig->console.start(rig->now_us);
  EXPECT_EQ(rig->reply("fit apply 0.998 1.002 150.6 1700000000 60 arc 152.1"),
            "ok c_l=0.998000 c_r=1.002000 wheelbase_mm=150.600006 wheelbase_arc_mm=152.100006 "
            "method=fit runs=60 unsaved=1");
  EXPECT_EQ(test::value_of(rig->reply("get wheelbase_arc_mm"), "wheelbase_arc_mm"), "152.100006");
  EXPECT_EQ(test::value_of(rig->reply("provenance"), "wheel_runs"), "60");
  EXPECT_EQ(rig->reply("fit apply 1 1 150.5 arc 151"),
            "ok c_l=1.000000 c_r=1.000000 wheelbase_mm=150.500000 wheelbase_arc_mm=151.000000 "
            "method=fit unsaved=1");
  // Refused whole: too far from wheelbase_mm, not a number, the keyword misplaced or alone, a
  // word too many.
  for (const char* bad :
       {"fit apply 1 1 150 arc 200", "fit apply 1 1 150 arc wide", "fit apply 1 1 150 arc",
        "fit apply 1 1 150 1700000000 60 7 arc 151", "fit apply 1 1 150 1700000000 60 151",
        "fit apply 1 1 150 arc -3", "lateral set 1 1 1700000000 3 arc 151"}) {
    const params::ParamSet before = rig->console.params();
    EXPECT_EQ(rig->reply(bad).rfind("err ", 0), 0u) << bad;
    EXPECT_TRUE(params::same(before, rig->console.params())) << bad;
  }
  EXPECT_EQ(rig->reply("fit apply 1 1 150 arc 200"),
            "err rejected drive refused (need wheelbase_arc_mm 0 or within 20% of wheelbase_mm)");
  // The old line: one wheelbase, the arc one cleared.
  EXPECT_EQ(rig->reply("fit apply 1 1 150.5"),
            "ok c_l=1.000000 c_r=1.000000 wheelbase_mm=150.500000 wheelbase_arc_mm=0.000000 "
            "method=fit unsaved=1");
  // `set` reaches it too, as a wheel factor typed by hand.
  EXPECT_EQ(rig->reply("set wheelbase_arc_mm 151.5").rfind("ok ", 0), 0u);
  EXPECT_EQ(test::value_of(rig->reply("provenance"), "wheel_method"), "manual");
}

}  // namespace
}  // namespace odocal
