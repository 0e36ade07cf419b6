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

double number(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  EXPECT_TRUE(!text.empty() && *end == '\0') << "not a number: '" << text << "'";
  return v;
}

// Printed with 6 decimals: within 0.5e-6 of the stored float.
constexpr double kPrinted = 0.5e-6 + 1e-9;

// Every reply line is `ok` + key=value pairs or `err <code> <message>`.
const std::regex kOkLine(R"(ok( [a-z_0-9]+=[^ =]+)*)");
const std::regex kErrLine(R"(err [a-z_]+ \S.*)");

std::unique_ptr<Rig> make_rig(ConsoleOptions options = Rig::quiet(), RigFlash* flash = nullptr) {
  auto rig = std::make_unique<Rig>(options, flash);
  (void)rig->console.start(rig->now_us);
  return rig;
}

TEST(Console, VersionReportsTheProjectVersion) {
  auto rig = make_rig();
  const std::string line = rig->reply("version");
  EXPECT_TRUE(std::regex_match(line, kOkLine)) << line;
  EXPECT_EQ(value_of(line, "name"), "odocal");
  EXPECT_EQ(value_of(line, "protocol"), "1");
  EXPECT_EQ(value_of(line, "record_format"), "2");
  // The version compiled into the core is the one CMake declares.
  const char* source = std::getenv("ODOCAL_SOURCE_DIR");
  ASSERT_NE(source, nullptr) << "run through ctest";
  std::ifstream cmake(std::string(source) + "/CMakeLists.txt");
  std::stringstream text;
  text << cmake.rdbuf();
  std::smatch match;
  const std::string s = text.str();
  ASSERT_TRUE(std::regex_search(s, match, std::regex(R"(project\(odocal VERSION ([0-9.]+))")));
  EXPECT_EQ(value_of(line, "version"), match[1].str());
  EXPECT_EQ(std::string(console::project_version), match[1].str());
}

TEST(Console, ErrorCodesAreDistinctAndAllDocumented) {
  const char* source = std::getenv("ODOCAL_SOURCE_DIR");
  ASSERT_NE(source, nullptr) << "run through ctest";
  std::ifstream file(std::string(source) + "/docs/console.md");
  std::stringstream text;
  text << file.rdbuf();
  const std::string docs = text.str();
  std::set<std::string> names;
  for (int code = 0; code <= static_cast<int>(console::ErrorCode::store_corrupt); ++code) {
    const std::string name = console::error_code_name(static_cast<console::ErrorCode>(code));
    EXPECT_TRUE(names.insert(name).second) << name << " used twice";
    EXPECT_NE(docs.find("| `" + name + "` |"), std::string::npos) << name << " not in docs";
  }
  EXPECT_EQ(names.size(), 21u);
}

TEST(Console, EveryCommandGetsExactlyOneWellFormedReply) {
  auto rig = make_rig();
  const char* commands[] = {"help",
                            "version",
                            "status",
                            "params",
                            "get c_l",
                            "set c_l 1.01",
                            "save",
                            "load",
                            "defaults",
                            "provenance",
                            "odom",
                            "odom reset",
                            "drive 0.1 0 100",
                            "stop",
                            "run line 1",
                            "stop",
                            "run umbmark-cw 2",
                            "stop",
                            "run umbmark-ccw 2",
                            "stop",
                            "run unseen",
                            "stop",
                            "umbmark clear",
                            "umbmark add cw 10 20",
                            "umbmark side 4",
                            "umbmark solve",
                            "umbmark apply",
                            "stream odom 10",
                            "stream off",
                            "echo off",
                            "nonsense",
                            "get",
                            "set c_l 9"};
  for (const char* command : commands) {
    const std::string line = rig->reply(command);
    EXPECT_TRUE(std::regex_match(line, kOkLine) || std::regex_match(line, kErrLine))
        << command << " -> " << line;
    rig->tick(2);
  }
}

