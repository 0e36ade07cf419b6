// The console's protocol: one reply per line, its format and error codes, `help`, and the line
// editing rules (length, bytes, line ends, echo, Ctrl-C) of docs/console.md.

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
  for (int code = 0; code < static_cast<int>(console::ErrorCode::count); ++code) {
    const std::string name = console::error_code_name(static_cast<console::ErrorCode>(code));
    EXPECT_TRUE(names.insert(name).second) << name << " used twice";
    EXPECT_NE(docs.find("| `" + name + "` |"), std::string::npos) << name << " not in docs";
  }
  EXPECT_EQ(names.size(), 22u);
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
  expect_refused_without_change(*rig, "ab b c d e f g h", "unknown_command");
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

}  // namespace
}  // namespace odocal::test
