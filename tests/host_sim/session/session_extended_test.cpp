// `odocal session --procedure extended` end to end: the real `odocal` drives the real `odocal-sim`
// (--sim: its tape measure with heading, and its `measure cables` floor), and refuses
// measurements without a heading before anything moves.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "session_harness.hpp"

namespace {

using nlohmann::json;
// The programs under test and running them: the session tests' shared harness.
using odocal_session_test::bin;
using odocal_session_test::Result;
using odocal_session_test::shell;

constexpr double pi = 3.14159265358979323846;

// The default robot's geometry (uncalibrated: a systematic heading error of several degrees in
// each direction, which the reference runs must take out), its slip and tape measure.
constexpr double true_right_diameter_mm = 60.03;
constexpr double true_wheelbase_mm = 151.5;
const char* const robot_10mm = R"({"slip_sigma": 0.0005, "measure_sigma_mm": 2})";
const char* const robot_5mm =
    R"({"slip_sigma": 0.0005, "measure_sigma_mm": 2, "bump_height_mm": 5})";

std::string temp(const std::string& name) {
  return odocal_session_test::test_dir() + "odocal_extended_" + name;
}

std::string write(const std::string& name, const std::string& content) {
  const std::string path = temp(name);
  std::ofstream(path, std::ios::binary) << content;
  return path;
}

json read_json(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return json::parse(text.str(), nullptr, false);
}

/// A whole --sim extended session (5 + 5 runs on each floor, 4 m square); its session.json.
json extended_session(const std::string& name, const char* robot_file, Result* result = nullptr) {
  const std::string robot = write(name + ".json", robot_file);
  const std::string out = temp(name + "_out");
  std::system(("rm -rf " + out).c_str());
  const Result r = shell(bin("odocal") + " session --sim " + robot +
                         " --seed 4 --procedure extended --json --out " + out + " </dev/null");
  EXPECT_EQ(r.status, 0) << r.err;
  if (result != nullptr) {
    *result = r;
  }
  return read_json(out + "/session.json");
}

/// The session of the default robot over 10 mm cables, run once for the tests that read it.
const json& session_10mm(Result* result = nullptr) {
  static Result r;
  static const json doc = extended_session("cables10", robot_10mm, &r);
  if (result != nullptr) {
    *result = r;
  }
  return doc;
}

/// What the cables alone cost the heading, both directions together, degrees: per direction ten
/// crossings of the right wheel, each losing (arc − chord) of ground travel (docs/simulation.md,
/// "Floor cables"), turning the robot by that over the wheelbase.
double cables_alone_deg(double height_mm) {
  const double r = 0.5 * true_right_diameter_mm;
  const double c = 0.5 * height_mm;
  const double arc = 2.0 * (r + c) * std::acos((r - c) / (r + c));
  const double chord = 4.0 * std::sqrt(r * c);
  return 2.0 * 10.0 * (arc - chord) / true_wheelbase_mm * 180.0 / pi;
}

/// Heading error (measured minus odometry, wrapped to ±180°) of each run of `label`.
std::vector<double> heading_errors(const json& doc, const std::string& label) {
  std::vector<double> errors;
  for (const json& run : doc["runs"]) {
    if (run["label"] == label) {
      errors.push_back(std::remainder(
          run["measured"]["theta_deg"].get<double>() - run["odom"]["theta_deg"].get<double>(),
          360.0));
    }
  }
  return errors;
}

double mean(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) {
    sum += x;
  }
  return sum / static_cast<double>(v.size());
}

double sample_sd(const std::vector<double>& v) {
  const double m = mean(v);
  double sum = 0.0;
  for (double x : v) {
    sum += (x - m) * (x - m);
  }
  return std::sqrt(sum / static_cast<double>(v.size() - 1));
}