TEST(Console, HelpListsEveryCommand) {
  auto rig = make_rig();
  const auto lines = rig->send("help");
  ASSERT_FALSE(lines.empty());
  const std::string& last = lines.back();
  EXPECT_EQ(last.rfind("ok ", 0), 0u);
  EXPECT_EQ(number(value_of(last, "commands")), static_cast<double>(lines.size() - 1));
  std::string all;
  for (const auto& l : lines)
    all += l + "\n";
  for (const char* word : {"help",
                           "version",
                           "status",
                           "params",
                           "get <name>",
                           "set <name> <value>",
                           "save",
                           "load",
                           "defaults",
                           "odom",
                           "odom reset",
                           "drive <v_mps> <w_radps> [ms]",
                           "stop",
                           "run umbmark-cw <side_m>",
                           "run umbmark-ccw <side_m>",
                           "run line <m>",
                           "run unseen",
                           "umbmark clear",
                           "umbmark add cw|ccw <x_mm> <y_mm>",
                           "umbmark solve",
                           "umbmark apply",
                           "stream odom <hz>",
                           "stream off"}) {
    EXPECT_NE(all.find(std::string("# ") + word), std::string::npos) << word;
  }
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

// A refused command changes nothing: the parameters, provenance, unsaved flag and the drive
// configuration are the same after it.
void expect_refused_without_change(Rig& rig, const std::string& command, const std::string& code) {
  const params::ParamSet before = rig.console.params();
  const bool unsaved_before = rig.console.unsaved();
  const drive::DriveConfig config_before = rig.loop.config();
  const std::string line = rig.reply(command);
  EXPECT_EQ(error_code(line), code) << command << " -> " << line;
  EXPECT_TRUE(std::regex_match(line, kErrLine)) << line;
  EXPECT_TRUE(params::same(before, rig.console.params())) << command;
  EXPECT_EQ(unsaved_before, rig.console.unsaved()) << command;
  const drive::DriveConfig after = rig.loop.config();
  EXPECT_EQ(std::memcmp(&config_before, &after, sizeof after), 0) << command;
}

TEST(Console, EveryErrorCodeOfTheParserAndTheTable) {
  auto rig = make_rig();
  expect_refused_without_change(*rig, "frobnicate", "unknown_command");
  expect_refused_without_change(*rig, "GET c_l", "unknown_command");
  expect_refused_without_change(*rig, "get C_L", "unknown_parameter");
  expect_refused_without_change(*rig, "set wheel 3", "unknown_parameter");
  expect_refused_without_change(*rig, "get", "wrong_arity");
  expect_refused_without_change(*rig, "get c_l c_r", "wrong_arity");
  expect_refused_without_change(*rig, "set c_l", "wrong_arity");
  expect_refused_without_change(*rig, "set c_l 1 2", "wrong_arity");
  expect_refused_without_change(*rig, "version now", "wrong_arity");
  expect_refused_without_change(*rig, "a b c d e f g h", "unknown_command");
  expect_refused_without_change(*rig, "set c_l 1 2 3 4 5 6", "wrong_arity");
  expect_refused_without_change(*rig, "run", "wrong_arity");
  expect_refused_without_change(*rig, "run line", "wrong_arity");
  expect_refused_without_change(*rig, "run unseen 3", "wrong_arity");
  expect_refused_without_change(*rig, "drive 0.1", "wrong_arity");
  expect_refused_without_change(*rig, "stream", "wrong_arity");
  expect_refused_without_change(*rig, "stream odom", "wrong_arity");
  expect_refused_without_change(*rig, "run circle 1", "bad_argument");
  expect_refused_without_change(*rig, "odom zero", "bad_argument");
  expect_refused_without_change(*rig, "stream pose 5", "bad_argument");
  expect_refused_without_change(*rig, "umbmark add up 1 2", "bad_argument");
  expect_refused_without_change(*rig, "umbmark redo", "bad_argument");
  expect_refused_without_change(*rig, "umbmark solve fast", "bad_argument");
  expect_refused_without_change(*rig, "echo maybe", "bad_argument");
  for (const char* bad :
       {"1.0abc", "nan", "inf", "-inf", "1e", "0x1", "1,5", "..5", "1e999", "--1", "one"}) {
    expect_refused_without_change(*rig, std::string("set c_l ") + bad, "bad_number");
  }
  expect_refused_without_change(*rig, "set max_illegal 3.5", "bad_number");
  expect_refused_without_change(*rig, "drive 0.1 0 10.5", "bad_number");
  expect_refused_without_change(*rig, "umbmark apply yesterday", "bad_number");
  expect_refused_without_change(*rig, "set c_l 2.0000001", "out_of_range");
  expect_refused_without_change(*rig, "set c_l 0.49", "out_of_range");
  expect_refused_without_change(*rig, "set c_l -1", "out_of_range");
  expect_refused_without_change(*rig, "set control_hz 1e9", "out_of_range");
  expect_refused_without_change(*rig, "run line 50", "out_of_range");
  expect_refused_without_change(*rig, "run line 0", "out_of_range");
  expect_refused_without_change(*rig, "drive 9 0", "out_of_range");
  expect_refused_without_change(*rig, "stream odom 1000", "out_of_range");
  // The cross-field rule of the drive: wheelbase must exceed a quarter of the wheel diameter.
  expect_refused_without_change(*rig, "set wheel_diameter_mm 1000", "rejected");
  expect_refused_without_change(*rig, "umbmark apply", "not_solved");
  expect_refused_without_change(*rig, "load", "store_empty");
  const std::string out_of_range = rig->reply("set c_l 3");
  EXPECT_EQ(out_of_range, "err out_of_range allowed min=0.500000 max=2.000000");
}

TEST(Console, LineTooLongIsRefusedWholeAndTheNextLineWorks) {
  auto rig = make_rig();
  // 127 bytes: accepted (padding zeros keep it a valid number).
  std::string max_line = "set c_l 1.";
  max_line += std::string(127 - max_line.size() - 1, '0') + "5";
  ASSERT_EQ(max_line.size(), 127u);
  EXPECT_EQ(rig->reply(max_line), "ok c_l=1.000000");
  // 128 bytes of a command that would otherwise be valid: refused, nothing changed.
  std::string too_long = "set c_l 1.";
  too_long += std::string(128 - too_long.size() - 1, '0') + "5";
  expect_refused_without_change(*rig, too_long, "line_too_long");
  expect_refused_without_change(*rig, std::string(5000, 'x'), "line_too_long");
  EXPECT_EQ(rig->reply("get c_l"), "ok c_l=1.000000");
}

TEST(Console, NonAsciiAndControlBytesAreRefused) {
  auto rig = make_rig();
  expect_refused_without_change(*rig, "set c_l 1.5\xc2\xa0", "non_ascii");
  expect_refused_without_change(*rig, "set c_\xff 1", "non_ascii");
  expect_refused_without_change(*rig, "set c_l \x1b[A1.5", "non_ascii");
  expect_refused_without_change(*rig, std::string("get c_l\0", 8), "non_ascii");
}

TEST(Console, LineEndingsBackspaceTabsAndBlankLines) {
  auto rig = make_rig();
  const std::size_t mark = rig->stream.output_size;
  rig->stream.type(
      "get c_l\rget c_r\r\nget f_lat\n\n\r\n   \nget\tf_lon\nget c_x\bl\nkp\x7f\x7fget kp\n");
  rig->settle();
  const auto lines = rig->split_lines(mark);
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_EQ(lines[0], "ok c_l=1.000000");
  EXPECT_EQ(lines[1], "ok c_r=1.000000");
  EXPECT_EQ(lines[2], "ok f_lat=1.000000");
  EXPECT_EQ(lines[3], "ok f_lon=1.000000");
  EXPECT_EQ(lines[4], "ok c_l=1.000000");
  EXPECT_EQ(lines[5], "ok kp=0.050000");
}

TEST(Console, EchoOnShowsTypedTextOffStaysSilentAutomaticWakesOnATerminal) {
  ConsoleOptions on = Rig::quiet();
  on.echo = EchoMode::on;
  on.crlf = true;
  auto interactive = make_rig(on);
  std::size_t mark = interactive->stream.output_size;
  interactive->stream.type("get c_x\bl\r");
  interactive->settle();
  EXPECT_EQ(
      std::string(interactive->stream.output.data() + mark, interactive->stream.output_size - mark),
      "get c_x\b \bl\r\nok c_l=1.000000\r\n");

  auto scripted = make_rig();
  mark = scripted->stream.output_size;
  scripted->stream.type("get c_l\n");
  scripted->settle();
  EXPECT_EQ(std::string(scripted->stream.output.data() + mark, scripted->stream.output_size - mark),
            "ok c_l=1.000000\n");

  ConsoleOptions automatic = Rig::quiet();
  automatic.echo = EchoMode::automatic;
  auto auto_rig = make_rig(automatic);
  mark = auto_rig->stream.output_size;
  auto_rig->stream.type("get c_l\n");  // a script: no echo
  auto_rig->settle();
  EXPECT_EQ(std::string(auto_rig->stream.output.data() + mark, auto_rig->stream.output_size - mark),
            "ok c_l=1.000000\n");
  mark = auto_rig->stream.output_size;
  auto_rig->stream.type("x\bget c_r\n");  // a person correcting a typo: echo from now on
  auto_rig->settle();
  EXPECT_EQ(std::string(auto_rig->stream.output.data() + mark, auto_rig->stream.output_size - mark),
            "get c_r\nok c_r=1.000000\n");

  EXPECT_EQ(scripted->reply("echo on"), "ok echo=on");
  EXPECT_EQ(scripted->send("get c_l").front(), "get c_l");
}

TEST(Console, CtrlCDiscardsTheLineWithoutReply) {
  auto rig = make_rig();
  const std::size_t mark = rig->stream.output_size;
  rig->stream.type("set c_l 1.5\x03get c_l\n");
  rig->settle();
  const auto lines = rig->split_lines(mark);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0], "ok c_l=1.000000");
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
  const auto banner = rebooted->split_lines(0);
  ASSERT_EQ(banner.size(), 1u);
  EXPECT_EQ(banner[0].rfind("# odocal ", 0), 0u);
  EXPECT_EQ(value_of(banner[0], "params"), "loaded");
  EXPECT_EQ(rebooted->reply("get c_l"), "ok c_l=0.990000");
  EXPECT_EQ(rebooted->reply("get wheelbase_mm"), "ok wheelbase_mm=152.500000");
  EXPECT_FLOAT_EQ(rebooted->loop.config().wheelbase_mm, 152.5f);
}

