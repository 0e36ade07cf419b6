// The session library's parsers: console reply lines, `#` lines, typed measurements, and the
// measurement file (strict, errors naming file, line and field).
#include <cstdio>
#include <fstream>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "odocal/console/text.hpp"
#include "odocal/host/csv.hpp"
#include "odocal/host/robot_client.hpp"
#include "odocal/host/session.hpp"
#include "session_harness.hpp"
#include "session_internal.hpp"

namespace {

using odocal::host::InputError;
using odocal::host::Reply;
using odocal::host::SessionPose;

std::string write_temp(const std::string& name, const std::string& content) {
  const std::string path = odocal_session_test::test_dir() + name;
  std::ofstream(path, std::ios::binary) << content;
  return path;
}

TEST(SessionReply, SplitsOkPairsAndErrCodes) {
  Reply r;
  ASSERT_TRUE(
      odocal::host::parse_reply("ok trial=3 path=line duration_ms=7532 count_l=-9054 x_mm=1.5", r));
  EXPECT_TRUE(r.ok);
  EXPECT_EQ(r.text("path"), "line");
  EXPECT_EQ(r.number("count_l"), -9054.0);
  EXPECT_EQ(r.number("x_mm"), 1.5);
  EXPECT_THROW(static_cast<void>(r.number("y_mm")), odocal::host::LinkError);
  ASSERT_TRUE(odocal::host::parse_reply("err busy a path is running; stop first", r));
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.code, "busy");
  EXPECT_EQ(r.message, "a path is running; stop first");
  EXPECT_FALSE(odocal::host::parse_reply("run line 1", r));  // an echo is no reply
  EXPECT_FALSE(odocal::host::parse_reply("okay", r));
  const auto pairs = odocal::host::hash_line_pairs("# done trial=12 path=umbmark-cw");
  EXPECT_EQ(pairs.at("trial"), "12");
  EXPECT_EQ(pairs.at("path"), "umbmark-cw");
}

TEST(SessionMeasurementLine, TakesTwoOrThreeNumbersAndSaysWhatIsWrong) {
  SessionPose pose;
  std::string why;
  ASSERT_TRUE(odocal::host::parse_measurement_line("-12.5 40", pose, why));
  EXPECT_EQ(pose.x_mm, -12.5);
  EXPECT_EQ(pose.y_mm, 40.0);
  EXPECT_FALSE(pose.theta_deg.has_value());
  ASSERT_TRUE(odocal::host::parse_measurement_line(" 3, -4 , 1.5\r", pose, why));
  EXPECT_EQ(*pose.theta_deg, 1.5);
  const std::pair<const char*, const char*> bad[] = {
      {"", "empty"},
      {"12", "got 1 word"},
      {"1 2 3 4", "got 4 words"},
      {"abc 2", "x_mm 'abc' is not a number"},
      {"1 2x", "y_mm '2x' is not a number"},
      {"1 nan", "y_mm 'nan' is not a number"},
      {"1e9 2", "absurd"},
      {"1 2 99999", "theta_deg 99999 is absurd"},
  };
  for (const auto& [text, message] : bad) {
    EXPECT_FALSE(odocal::host::parse_measurement_line(text, pose, why)) << text;
    EXPECT_NE(why.find(message), std::string::npos) << text << " -> " << why;
  }
}

TEST(SessionMeasurementFile, ReadsBothHeadersWithOptionalHeading) {
  const auto two = odocal::host::file_measurements(
      write_temp("m2.csv", "\xEF\xBB\xBF# notes\r\nx_mm,y_mm\r\n1,2\r\n3,4\r\n"));
  EXPECT_EQ(two->available(0), 2u);
  EXPECT_EQ(two->available(1), 1u);
  const odocal::host::RunRecord run;
  EXPECT_EQ(two->take(run, 1, 2).x_mm, 3.0);
  EXPECT_THROW(static_cast<void>(two->take(run, 2, 3)), InputError);
  const auto three =
      odocal::host::file_measurements(write_temp("m3.csv", "x_mm,y_mm,theta_deg\n1,2,\n3,4,-5\n"));
  EXPECT_FALSE(three->take(run, 0, 2).theta_deg.has_value());
  EXPECT_EQ(*three->take(run, 1, 2).theta_deg, -5.0);
}

TEST(SessionMeasurementFile, ReadsASessionsOwnJournal) {
  // measurements.csv as a session writes it: numbered rows, the heading empty when not measured.
  const auto journal = odocal::host::file_measurements(write_temp(
      "journal.csv", "run,x_mm,y_mm,theta_deg\n1,-1.500,2.000,\n2,3.000,4.000,-5.000\n"));
  EXPECT_EQ(journal->available(0), 2u);
  const odocal::host::RunRecord run;
  EXPECT_EQ(journal->take(run, 0, 2).x_mm, -1.5);
  EXPECT_FALSE(journal->take(run, 0, 2).theta_deg.has_value());
  EXPECT_EQ(journal->take(run, 1, 2).y_mm, 4.0);
  EXPECT_EQ(*journal->take(run, 1, 2).theta_deg, -5.0);
}