TEST(SessionExtended, FigureIsTheDefinitionComputedFromTheRunsItRecorded) {
  Result r;
  const json& doc = session_10mm(&r);
  ASSERT_TRUE(doc.is_object()) << r.err;
  EXPECT_EQ(doc["procedure"], "extended");
  EXPECT_TRUE(doc["complete"].get<bool>());
  // A measurement, not a calibration.
  EXPECT_FALSE(doc["applied"].get<bool>());
  EXPECT_FALSE(doc["saved"].get<bool>());
  EXPECT_EQ(doc["factors"]["c_l"].get<double>(), 1.0);
  EXPECT_EQ(doc["factors"]["c_r"].get<double>(), 1.0);
  EXPECT_EQ(doc["factors"]["wheelbase_mm"].get<double>(), 150.0);
  // The --json on stdout is session.json.
  const json printed = json::parse(r.out, nullptr, false);
  ASSERT_TRUE(printed.is_object()) << r.out;
  EXPECT_EQ(printed["result"], doc["result"]);
  ASSERT_EQ(doc["runs"].size(), 20u);
  for (const json& run : doc["runs"]) {
    EXPECT_FALSE(run["measured"]["theta_deg"].is_null());
  }

  const json& result = doc["result"];
  double figure = 0.0;
  const char* const directions[2] = {"cw", "ccw"};
  std::size_t bump_index = 0;
  for (const char* direction : directions) {
    const std::vector<double> reference = heading_errors(doc, direction);
    const std::vector<double> bumps = heading_errors(doc, std::string("bumps-") + direction);
    ASSERT_EQ(reference.size(), 5u);
    ASSERT_EQ(bumps.size(), 5u);
    const double reference_mean = mean(reference);
    EXPECT_NEAR(result["reference"][direction].get<double>(), reference_mean, 1e-9);
    double deviation = 0.0;
    for (double theta : bumps) {
      deviation += std::fabs(theta - reference_mean) / 5.0;
      // result.runs: the bump runs, cw first, in the order driven.
      const json& run = result["runs"][bump_index++];
      EXPECT_EQ(run["direction"], direction);
      EXPECT_NEAR(run["theta_error_deg"].get<double>(), theta, 1e-9);
      for (const char* key : {"x_mm", "y_mm"}) {
        EXPECT_TRUE(run[key].is_number()) << key;
      }
    }
    EXPECT_NEAR(result[std::string("e_nonsys_") + direction + "_deg"].get<double>(), deviation,
                1e-9);
    figure += deviation;
  }
  EXPECT_EQ(bump_index, result["runs"].size());
  EXPECT_NEAR(result["e_nonsys_deg"].get<double>(), figure, 1e-9);
  // The interval holds the figure.
  EXPECT_LE(result["ci"][0].get<double>(), figure);
  EXPECT_GE(result["ci"][1].get<double>(), figure);
  // Where the simulator laid the cables: as the session told the user (L/20, then every L/10).
  EXPECT_EQ(result["bumps"]["count"], 10);
  EXPECT_NEAR(result["bumps"]["first_mm"].get<double>(), 200.0, 1e-9);
  EXPECT_NEAR(result["bumps"]["spacing_mm"].get<double>(), 400.0, 1e-9);
  EXPECT_NEAR(result["bumps"]["height_mm"].get<double>(), 10.0, 1e-3);
  EXPECT_EQ(result["bumps"]["wheel"], "right");
  EXPECT_NE(r.err.find("Now lay the cables"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("200, 600, 1000"), std::string::npos) << r.err;
  // The figure is what the cables cost: the skid per crossing (2 mrad) and the slip scatter it
  // by well under a degree per run; 5 % of ~40° is generous for them.
  EXPECT_NEAR(figure, cables_alone_deg(10.0), 0.05 * cables_alone_deg(10.0));
}

TEST(SessionExtended, BumpRunsStandOutOfTheBumpFreeScatter) {
  const json& doc = session_10mm();
  ASSERT_TRUE(doc.is_object());
  for (const char* direction : {"cw", "ccw"}) {
    const std::vector<double> reference = heading_errors(doc, direction);
    const std::vector<double> bumps = heading_errors(doc, std::string("bumps-") + direction);
    ASSERT_EQ(bumps.size(), 5u);
    const double reference_mean = mean(reference);
    // The bump-free scatter: the tape measure's 0.4° and the slip.
    const double spread = std::max(sample_sd(reference), 0.1);
    for (double theta : bumps) {
      // Ten crossings of the right wheel turn the robot right by ~20° in either direction.
      EXPECT_LT(theta - reference_mean, -10.0 * spread) << direction;
      EXPECT_NEAR(theta - reference_mean, -0.5 * cables_alone_deg(10.0),
                  0.1 * cables_alone_deg(10.0))
          << direction;
    }
  }
}

TEST(SessionExtended, LowerCablesGiveASmallerFigure) {
  const json& high = session_10mm();
  const json low = extended_session("cables5", robot_5mm);
  ASSERT_TRUE(high.is_object());
  ASSERT_TRUE(low.is_object());
  EXPECT_NEAR(low["result"]["bumps"]["height_mm"].get<double>(), 5.0, 1e-3);
  const double figure_low = low["result"]["e_nonsys_deg"].get<double>();
  const double figure_high = high["result"]["e_nonsys_deg"].get<double>();
  // Disjoint intervals, and each near what its cables cost (14.3° and 39.8°).
  EXPECT_LT(low["result"]["ci"][1].get<double>(), high["result"]["ci"][0].get<double>());
  EXPECT_NEAR(figure_low, cables_alone_deg(5.0), 0.08 * cables_alone_deg(5.0));
  EXPECT_LT(figure_low, figure_high);
}

TEST(SessionExtended, RefusesMeasurementsWithoutHeadingBeforeAnythingMoves) {
  const std::string robot = write("noheading_robot.json", robot_10mm);
  std::string rows = "x_mm,y_mm\n";
  for (int i = 0; i < 8; ++i) {
    rows += "1.0,2.0\n";
  }
  const std::string file = write("noheading.csv", rows);
  const std::string out = temp("noheading_out");
  std::system(("rm -rf " + out).c_str());
  const Result r = shell(bin("odocal") + " session --sim " + robot +
                         " --procedure extended --runs 2 --measurements " + file + " --out " + out +
                         " </dev/null");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("theta_deg"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("heading"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("two marks"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("Run 1/"), std::string::npos) << r.err;  // nothing was driven
  const json doc = read_json(out + "/session.json");
  ASSERT_TRUE(doc.is_object());
  EXPECT_FALSE(doc["complete"].get<bool>());
  EXPECT_TRUE(doc["runs"].empty());

  // A heading missing on one row only is named too.
  rows = "x_mm,y_mm,theta_deg\n";
  for (int i = 0; i < 8; ++i) {
    rows += i == 5 ? "1.0,2.0,\n" : "1.0,2.0,0.5\n";
  }
  const std::string partial = write("partial_heading.csv", rows);
  std::system(("rm -rf " + out).c_str());
  const Result p = shell(bin("odocal") + " session --sim " + robot +
                         " --procedure extended --runs 2 --measurements " + partial + " --out " +
                         out + " </dev/null");
  EXPECT_EQ(p.status, 2);
  EXPECT_NE(p.err.find("measurement row 6"), std::string::npos) << p.err;
  EXPECT_EQ(p.err.find("Run 1/"), std::string::npos) << p.err;
}

/// odocal-sim on a pty, as a robot on a serial port would be.
class CablesSimOnPty {
 public:
  explicit CablesSimOnPty(const std::string& robot) {
    int out[2];
    EXPECT_EQ(::pipe(out), 0);
    pid_ = ::fork();
    if (pid_ == 0) {
      ::dup2(out[1], STDOUT_FILENO);
      ::close(out[0]);
      ::execl(bin("odocal-sim").c_str(), "odocal-sim", "--pty", "--speed", "0", "--robot",
              robot.c_str(), static_cast<char*>(nullptr));
      ::_exit(127);
    }
    ::close(out[1]);
    std::string line;
    char c = 0;
    while (::read(out[0], &c, 1) == 1 && c != '\n') {
      line += c;
    }
    ::close(out[0]);
    const auto at = line.find("/dev/");
    path_ = at == std::string::npos ? "" : line.substr(at);
  }
  ~CablesSimOnPty() {
    ::kill(pid_, SIGTERM);
    int status = 0;
    ::waitpid(pid_, &status, 0);
  }
  CablesSimOnPty(const CablesSimOnPty&) = delete;
  CablesSimOnPty& operator=(const CablesSimOnPty&) = delete;
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  pid_t pid_ = -1;
  std::string path_;
};

TEST(SessionExtended, MeasurementsFromAFileWithHeadingsOnTheSimulator) {
  // The simulator still lays the cables; the figure comes from the file's headings.
  const std::string robot = write("file_robot.json", robot_10mm);
  std::string rows = "# 2 cw, 2 ccw bump-free, then over the cables\nx_mm,y_mm,theta_deg\n";
  const double theta[8] = {1.0, 1.4, -0.5, -0.3, -9.0, -10.0, -11.5, -12.5};
  for (double t : theta) {
    rows += "5.0,-3.0," + std::to_string(t) + "\n";
  }
  const std::string file = write("with_heading.csv", rows);
  const std::string out = temp("file_out");
  std::system(("rm -rf " + out).c_str());
  const Result r = shell(bin("odocal") + " session --sim " + robot +
                         " --procedure extended --runs 2 --side-m 1 --measurements " + file +
                         " --json --out " + out + " </dev/null");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("odocal-sim laid them"), std::string::npos) << r.err;
  const json doc = read_json(out + "/session.json");
  ASSERT_TRUE(doc.is_object());
  const json& result = doc["result"];
  EXPECT_EQ(result["bumps"]["laid_by"], "odocal-sim");
  EXPECT_NEAR(result["bumps"]["first_mm"].get<double>(), 50.0, 1e-9);
  EXPECT_NEAR(result["bumps"]["spacing_mm"].get<double>(), 100.0, 1e-9);
  double figure = 0.0;
  for (int direction = 0; direction < 2; ++direction) {
    // Measured headings against the odometry's, per run (the odometry's from session.json).
    double e[4];
    for (int i = 0; i < 2; ++i) {
      for (int floor = 0; floor < 2; ++floor) {
        const int index = floor * 4 + direction * 2 + i;
        e[floor * 2 + i] = std::remainder(
            theta[index] - doc["runs"][index]["odom"]["theta_deg"].get<double>(), 360.0);
      }
    }
    const double reference = 0.5 * (e[0] + e[1]);
    figure += 0.5 * (std::fabs(e[2] - reference) + std::fabs(e[3] - reference));
  }
  EXPECT_NEAR(result["e_nonsys_deg"].get<double>(), figure, 1e-9);
}

TEST(SessionExtended, SimulatorLaysCablesOnlyWhenAskedRight) {
  const std::string script = write("cables.txt",
                                   "measure cables 200 400 10 right\n"
                                   "measure cables 200 400 10 left 4.5\n"
                                   "measure cables off\n"
                                   "measure cables 200 400\n"
                                   "measure cables 200 400 10 middle\n"
                                   "measure cables 200 -1 10 right\n"
                                   "measure cables 200 400 10 right 31\n"
                                   "measure floor\n"
                                   "measure\n");
  const Result r = shell(bin("odocal-sim") + " <" + script);
  std::vector<std::string> lines;
  std::istringstream in(r.out);
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && line[0] != '#') {
      lines.push_back(line);
    }
  }
  ASSERT_EQ(lines.size(), 9u) << r.out;
  EXPECT_EQ(lines[0],
            "ok cables=10 height_mm=10.000 first_mm=200.000 spacing_mm=400.000 wheel=right");
  EXPECT_EQ(lines[1],
            "ok cables=10 height_mm=4.500 first_mm=200.000 spacing_mm=400.000 wheel=left");
  EXPECT_EQ(lines[2], "ok cables=0");
  EXPECT_EQ(lines[3].rfind("err wrong_arity", 0), 0u) << lines[3];
  EXPECT_EQ(lines[4].rfind("err bad_argument", 0), 0u) << lines[4];
  EXPECT_EQ(lines[5].rfind("err bad_argument", 0), 0u) << lines[5];
  EXPECT_EQ(lines[6].rfind("err bad_argument", 0), 0u) << lines[6];  // above the 30 mm radius
  EXPECT_EQ(lines[7].rfind("err wrong_arity", 0), 0u) << lines[7];
  EXPECT_EQ(lines[8].rfind("ok x_mm=", 0), 0u) << lines[8];
}