TEST(Console, BannerSaysWhyTheDefaultsAreInForce) {
  ConsoleOptions with_banner = Rig::quiet();
  with_banner.banner = true;
  auto rig = std::make_unique<Rig>(with_banner);
  EXPECT_EQ(rig->console.start(rig->now_us), params::StoreResult::empty);
  rig->settle();
  const auto lines = rig->split_lines(0);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0], std::string("# odocal ") + console::project_version +
                          " console params=defaults store=empty");
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

// Decision (docs/console.md): `set` is refused while a path runs, because the runs of a
// calibration must be driven and measured with one set of factors; `get` works; `stop` always
// works, and `set` works again at once after it.
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

TEST(Console, AFullOutputQueueDropsStreamLinesNeverReplies) {
  auto rig = make_rig();
  rig->reply("stream odom 100");
  rig->stream.write_limit = 0;  // the link stalls (terminal closed, flow control)
  for (int i = 0; i < 5000; ++i) {
    rig->now_us += 1000;
    rig->console.poll(rig->now_us);  // returns every time: nothing blocks
  }
  rig->stream.type("get c_l\n");
  for (int i = 0; i < 10; ++i) {
    rig->now_us += 1000;
    rig->console.poll(rig->now_us);
  }
  rig->stream.write_limit = 1 << 20;
  const std::size_t mark = rig->stream.output_size;
  rig->console.poll(rig->now_us);
  const auto lines = rig->split_lines(mark);
  bool got_reply = false;
  for (const auto& l : lines)
    got_reply = got_reply || l == "ok c_l=1.000000";
  EXPECT_TRUE(got_reply);
  EXPECT_GT(rig->console.counters().stream_dropped, 400u);
  const std::string status = rig->reply("stream off");
  EXPECT_GT(number(value_of(rig->reply("status"), "stream_dropped")), 400.0);
}

