// What a simulated session measures does not depend on how much the host talks (issue 47): the
// lockstep robot's clock moves for motions and for lines that change something, never for a
// question. The same session, once as it is and once with a harmless question after every
// command (ODOCAL_TEST_CHATTER, read by `odocal session` for this test only), gives the same
// figures to the last digit: tick logs, measured stops, factors, session.json (its date aside).

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "session_harness.hpp"

namespace {

using nlohmann::json;
using odocal_session_test::bin;
using odocal_session_test::Result;
using odocal_session_test::shell;

std::string file_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Drops every "date" key (the wall-clock time the session started or applied), at any depth.
void drop_dates(json& doc) {
  if (doc.is_object()) {
    doc.erase("date");
    for (auto& [key, value] : doc.items()) {
      drop_dates(value);
    }
  } else if (doc.is_array()) {
    for (json& value : doc) {
      drop_dates(value);
    }
  }
}

struct Session {
  Result r;
  std::string out;
};

/// One session on a robot of this test's own; `chatter` (empty: none) is asked after every
/// command.
Session run(const std::string& name, const std::string& flags, const std::string& chatter) {
  const std::string dir = odocal_session_test::test_dir();
  const std::string robot = dir + "chatter_robot.json";
  std::ofstream(robot) << R"({"wheel_diameter_mm": 52, "wheelbase_mm": 118, "counts_per_rev": 700,
      "true_left_diameter_mm": 52.3, "true_right_diameter_mm": 51.9,
      "true_wheelbase_mm": 121.0})";
  // Every session under the same names (the options it records match), its folder then moved to
  // `name`.
  const std::string out = dir + "out";
  const std::string store = dir + "robot.store";
  std::filesystem::remove_all(out);
  std::filesystem::remove(store);
  Session s;
  const std::string env = chatter.empty() ? "" : "ODOCAL_TEST_CHATTER='" + chatter + "' ";
  s.r = shell(env + bin("odocal") + " session --sim " + robot + " --store " + store +
              " --seed 11 --yes --out " + out + " " + flags + " </dev/null");
  s.out = dir + name;
  std::filesystem::remove_all(s.out);
  std::filesystem::rename(out, s.out);
  return s;
}

/// The files a session writes that carry figures: session.json (dates dropped) and every CSV.
void expect_same_figures(const Session& quiet, const Session& chatty) {
  json a = json::parse(file_text(quiet.out + "/session.json"), nullptr, false);
  json b = json::parse(file_text(chatty.out + "/session.json"), nullptr, false);
  ASSERT_TRUE(a.is_object());
  ASSERT_TRUE(b.is_object());
  drop_dates(a);
  drop_dates(b);
  EXPECT_EQ(a, b);
  std::vector<std::string> csvs;
  for (const auto& entry : std::filesystem::directory_iterator(quiet.out)) {
    if (entry.path().extension() == ".csv") {
      csvs.push_back(entry.path().filename().string());
    }
  }
  std::sort(csvs.begin(), csvs.end());
  ASSERT_GE(csvs.size(), 3u);  // measurements.csv, runs.csv and the runs' tick logs at least
  for (const std::string& csv : csvs) {
    SCOPED_TRACE(csv);
    const std::string theirs = chatty.out + "/" + csv;
    ASSERT_TRUE(std::filesystem::exists(theirs));
    EXPECT_EQ(file_text(quiet.out + "/" + csv), file_text(theirs));
  }
}

/// The count of console lines the session says it sent (its log's "Console:" line).
long lines_sent(const Result& r) {
  const std::string all = r.out + r.err;
  const std::size_t at = all.find("Console: ");
  if (at == std::string::npos) {
    return -1;
  }
  return std::atol(all.c_str() + at + 9);
}

TEST(SessionChatter, AutoWithAQuestionAfterEveryCommandMeasuresTheSameToTheLastDigit) {
  const Session quiet = run("auto_quiet", "--procedure auto", "");
  const Session chatty = run("auto_chatty", "--procedure auto", "get v_max_mps");
  ASSERT_EQ(quiet.r.status, 0) << quiet.r.err;
  ASSERT_EQ(chatty.r.status, 0) << chatty.r.err;
  // The chatter was sent: every command line had a question after it.
  ASSERT_GT(lines_sent(quiet.r), 0) << quiet.r.err;
  EXPECT_GT(2 * lines_sent(chatty.r), 3 * lines_sent(quiet.r)) << chatty.r.err;
  expect_same_figures(quiet, chatty);
}

TEST(SessionChatter, UmbmarkAndLateralWithStatusAfterEveryCommandMeasureTheSame) {
  for (const char* flags :
       {"--procedure umbmark --runs 2 --side-m 1 --passes 1", "--procedure lateral --runs 3"}) {
    SCOPED_TRACE(flags);
    const Session quiet = run("quiet", flags, "");
    const Session chatty = run("chatty", flags, "status");
    ASSERT_EQ(quiet.r.status, 0) << quiet.r.err;
    ASSERT_EQ(chatty.r.status, 0) << chatty.r.err;
    EXPECT_GT(2 * lines_sent(chatty.r), 3 * lines_sent(quiet.r)) << chatty.r.err;
    expect_same_figures(quiet, chatty);
  }
}

}  // namespace