TEST(SessionExtended, OnAPortTheUserLaysTheCablesAndIsAskedForAMissingHeading) {
  const std::string robot = write("port_robot.json", robot_10mm);
  CablesSimOnPty sim(robot);
  ASSERT_FALSE(sim.path().empty());
  // Before each run an Enter, then the measurement; run 2 comes without its heading, which is
  // asked for alone (a word first: asked again).
  const std::string typed = write("port_typed.txt",
                                  "\n1 2 0.5\n"
                                  "\n3 4\nabc\n0.7\n"
                                  "\n1 1 -0.2\n"
                                  "\n2 2 0.1\n"
                                  "\n0 0 -19\n"
                                  "\n0 0 -20\n"
                                  "\n0 0 -21\n"
                                  "\n0 0 -20.5\n");
  const std::string out = temp("port_out");
  std::system(("rm -rf " + out).c_str());
  const Result r =
      shell(bin("odocal") + " session --port " + sim.path() +
            " --procedure extended --runs 2 --side-m 1 --json --out " + out + " <" + typed);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("two marks"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Heading of run 2 (cw)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Not taken: 'abc'"), std::string::npos) << r.err;
  // The user lays the cables, told where before the first run over them; a robot on a port is
  // never sent the simulator's floor command.
  const auto lay = r.err.find("Now lay the cables");
  ASSERT_NE(lay, std::string::npos) << r.err;
  EXPECT_LT(lay, r.err.find("Run 5/8 (bumps-cw)"));
  EXPECT_GT(lay, r.err.find("Run 4/8: ccw"));
  EXPECT_NE(r.err.find("50, 150, 250, 350, 450, 550, 650, 750, 850, 950"), std::string::npos);
  EXPECT_EQ(r.err.find("laid them"), std::string::npos) << r.err;
  const json doc = read_json(out + "/session.json");
  ASSERT_TRUE(doc.is_object());
  EXPECT_EQ(doc["result"]["bumps"]["laid_by"], "you");
  EXPECT_EQ(doc["runs"][1]["measured"]["theta_deg"].get<double>(), 0.7);
  EXPECT_FALSE(doc["applied"].get<bool>());
  // Nothing typed is lost: the late heading is in the journal too.
  std::ifstream journal(out + "/measurements.csv");
  std::stringstream rows;
  rows << journal.rdbuf();
  EXPECT_NE(rows.str().find("\n2,3.000,4.000,0.700\n"), std::string::npos) << rows.str();
  // The figure from the typed headings, by hand: |bump − mean(reference)| per direction.
  double figure = 0.0;
  for (int direction = 0; direction < 2; ++direction) {
    double e[4];
    for (int i = 0; i < 4; ++i) {
      const int index = (i / 2) * 4 + direction * 2 + i % 2;
      const json& run = doc["runs"][index];
      e[i] = std::remainder(
          run["measured"]["theta_deg"].get<double>() - run["odom"]["theta_deg"].get<double>(),
          360.0);
    }
    const double reference = 0.5 * (e[0] + e[1]);
    figure += 0.5 * (std::fabs(e[2] - reference) + std::fabs(e[3] - reference));
  }
  EXPECT_NEAR(doc["result"]["e_nonsys_deg"].get<double>(), figure, 1e-9);
}

}  // namespace
