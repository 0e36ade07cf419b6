// `odocal fit`: reading tick logs, recovering a known geometry, refusing what the data cannot
// determine, and the bootstrap's intervals — on hand-made logs and on the simulated robot.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "odocal/calib/random.hpp"
#include "odocal/host/csv.hpp"
#include "odocal/host/fit.hpp"
#include "odocal/host/sim_procedures.hpp"
#include "synthetic_logs.hpp"

namespace odocal::host {
namespace {

constexpr double pi = synthetic::pi;
using synthetic::line;
using synthetic::make_log;
using synthetic::Move;
using synthetic::square;
using synthetic::Truth;
using synthetic::Truthing;
using synthetic::turn;

FitNominal nominal_for(const Truth& t) {
  return FitNominal{60.0, 150.0, t.counts_per_rev};
}

void expect_recovered(const FitResult& r, const Truth& t, double tolerance) {
  EXPECT_NEAR(r.geometry.wheel_diameter_left_mm / t.left_mm, 1.0, tolerance);
  EXPECT_NEAR(r.geometry.wheel_diameter_right_mm / t.right_mm, 1.0, tolerance);
  EXPECT_NEAR(r.geometry.wheelbase_mm / t.wheelbase_mm, 1.0, tolerance);
}

TEST(FitGeometry, RecoversAKnownRobotFromMotionCaptureAwayFromTheOriginWithUnwrappedHeading) {
  const Truth t;
  // Three ccw loops (heading past 1000°), started at (500, -200) facing 30°.
  std::vector<Move> moves;
  for (int k = 0; k < 3; ++k) {
    for (const Move& m : square(t, 1000.0, false)) {
      moves.push_back(m);
    }
  }
  const TickLog log = make_log(t, moves, Truthing::path, 500.0, -200.0, 30.0);
  ASSERT_GT(log.rows.size(), 3000u);
  FitOptions options;
  options.replicates = 20;
  const FitOutcome out = fit_geometry({log}, nominal_for(t), options);
  ASSERT_TRUE(out) << out.error.message;
  // Exact data: only the counts' rounding and floating point remain.
  expect_recovered(*out.result, t, 1e-7);
  EXPECT_NEAR(out.result->c_l, t.left_mm / 60.0, 1e-7);
  EXPECT_NEAR(out.result->e_d, t.right_mm / t.left_mm, 1e-7);
  EXPECT_NEAR(out.result->e_b, t.wheelbase_mm / 150.0, 1e-7);
  EXPECT_LT(out.result->fit.path_rms_after_mm, 1e-3);
  EXPECT_GT(out.result->fit.path_rms_before_mm, 1e3 * out.result->fit.path_rms_after_mm);
  // One run, cut into pieces for the bootstrap.
  EXPECT_GE(out.result->bootstrap_units, 6u);
  ASSERT_TRUE(out.result->ci_wheelbase_mm.has_value());
  EXPECT_LE(out.result->ci_wheelbase_mm->lo, out.result->geometry.wheelbase_mm + 1e-6);
  EXPECT_GE(out.result->ci_wheelbase_mm->hi, out.result->geometry.wheelbase_mm - 1e-6);
}

TEST(FitGeometry, CopesWithSparseTruthFractionalCountsAndReversing) {
  Truth t;
  t.counts_per_rev = 1234.5;
  // Forward, turn, back up (counts fall), turn the other way; truth in every third row only.
  const std::vector<Move> a = {line(800.0),  turn(pi / 2, t), line(-600.0),
                               turn(-pi, t), line(500.0),     Move{300.0, 100.0, 200}};
  const std::vector<Move> b = {Move{-200.0, 400.0, 300}, line(-900.0), turn(2.5 * pi, t)};
  FitOptions options;
  options.replicates = 0;
  const FitOutcome out =
      fit_geometry({make_log(t, a, Truthing::every_third_row, 10.0, 20.0, -170.0),
                    make_log(t, b, Truthing::every_third_row, 0.0, 0.0, 179.0)},
                   nominal_for(t), options);
  ASSERT_TRUE(out) << out.error.message;
  expect_recovered(*out.result, t, 1e-7);
  EXPECT_FALSE(out.result->ci_left_mm.has_value());  // B = 0: no intervals
}

TEST(FitGeometry, TapeMeasureRunsOfLinesAndSquaresDetermineEverything) {
  const Truth t;
  std::vector<TickLog> logs;
  for (int i = 0; i < 3; ++i) {
    logs.push_back(make_log(t, {line(2000.0)}, Truthing::end_only));
    logs.push_back(make_log(t, square(t, 1500.0, i % 2 == 0), Truthing::end_only));
  }
  logs.push_back(make_log(t, square(t, 1500.0, false), Truthing::end_xy_only));
  FitOptions options;
  options.replicates = 50;
  const FitOutcome out = fit_geometry(logs, nominal_for(t), options, {logs.front()});
  ASSERT_TRUE(out) << out.error.message;
  expect_recovered(*out.result, t, 1e-6);
  ASSERT_TRUE(out.result->holdout.has_value());
  EXPECT_EQ(out.result->holdout->runs, 1u);
  EXPECT_EQ(out.result->fit.runs, 7u);
  // End-only runs: the end and path figures are the same rows.
  EXPECT_NEAR(out.result->fit.end_rms_before_mm, out.result->fit.path_rms_before_mm, 1e-9);
  EXPECT_GT(out.result->fit.end_rms_before_mm, 20.0);
}

TEST(FitGeometry, StraightLinesAloneCannotDetermineTheWheelbase) {
  const Truth t;
  std::vector<TickLog> logs;
  for (int i = 0; i < 4; ++i) {
    logs.push_back(make_log(t, {line(2000.0)}, Truthing::end_only));
    logs.push_back(make_log(t, {line(1500.0), line(-1500.0)}, Truthing::path));
  }
  const FitOutcome out = fit_geometry(logs, nominal_for(t), FitOptions{});
  ASSERT_FALSE(out);
  EXPECT_EQ(out.error.parameter, "wheelbase_mm");
  EXPECT_NE(out.error.message.find("wheelbase_mm"), std::string::npos) << out.error.message;
}

TEST(FitGeometry, ClosedLoopsMeasuredOnlyAtTheEndCannotDetermineTheScale) {
  const Truth t;
  std::vector<TickLog> logs;
  for (int i = 0; i < 6; ++i) {
    logs.push_back(make_log(t, square(t, 2000.0, i % 2 == 0), Truthing::end_only));
  }
  const FitOutcome out = fit_geometry(logs, nominal_for(t), FitOptions{});
  ASSERT_FALSE(out);
  EXPECT_EQ(out.error.parameter, "scale");
  EXPECT_NE(out.error.message.find("scale"), std::string::npos);
  EXPECT_NE(out.error.message.find("wheel_diameter"), std::string::npos);
  // The same loops with the truth along the path determine it.
  logs.push_back(make_log(t, square(t, 2000.0, true), Truthing::path));
  EXPECT_TRUE(fit_geometry(logs, nominal_for(t), FitOptions{}));
}

TEST(FitGeometry, CopesWithWhatRealLogsHold) {
  // A motion-capture log as public data sets give it once converted to the tick-log header:
  // UNIX time stamps, counts that start far from zero, headings wrapped to ±180° at every row,
  // the robot at rest for the first second (the capture jittering), dropouts (rows and a whole
  // second without truth, rows with only the heading), and thousands of rows.
  Truth t;
  t.counts_per_rev = 2469.6;                     // 51.45:1 gearbox on a 12-count encoder at x4
  std::vector<Move> moves{Move{0.0, 0.0, 100}};  // at rest
  for (const Move& m : square(t, 1200.0, false)) {
    moves.push_back(m);
  }
  moves.push_back(Move{900.0, 300.0, 600});
  moves.push_back(turn(-3.0 * pi, t));
  TickLog log = make_log(t, moves, Truthing::path, 2500.0, -1300.0, 135.0);
  ASSERT_GT(log.rows.size(), 3000u);
  calib::Random random(7u);
  const auto normal = [&] {
    // Sum of 12 uniforms: mean 6, variance 1.
    double sum = 0.0;
    for (int i = 0; i < 12; ++i) {
      sum += random.uniform();
    }
    return sum - 6.0;
  };
  constexpr double jitter_mm = 0.3, jitter_deg = 0.1;  // a motion-capture system's scatter
  for (std::size_t i = 0; i < log.rows.size(); ++i) {
    TickRow& row = log.rows[i];
    row.t_s += 1.7e9;
    row.count_l += 123456789.0;
    row.count_r -= 987654.0;
    row.x_mm += jitter_mm * normal();
    row.y_mm += jitter_mm * normal();
    row.theta_deg = std::remainder(row.theta_deg + jitter_deg * normal(), 360.0);
    const bool gap = i > 1500 && i < 1600;
    if (i > 0 && (gap || random.below(10) == 0)) {
      row.has_xy = false;
      row.has_theta = row.has_theta && !gap && random.below(2) == 0;
    }
  }
  // Through the file: the reader takes what the writer wrote (17 digits of UNIX time).
  std::ostringstream text;
  write_tick_log(log, text);
  const std::string path = ::testing::TempDir() + "fit_real_shape.csv";
  std::ofstream(path, std::ios::binary) << text.str();
  const TickLog read = read_tick_log(path);
  ASSERT_EQ(read.rows.size(), log.rows.size());
  FitOptions options;
  options.replicates = 100;
  const FitOutcome out = fit_geometry({read}, nominal_for(t), options);
  ASSERT_TRUE(out) << out.error.message;
  // The jitter (0.3 mm over paths of metres, averaged over thousands of rows, the start pose over
  // the rows at rest) leaves well under 1e-4 of each parameter; without the averaging, 0.1° of
  // start heading alone would bend a 6 m path by 10 mm.
  expect_recovered(*out.result, t, 1e-4);
  ASSERT_TRUE(out.result->ci_wheelbase_mm.has_value());
  EXPECT_LE(out.result->ci_wheelbase_mm->lo, t.wheelbase_mm);
  EXPECT_GE(out.result->ci_wheelbase_mm->hi, t.wheelbase_mm);
}

TEST(FitGeometry, WheelTravelGivenAsTurnsOrDistanceFitsAlike) {
  // Some public data sets log each wheel's travel (turns, or metres for a nominal wheel) instead
  // of counts: as fractional "counts" with counts_per_rev 1 (turns) the fit is the same.
  const Truth t;
  std::vector<Move> moves = square(t, 1000.0, true);
  moves.push_back(line(1500.0));
  const TickLog counts = make_log(t, moves, Truthing::path, 300.0, 400.0, -60.0);
  TickLog turns = counts;
  for (TickRow& row : turns.rows) {
    row.count_l /= t.counts_per_rev;
    row.count_r /= t.counts_per_rev;
  }
  std::ostringstream text;
  write_tick_log(turns, text);
  const std::string path = ::testing::TempDir() + "fit_turns.csv";
  std::ofstream(path, std::ios::binary) << text.str();
  FitOptions options;
  options.replicates = 0;
  const FitOutcome a = fit_geometry({counts}, nominal_for(t), options);
  const FitOutcome b = fit_geometry({read_tick_log(path)}, FitNominal{60.0, 150.0, 1.0}, options);
  ASSERT_TRUE(a && b) << a.error.message << b.error.message;
  EXPECT_NEAR(b.result->geometry.wheel_diameter_left_mm, a.result->geometry.wheel_diameter_left_mm,
              1e-9 * t.left_mm);
  EXPECT_NEAR(b.result->geometry.wheelbase_mm, a.result->geometry.wheelbase_mm,
              1e-9 * t.wheelbase_mm);
  expect_recovered(*b.result, t, 1e-7);
}

TEST(FitGeometry, OneTapeMeasureRunGivesTheGeometryWithoutIntervals) {
  // A loop measured at its end in x, y and heading: three numbers for three parameters, enough
  // when it turns and travels (a 1.5 m side, then half a turn more) but no scatter between runs.
  const Truth t;
  std::vector<Move> moves = square(t, 1500.0, false);
  moves.push_back(line(2500.0));
  moves.push_back(turn(pi, t));
  const FitOutcome out =
      fit_geometry({make_log(t, moves, Truthing::end_only)}, nominal_for(t), FitOptions{});
  ASSERT_TRUE(out) << out.error.message;
  EXPECT_FALSE(out.result->ci_left_mm.has_value());
  EXPECT_EQ(out.result->replicates, 0u);
  EXPECT_NE(fit_result_text(*out.result).find("single run"), std::string::npos);
}

// ------------------------------------------------------------------------------ reading logs

std::string write_file(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

/// The InputError read_tick_log throws for `text`, or "" when it reads.
std::string read_error(const std::string& text, std::size_t& line, std::string& field) {
  const std::string path = write_file("fit_log.csv", text);
  try {
    static_cast<void>(read_tick_log(path));
  } catch (const InputError& e) {
    line = e.line();
    field = e.field();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
    return e.what();
  }
  return "";
}

TEST(TickLog, ReadsBothHeadersWithBomCrlfCommentsAndEmptyTruthCells) {
  const std::string path = write_file(
      "fit_ok.csv",
      "\xEF\xBB\xBFt_s,count_l,count_r,x_mm,y_mm,theta_deg\r\n# comment\r\n0,0,0,1.5,2,370\r\n"
      "0.01,10,12,,,\r\n0.02,20,24,3,4,\r\n0.03,30,36,,,-190.5\r\n");
  const TickLog log = read_tick_log(path);
  ASSERT_EQ(log.rows.size(), 4u);
  EXPECT_TRUE(log.rows[0].has_xy && log.rows[0].has_theta);
  EXPECT_DOUBLE_EQ(log.rows[0].theta_deg, 370.0);
  EXPECT_FALSE(log.rows[1].has_xy || log.rows[1].has_theta);
  EXPECT_TRUE(log.rows[2].has_xy && !log.rows[2].has_theta);
  EXPECT_TRUE(!log.rows[3].has_xy && log.rows[3].has_theta);
  EXPECT_EQ(log.rows[3].line, 6u);  // header, comment, then the rows from line 3
  // A logger may stamp two rows alike: time must only not go back.
  EXPECT_NO_THROW(static_cast<void>(
      read_tick_log(write_file("fit_same_t.csv",
                               "t_s,count_l,count_r,x_mm,y_mm,theta_deg\n0,0,0,,,\n0,1,1,,,\n"
                               "0.1,5,5,1,0,0\n"))));
}

TEST(TickLog, BadInputIsRefusedNamingLineAndField) {
  struct Case {
    const char* text;
    std::size_t line;
    const char* field;
    const char* says;
  };
  const Case cases[] = {
      {"0,0,0\n0.1,5,5\n", 1, "0", "unknown or misplaced column"},
      {"", 1, "t_s", "missing header"},
      {"t_s,count_l,count_r,x_mm,y_mm,theta_deg,extra\n0,0,0,,,\n", 1, "extra", "unknown"},
      {"t_s,count_l,count_r,x_mm,y_mm,heading\n0,0,0,,,\n", 1, "heading", "unknown"},
      {"t_s,count_r,count_l\n0,0,0\n", 1, "count_r", "misplaced"},
      {"t_s,count_l,count_r,x_mm,y_mm,theta_deg\n0,0,0,,,\n0.1,5x,5,10,0,0\n", 3, "count_l",
       "not a number"},
      {"t_s,count_l,count_r,x_mm,y_mm,theta_deg\n0,0,0,,,\n0.1,5,5,nan,0,0\n", 3, "x_mm", "finite"},
      {"t_s,count_l,count_r,x_mm,y_mm,theta_deg\n0,0,0,,,\n0.1,5,5,10,0\n", 3, "theta_deg",
       "fields"},
      {"t_s,count_l,count_r,x_mm,y_mm,theta_deg\n0.2,0,0,,,\n0.1,5,5,10,0,0\n", 3, "t_s",
       "backwards"},
      {"t_s,count_l,count_r,x_mm,y_mm,theta_deg\n0,0,0,,,\n", 2, "t_s", "too few rows"},
      {"t_s,count_l,count_r,x_mm,y_mm,theta_deg\n0,0,0,,,\n0.1,5,5,10,,0\n", 3, "y_mm", "together"},
      {"t_s,count_l,count_r,x_mm,y_mm,theta_deg\n0,0,0,1,2,\n0.1,5,5,10,0,0\n", 2, "theta_deg",
       "start pose"},
      {"t_s,count_l,count_r,x_mm,y_mm,theta_deg\n0,0,0,,,\n0.1,5,5,,,\n", 3, "x_mm",
       "no ground truth"},
      {"t_s,count_l,count_r\n0,0,0\n0.1,5,5\n", 3, "x_mm", "no ground truth"},
      {"t_s,count_l,count_r,x_mm,y_mm,theta_deg\n0,0,0,,,\n0.1,5,5,1e300,0,0\n", 3, "x_mm",
       "absurd"},
      {"t_s,count_l,count_r,x_mm,y_mm,theta_deg\n1.7e18,0,0,,,\n1.8e18,5,5,1,0,0\n", 2, "t_s",
       "nanosecond"},
      {"t_s,count_l,count_r,x_mm,y_mm,theta_deg\n0,0,0,,,\n4e7,5,5,1,0,0\n", 3, "t_s",
       "more than a year"},
  };
  for (const Case& c : cases) {
    std::size_t line = 0;
    std::string field;
    const std::string error = read_error(c.text, line, field);
    ASSERT_FALSE(error.empty()) << c.text;
    EXPECT_NE(error.find(c.says), std::string::npos) << c.text << " -> " << error;
    if (std::string(c.field) != "0") {
      EXPECT_EQ(field, c.field) << error;
    }
    EXPECT_EQ(line, c.line) << error;
  }
  std::size_t line = 0;
  std::string field;
  EXPECT_NE(read_error("", line, field), "");
  try {
    static_cast<void>(read_tick_log("/nonexistent/log.csv"));
    ADD_FAILURE() << "a missing file must be an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot open"), std::string::npos);
  }
}

// --------------------------------------------------------------------- the simulated robot

RobotSpec hidden_robot(std::uint64_t seed) {
  calib::Random random(seed);
  RobotSpec spec = default_robot();
  spec.truth.left_diameter_m = 0.060 * (1.0 + 0.005 * (2.0 * random.uniform() - 1.0));
  spec.truth.right_diameter_m = 0.060 * (1.0 + 0.005 * (2.0 * random.uniform() - 1.0));
  spec.truth.wheelbase_m = 0.150 * (1.0 + 0.02 * (2.0 * random.uniform() - 1.0));
  return spec;
}

FitNominal nominal_of(const RobotSpec& spec) {
  return FitNominal{static_cast<double>(spec.nominal.wheel_diameter_mm),
                    static_cast<double>(spec.nominal.wheelbase_mm),
                    static_cast<double>(spec.nominal.counts_per_rev)};
}

/// Lines and squares driven with the real firmware, logged with the truth `truth` asks for.
std::vector<TickLog> drive_runs(const RobotSpec& spec, std::uint64_t seed, LogTruth truth,
                                int lines, int squares, double side_m, std::uint32_t period_ms) {
  SimulatedRobot robot(spec, seed);
  std::vector<TickLog> logs;
  for (int i = 0; i < lines + 2 * squares; ++i) {
    const drive::Path path =
        i < lines ? drive::make_line(2.0f)
                  : drive::make_umbmark_square((i - lines) % 2 == 0, static_cast<float>(side_m));
    TickLog log;
    log.source = "sim run " + std::to_string(i + 1);
    const RunOutcome out = run_path_logged(robot, path, log, truth, period_ms);
    EXPECT_TRUE(out.completed);
    check_tick_log(log);
    logs.push_back(std::move(log));
  }
  return logs;
}

TEST(FitSimulated, MotionCaptureOfAHiddenRobotRecoversItsGeometry) {
  const RobotSpec spec = hidden_robot(11u);
  const std::vector<TickLog> logs = drive_runs(spec, 5u, LogTruth::path, 2, 1, 1.5, 20u);
  FitOptions options;
  options.replicates = 0;
  const FitOutcome out = fit_geometry(logs, nominal_of(spec), options);
  ASSERT_TRUE(out) << out.error.message;
  const sim::RobotModel& t = spec.truth;
  // The targets: the diameter ratio within 1e-4, the wheelbase within 1e-3 (relative).
  // Slip (σ 5e-4 per 5 cm, zero mean) averages over some 20 m of wheel travel to ~1e-5.
  EXPECT_NEAR(out.result->e_d, t.right_diameter_m / t.left_diameter_m, 1e-4);
  EXPECT_NEAR(out.result->geometry.wheelbase_mm / (t.wheelbase_m * 1e3), 1.0, 1e-3);
  EXPECT_NEAR(out.result->geometry.wheel_diameter_left_mm / (t.left_diameter_m * 1e3), 1.0, 1e-3);
  EXPECT_LT(out.result->fit.path_rms_after_mm, 0.2 * out.result->fit.path_rms_before_mm);
}

}  // namespace
}  // namespace odocal::host