void expect_file_error(const std::string& name, const std::string& content,
                       const std::string& where, const std::string& field) {
  const std::string path = write_temp(name, content);
  try {
    static_cast<void>(odocal::host::file_measurements(path));
    ADD_FAILURE() << name << " was accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path + where), std::string::npos) << what;
    if (!field.empty()) {
      EXPECT_NE(what.find("field '" + field + "'"), std::string::npos) << what;
    }
  }
}

TEST(SessionMeasurementFile, GarbageIsRefusedNamingFileLineAndField) {
  expect_file_error("g1.csv", "x_mm,y_mm\n1,2\nabc,4\n", ":3", "x_mm");
  expect_file_error("g2.csv", "x_mm,y_mm\n1,2,3\n", ":2", "");
  expect_file_error("g3.csv", "x,y\n1,2\n", ":1", "");
  expect_file_error("g4.csv", "x_mm,y_mm,theta_deg\n1,2,inf\n", ":2", "theta_deg");
  expect_file_error("g5.csv", "x_mm,y_mm\n1,1e300\n", ":2", "y_mm");
  expect_file_error("g6.csv", "x_mm,y_mm\n", "", "");
  expect_file_error("missing.csv/nope", "", "", "");
  // A journal's rows in the order of the runs, numbered from 1.
  expect_file_error("j1.csv", "run,x_mm,y_mm,theta_deg\n2,1,2,\n", ":2", "run");
  expect_file_error("j2.csv", "run,x_mm,y_mm,theta_deg\n1,1,2,\n1,3,4,\n", ":3", "run");
  expect_file_error("j3.csv", "run,x_mm,y_mm\n1,1,2\n", ":1", "");
}

}  // namespace

namespace {

// A checked `# ticks` line damaged as a serial line damages it (bytes lost, bits flipped, one to
// four times) never reads as another sample: it reads as the line sent or not at all. Unchecked,
// the same damage leaves values that read but are wrong: what the check is for.
TEST(SessionTickLine, ADamagedCheckedLineNeverReadsAsAnotherSample) {
  using odocal::host::TickSample;
  using odocal::host::session::read_tick_line;
  std::mt19937_64 random(7);
  std::size_t read_wrong_unchecked = 0;
  for (int n = 0; n < 20000; ++n) {
    const std::int64_t l = static_cast<std::int64_t>(random() % 2000000) - 1000000;
    const std::int64_t r = static_cast<std::int64_t>(random() % 2000000) - 1000000;
    const std::uint64_t t = random() % 100000000;
    const std::string text = "# ticks t_ms=" + std::to_string(t) + " count_l=" + std::to_string(l) +
                             " count_r=" + std::to_string(r);
    const std::string sent =
        text + " crc=" + std::to_string(odocal::console::crc16(text.data(), text.size()));
    const std::optional<TickSample> clean = read_tick_line(sent, true);
    ASSERT_TRUE(clean && clean->t_ms == static_cast<double>(t) && clean->count_l == l &&
                clean->count_r == r)
        << sent;
    std::string damaged = sent;
    std::string plain = text;
    const int hits = 1 + static_cast<int>(random() % 4);
    for (int h = 0; h < hits; ++h) {
      const std::size_t at = random() % damaged.size();
      const std::size_t at_plain = at % plain.size();
      if (random() % 2 == 0) {
        damaged.erase(at, 1);
        plain.erase(at_plain, 1);
      } else {
        const auto flip = static_cast<char>(1u << (random() % 8));
        damaged[at] = static_cast<char>(damaged[at] ^ flip);
        plain[at_plain] = static_cast<char>(plain[at_plain] ^ flip);
      }
    }
    const std::optional<TickSample> got = read_tick_line(damaged, true);
    if (got) {
      EXPECT_TRUE(got->t_ms == static_cast<double>(t) && got->count_l == l && got->count_r == r)
          << "'" << damaged << "' read as " << got->t_ms << " " << got->count_l << " "
          << got->count_r << " (sent '" << sent << "')";
    }
    const std::optional<TickSample> unchecked = read_tick_line(plain, false);
    if (unchecked && (unchecked->t_ms != static_cast<double>(t) || unchecked->count_l != l ||
                      unchecked->count_r != r)) {
      ++read_wrong_unchecked;
    }
    // A checked line read without its check, or an unchecked one read as checked: not a sample.
    EXPECT_FALSE(read_tick_line(text, true)) << text;
    EXPECT_FALSE(read_tick_line(sent, false)) << sent;
  }
  // Without the check, many such lines read as wrong values (a digit's low bit flipped leaves a
  // digit, a lost digit leaves a number): more than 1 in 20 here; with it none do.
  EXPECT_GT(read_wrong_unchecked, 1000u);
}

}  // namespace