TEST(Console, RxRingOverflowIsCountedNotFatal) {
  auto rig = make_rig();
  int accepted = 0;
  for (int i = 0; i < 400; ++i)
    accepted += rig->console.receive_from_isr('x') ? 1 : 0;
  EXPECT_EQ(accepted, static_cast<int>(console::Console::rx_capacity - 1));
  EXPECT_EQ(rig->console.counters().rx_dropped, 400u - accepted);
  rig->settle();  // the main loop catches up: 255 bytes of an unterminated line
  for (char c : std::string("\nget c_l\n"))
    (void)rig->console.receive_from_isr(static_cast<std::uint8_t>(c));
  const std::size_t mark = rig->stream.output_size;
  rig->settle();
  const auto lines = rig->split_lines(mark);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(error_code(lines[0]), "line_too_long");
  EXPECT_EQ(lines[1], "ok c_l=1.000000");
}

TEST(Console, OneCommandPerPollAndReadsOnlyWhenAReplyFits) {
  auto rig = make_rig();
  rig->stream.type("get c_l\nget c_r\n");
  rig->now_us += 100;
  rig->console.poll(rig->now_us);
  EXPECT_EQ(rig->split_lines(0).size(), 1u);
  EXPECT_FALSE(rig->console.idle());
  rig->console.poll(rig->now_us);
  EXPECT_EQ(rig->split_lines(0).size(), 2u);
  EXPECT_TRUE(rig->console.idle());
}

