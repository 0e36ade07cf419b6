// The strict input every `odocal` command shares: CSV and JSON files (byte order marks, line
// ends, duplicate keys, overflow, NUL bytes, directories) and command-line numbers.
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_process.hpp"

namespace {

using namespace cli_test;

// A spreadsheet export: UTF-8 byte order mark before the header, CRLF line ends. Same figures as
// the plain file.
TEST(CliCsv, ByteOrderMarkAndCrlfAreAccepted) {
  const auto exported = [](const std::string& name) {
    std::string crlf = "\xEF\xBB\xBF";
    for (const char c : read_text(data(name))) {
      crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    }
    return temp_file("bom_" + name, crlf);
  };
  const json plain = parse_json(odocal(umbmark_args + " --cw " + data("umbmark_cw.csv") +
                                       " --ccw " + data("umbmark_ccw.csv")));
  const json bom = parse_json(odocal(umbmark_args + " --cw " + exported("umbmark_cw.csv") +
                                     " --ccw " + exported("umbmark_ccw.csv")));
  EXPECT_EQ(bom["e_d"], plain["e_d"]);
  EXPECT_EQ(bom["e_b"], plain["e_b"]);
  const std::string accuracy_bom = temp_file(
      "bom_accuracy.csv", "\xEF\xBB\xBFscenario,trial,x_mm,y_mm\r\nNC,1,3,4\r\nCL,1,0,1\r\n");
  const json accuracy = parse_json(odocal("accuracy --json " + accuracy_bom));
  EXPECT_EQ(accuracy["scenarios"][0]["name"], "NC");
  EXPECT_NEAR(accuracy["scenarios"][1]["improvement_pct"].get<double>(), 80.0, 1e-9);
  // A BOM anywhere but the start of line 1 is still junk.
  expect_bad_input(
      odocal("accuracy " +
             temp_file("bom_late.csv", "scenario,trial,x_mm,y_mm\n\xEF\xBB\xBFNC,1,3,4\n")),
      "bom_late.csv", "2", "scenario");
}

// Every command-line number: a finite decimal within human bounds, else exit 2 naming the flag,
// with a short message (no 300-digit bounds) and nothing on stdout.
TEST(CliFlags, NumbersAreFiniteAndBounded) {
  const std::string umbmark_files =
      " --cw " + data("umbmark_cw.csv") + " --ccw " + data("umbmark_ccw.csv");
  const std::string umbmark = "umbmark" + umbmark_files;
  const std::string lateral_files = " --trials " + data("lateral_trials.csv");
  const std::string lateral_ok = "--length-mm 1000 --wheelbase-mm 150 --dl-mm 60 --dr-mm 60";
  const std::string bootstrap = "bootstrap --training " + data("bootstrap_training.csv") +
                                " --unknowns " + data("bootstrap_unknowns.csv");
  struct Case {
    std::string args;
    std::string flag;
  };
  const Case cases[] = {
      {umbmark + " --wheelbase-mm 340 --side-mm nan", "--side-mm"},
      {umbmark + " --wheelbase-mm 340 --side-mm 4000x", "--side-mm"},
      {umbmark + " --wheelbase-mm 340 --side-mm 0x10", "--side-mm"},
      {umbmark + " --wheelbase-mm 340 --side-mm 1e400", "--side-mm"},
      {umbmark + " --side-mm 4000 --wheelbase-mm inf", "--wheelbase-mm"},
      {umbmark + " --side-mm 4000 --wheelbase-mm 0", "--wheelbase-mm"},
      {"lateral" + lateral_files + " --wheelbase-mm 150 --dl-mm 60 --dr-mm 60 --length-mm -1",
       "--length-mm"},
      {"lateral" + lateral_files + " --length-mm 1000 --wheelbase-mm 150 --dr-mm 60 --dl-mm nan",
       "--dl-mm"},
      {"lateral" + lateral_files + " --length-mm 1000 --wheelbase-mm 150 --dl-mm 60 --dr-mm 1e9",
       "--dr-mm"},
      {"lateral" + lateral_files + " " + lateral_ok + " --theta-l-rad 1e-300", "--theta-l-rad"},
      {"lateral" + lateral_files + " " + lateral_ok + " --theta-l-rad 1910", "--theta-l-rad"},
      {"lateral" + lateral_files + " " + lateral_ok + " --theta-l-rad -1", "--theta-l-rad"},
      {bootstrap + " --level 0", "--level"},
      {bootstrap + " --level 1", "--level"},
      {bootstrap + " --level nan", "--level"},
      {bootstrap + " --b 0", "--b"},
      {bootstrap + " --b 99", "--b"},
      {bootstrap + " --b 1000001", "--b"},
      {bootstrap + " --b 2e3", "--b"},
      {bootstrap + " --seed -1", "--seed"},
      {bootstrap + " --seed 18446744073709551616", "--seed"},
      {bootstrap + " --seed 1.5", "--seed"},
      {bootstrap + " --wheelbase-mm 150 --dl-mm 60 --dr-mm nan", "--dr-mm"},
      {bootstrap + " --dl-mm 60", "--wheelbase-mm"},
      {bootstrap + " --date 2020-13-45", "--date"},
      {bootstrap + " --date 2021-02-29", "--date"},
      {bootstrap + " --date 2021-04-31", "--date"},
      {bootstrap + " --date 2021-1-01", "--date"},
      {"accuracy " + data("table3_systematic.csv") + " --date 0000-00-00", "--date"},
  };
  for (const Case& c : cases) {
    const Result r = odocal(c.args);
    EXPECT_EQ(r.status, 2) << c.args << "\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << c.args << "\n" << r.out;
    EXPECT_NE(r.err.find(c.flag), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_LT(r.err.size(), 400u) << r.err;
  }
  // The edges that are allowed.
  EXPECT_EQ(odocal(bootstrap + " --seed 18446744073709551615 --b 100 --level 0.5 --date "
                               "2024-02-29")
                .status,
            0);
  EXPECT_EQ(odocal("lateral" + lateral_files + " " + lateral_ok + " --theta-l-rad 34").status, 0);
}

// A hand-edited key given twice used to go through with the last value (exit 0).
TEST(CliJson, DuplicateKeysAreRefusedInEveryObject) {
  const Result top = odocal(
      "ros2 --from " +
      temp_file("dup_top.json", "{\"c_l\": 1.0,\n \"c_r\": 1.0,\n \"e_b\": 1.0,\n \"c_l\": 1.5}"));
  expect_refused(top, "dup_top.json:4: field 'c_l'", "more than once");
  const Result nested =
      odocal("ros2 --from " + temp_file("dup_nested.json",
                                        "{\"c_l\": 1, \"c_r\": 1, \"e_b\": 1,\n \"provenance\": "
                                        "{\"runs\": 5,\n \"runs\": 6}}"));
  expect_refused(nested, "dup_nested.json:3: field 'runs'", "more than once");
  // The same key in two different objects is not a duplicate.
  const Result separate =
      odocal("ros2 --from " +
             temp_file("dup_separate.json",
                       "{\"c_l\": 1, \"c_r\": 1, \"e_b\": 1, \"x\": [{\"a\": 1}, {\"a\": 2}]}"));
  EXPECT_EQ(separate.status, 0) << separate.err;
}

TEST(CliJson, OverflowNulAndDirectoryAreNamedInPlainWords) {
  expect_refused(
      odocal("ros2 --from " + temp_file("huge.json", "{\"c_l\": 1,\n \"c_r\": 1e400, \"e_b\": 1}")),
      "huge.json:2: field 'c_r'", "out of range");
  expect_refused(
      odocal("ros2 --from " + temp_file("nul.json", std::string("{\"c_l\": 1,\n \"c_r\": 1") +
                                                        '\0' + ", \"e_b\": 1}")),
      "nul.json:2", "NUL byte");
  expect_refused(odocal("ros2 --from " + ::testing::TempDir()), ::testing::TempDir(),
                 "is a directory");
}

TEST(CliCsv, DirectoryNulAndOverflowAreNamed) {
  const std::string ccw = " --ccw " + data("umbmark_ccw.csv");
  expect_refused(odocal(umbmark_args + " --cw " + ::testing::TempDir() + ccw), ::testing::TempDir(),
                 "is a directory");
  // The message goes on past the NUL byte (it used to end where the byte was printed).
  const Result nul =
      odocal(umbmark_args + " --cw " +
             temp_file("nul.csv", std::string("x_mm,y_mm\n1,2\n3,") + '\0' + "4\n") + ccw);
  expect_refused(nul, "nul.csv:3: field 'y_mm'", "contains a NUL byte");
  EXPECT_EQ(nul.err.find('\0'), std::string::npos);
  const Result huge =
      odocal(umbmark_args + " --cw " + temp_file("huge.csv", "x_mm,y_mm\n1e400,2\n3,4\n") + ccw);
  expect_refused(huge, "huge.csv:2: field 'x_mm'", "out of range");
  EXPECT_EQ(huge.err.find("not a number"), std::string::npos) << huge.err;
}

// Old Mac exports end lines with a bare CR, as the robot's console accepts: same figures as LF.
TEST(CliCsv, CarriageReturnLineEndsAreLines) {
  std::string cr;
  for (const char c : read_text(data("umbmark_cw.csv"))) {
    cr += c == '\n' ? '\r' : c;
  }
  const json plain = parse_json(odocal(umbmark_args + " --cw " + data("umbmark_cw.csv") +
                                       " --ccw " + data("umbmark_ccw.csv")));
  const json mac = parse_json(odocal(umbmark_args + " --cw " + temp_file("cr_cw.csv", cr) +
                                     " --ccw " + data("umbmark_ccw.csv")));
  EXPECT_EQ(mac["e_d"], plain["e_d"]);
  EXPECT_EQ(mac["e_b"], plain["e_b"]);
}

// 1e-310 is a (subnormal) number: it is taken, and only a range check may refuse it.
TEST(CliCsv, SubnormalIsANumber) {
  const Result tiny = odocal(umbmark_args + " --cw " +
                             temp_file("tiny.csv", "x_mm,y_mm\n1e-310,2\n3,4\n5,1\n2,2\n4,3\n") +
                             " --ccw " + data("umbmark_ccw.csv"));
  EXPECT_EQ(tiny.status, 0) << tiny.err;
  EXPECT_EQ(tiny.err.find("not a number"), std::string::npos) << tiny.err;
}

}  // namespace