TEST(Console, PollingACommandSessionAllocatesNothing) {
  auto rig = make_rig();
  rig->stream.type(
      "help\nparams\nversion\nstatus\nget c_l\nset c_l 1.01\nsave\nload\ndefaults\nodom\n"
      "odom reset\ndrive 0.1 0 10\nstop\nrun line 1\nstop\numbmark add cw 1 2\numbmark add cw 2 "
      "1\numbmark add ccw 1 2\numbmark add ccw 2 1\numbmark solve\numbmark apply\n"
      "stream odom 50\nbad\nset c_l 1e\nprovenance\n");
  AllocationWatch watch;
  for (int i = 0; i < 20000; ++i) {
    rig->now_us += 100;
    rig->console.poll(rig->now_us);
    if (i % 10 == 0)
      rig->loop.tick(rig->now_us);
  }
  EXPECT_EQ(watch.allocations(), 0u);
  EXPECT_TRUE(rig->stream.drained());
  EXPECT_GE(rig->console.counters().commands, 25u);
}

}  // namespace
}  // namespace odocal::test

namespace odocal::test {
namespace {

std::size_t target_pairs(void* context, char* out, std::size_t capacity) {
  const char* text = static_cast<const char*>(context);
  std::size_t n = 0;
  while (text[n] != '\0' && n < capacity) {
    out[n] = text[n];
    ++n;
  }
  return n;
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

}  // namespace
}  // namespace odocal::test

namespace odocal::test {
namespace {

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
