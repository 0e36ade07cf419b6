// The extended UMBmark (`odocal sim extended`): its figure against the definition computed by hand
// from the runs, the cables' effect against the physics of one wheel rolling over them, and the
// figure's response to larger cables and to more slip; the command line's contract.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "odocal/host/sim_procedures.hpp"

namespace odocal::host {
namespace {

constexpr double pi = 3.14159265358979323846;

double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v)
    s += x;
  return s / static_cast<double>(v.size());
}

double sample_variance(const std::vector<double>& v) {
  const double m = mean(v);
  double s = 0.0;
  for (double x : v)
    s += (x - m) * (x - m);
  return s / static_cast<double>(v.size() - 1);
}

std::vector<double> headings(const std::vector<ExtendedRun>& runs, bool clockwise) {
  std::vector<double> out;
  for (const ExtendedRun& r : runs) {
    if (r.clockwise == clockwise)
      out.push_back(r.theta_error_deg);
  }
  return out;
}

/// Wheel travel lost on one cable of height h by a wheel of radius r: the arc 2(r+c)·acos((r−c)/
/// (r+c)) it turns through against the chord 4·sqrt(r·c) it covers, c = h/2.
double loss_per_cable_m(double r, double h) {
  const double c = 0.5 * h;
  return 2.0 * (r + c) * std::acos((r - c) / (r + c)) - 4.0 * std::sqrt(r * c);
}

ExtendedReport run(const RobotSpec& robot, std::uint64_t seed, double height_m = 0.0) {
  ExtendedOptions o;
  o.bump_height_m = height_m;
  ExtendedReport r = run_extended(robot, seed, o);
  EXPECT_TRUE(r.ok) << r.error;
  return r;
}

TEST(ExtendedUmbmark, FigureIsTheDefinitionComputedByHandFromTheRuns) {
  const ExtendedReport r = run(default_robot(), 3u);
  ASSERT_EQ(r.reference.size(), 10u);
  ASSERT_EQ(r.bump_runs.size(), 10u);
  double figure = 0.0;
  for (const bool cw : {true, false}) {
    const double reference = mean(headings(r.reference, cw));
    double sum = 0.0;
    const std::vector<double> bumps = headings(r.bump_runs, cw);
    ASSERT_EQ(bumps.size(), 5u);
    for (double theta : bumps)
      sum += std::fabs(theta - reference);
    figure += sum / 5.0;
    EXPECT_NEAR(cw ? r.figure.reference_cw_deg : r.figure.reference_ccw_deg, reference, 1e-12);
  }
  EXPECT_NEAR(r.figure.e_nonsys_deg, figure, 1e-12);
  EXPECT_NEAR(r.figure.e_cw_deg + r.figure.e_ccw_deg, r.figure.e_nonsys_deg, 1e-12);
  EXPECT_LE(r.figure.ci_lo_deg, r.figure.e_nonsys_deg);
  EXPECT_GE(r.figure.ci_hi_deg, r.figure.e_nonsys_deg);
  // The JSON holds the same numbers under the contract's keys.
  const nlohmann::json j = extended_report_json(r);
  EXPECT_DOUBLE_EQ(j.at("e_nonsys_deg").get<double>(), r.figure.e_nonsys_deg);
  EXPECT_DOUBLE_EQ(j.at("reference").at("cw").get<double>(), r.figure.reference_cw_deg);
  EXPECT_DOUBLE_EQ(j.at("reference").at("ccw").get<double>(), r.figure.reference_ccw_deg);
  ASSERT_EQ(j.at("runs").size(), 10u);
  EXPECT_EQ(j.at("runs")[0].at("direction"), "cw");
  EXPECT_EQ(j.at("runs")[9].at("direction"), "ccw");
  EXPECT_DOUBLE_EQ(j.at("runs")[2].at("theta_error_deg").get<double>(),
                   r.bump_runs[2].theta_error_deg);
  EXPECT_GT(j.at("simulated_s").get<double>(), 20 * 16.0 / 0.2);  // 20 squares of 16 m at 0.2 m/s
}

TEST(ExtendedUmbmark, SameSeedSameReport) {
  EXPECT_EQ(extended_report_json(run(default_robot(), 7u)).dump(),
            extended_report_json(run(default_robot(), 7u)).dump());
}

TEST(ExtendedUmbmark, BumpRunsStandOutOfTheBumpFreeScatterByTheLostTravelOfOneWheel) {
  const RobotSpec robot = default_robot();
  const ExtendedReport r = run(robot, 5u);
  // Ten 10 mm cables under the right wheel: it rolls 10 arcs but covers 10 chords, so the robot
  // turns right (clockwise) by 10·loss/b while the encoders see nothing of it. The heading error
  // (measured minus odometry) of every bump run is that much below the bump-free average.
  const double loss = loss_per_cable_m(0.5 * robot.truth.right_diameter_m, 0.010);
  const double expected_deg = -10.0 * loss / robot.truth.wheelbase_m * 180.0 / pi;
  ASSERT_LT(expected_deg, -15.0);  // ~19.9° for this robot
  for (const bool cw : {true, false}) {
    const std::vector<double> reference = headings(r.reference, cw);
    const std::vector<double> bumps = headings(r.bump_runs, cw);
    for (const ExtendedRun& run : r.bump_runs) {
      EXPECT_EQ(run.bumps_crossed, 10u);  // every cable, by one wheel only
    }
    for (const ExtendedRun& run : r.reference) {
      EXPECT_EQ(run.bumps_crossed, 0u);
    }
    // Out of the scatter: each bump run lies more than 6 bump-free standard deviations (of one
    // run, and of their mean) from the bump-free average.
    const double sd = std::sqrt(sample_variance(reference) * (1.0 + 1.0 / 5.0));
    for (double theta : bumps) {
      EXPECT_GT(std::fabs(theta - mean(reference)), 6.0 * sd) << (cw ? "cw" : "ccw");
    }
    // And by the physics: the mean shift equals the lost travel's turn within 4 standard errors
    // of the two means (the skid at each cable and the slip make the scatter).
    const double se = std::sqrt(sample_variance(reference) / 5.0 + sample_variance(bumps) / 5.0);
    EXPECT_NEAR(mean(bumps) - mean(reference), expected_deg,
                4.0 * se + 0.01 * std::fabs(expected_deg))
        << (cw ? "cw" : "ccw");
  }
}

TEST(ExtendedUmbmark, LargerCablesGiveALargerFigure) {
  const RobotSpec robot = default_robot();
  double previous = 0.0;
  double previous_sd = 0.0;
  for (const double height : {0.004, 0.008, 0.012}) {
    const ExtendedReport r = run(robot, 11u, height);
    // Its size: two directions of 10 cables' lost travel (the slip adds a little).
    const double loss = loss_per_cable_m(0.5 * robot.truth.right_diameter_m, height);
    const double expected = 2.0 * 10.0 * loss / robot.truth.wheelbase_m * 180.0 / pi;
    EXPECT_NEAR(r.figure.e_nonsys_deg, expected, 4.0 * r.figure.sd_deg + 0.02 * expected) << height;
    if (previous > 0.0) {
      EXPECT_GT(r.figure.e_nonsys_deg - previous, 4.0 * std::hypot(r.figure.sd_deg, previous_sd))
          << height;
    }
    previous = r.figure.e_nonsys_deg;
    previous_sd = r.figure.sd_deg;
  }
}

TEST(ExtendedUmbmark, MoreSlipGivesALargerFigure) {
  // Low cables (2 mm: ~1.7° per direction) so that the random part can show: with slip the bump
  // runs scatter about the bump-free average, and the average absolute deviation grows. Several
  // seeds per slip level; the difference of the means must exceed 4 of its standard errors.
  std::vector<double> figures[2];
  const double slips[2] = {5.0e-4, 1.0e-2};
  for (int level = 0; level < 2; ++level) {
    RobotSpec robot = default_robot();
    robot.truth.slip_sigma = slips[level];
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
      figures[level].push_back(run(robot, seed, 0.002).figure.e_nonsys_deg);
    }
  }
  const double difference = mean(figures[1]) - mean(figures[0]);
  const double se =
      std::sqrt(sample_variance(figures[0]) / 6.0 + sample_variance(figures[1]) / 6.0);
  EXPECT_GT(difference, 4.0 * se) << mean(figures[0]) << " vs " << mean(figures[1]);
}

TEST(ExtendedUmbmark, RobotFileBumpHeightReplacesThePublishedTenMillimetres) {
  RobotSpec robot = default_robot();
  EXPECT_NEAR(run(robot, 2u).bump_height_m, 0.010, 1e-15);
  robot.truth.bump_height_m = 0.006;
  const ExtendedReport r = run(robot, 2u);
  EXPECT_NEAR(r.bump_height_m, 0.006, 1e-15);
  // Laid as published whatever the robot file's spacing: 10 along the 4 m leg.
  EXPECT_NEAR(r.bump_first_m, 0.2, 1e-12);
  EXPECT_NEAR(r.bump_spacing_m, 0.4, 1e-12);
}

// --- the command line --------------------------------------------------------------------------

std::string odocal_binary() {
  const char* bin = std::getenv("ODOCAL_BIN_DIR");
  const std::string odocal = bin != nullptr ? std::string(bin) + "/odocal" : "";
  return odocal.empty() || !std::ifstream(odocal) ? std::string() : odocal;
}

int run_command(const std::string& command, std::string& out, std::string& err) {
  const std::string tag = std::to_string(::getpid());
  const std::string out_file = ::testing::TempDir() + "odocal_ext_out_" + tag + ".txt";
  const std::string err_file = ::testing::TempDir() + "odocal_ext_err_" + tag + ".txt";
  const int status = std::system((command + " >" + out_file + " 2>" + err_file).c_str());
  std::ifstream o(out_file);
  out.assign(std::istreambuf_iterator<char>(o), std::istreambuf_iterator<char>());
  std::ifstream e(err_file);
  err.assign(std::istreambuf_iterator<char>(e), std::istreambuf_iterator<char>());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(OdocalSimExtended, JsonHoldsTheContractKeysAndTheFigureOfItsRuns) {
  const std::string odocal = odocal_binary();
  if (odocal.empty()) {
    FAIL() << "odocal not built (cmake --build --preset host builds it)";
  }
  std::string out, err;
  ASSERT_EQ(run_command(odocal + " sim extended --seed 4 --json", out, err), 0) << err;
  const nlohmann::json j = nlohmann::json::parse(out);
  for (const char* key : {"e_nonsys_deg", "runs", "reference", "simulated_s"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  ASSERT_EQ(j["runs"].size(), 10u);
  double figure = 0.0;
  for (const char* direction : {"cw", "ccw"}) {
    const double reference = j["reference"][direction].get<double>();
    double sum = 0.0;
    int n = 0;
    for (const auto& run : j["runs"]) {
      for (const char* key : {"direction", "theta_error_deg", "x_mm", "y_mm"}) {
        ASSERT_TRUE(run.contains(key)) << key;
      }
      if (run["direction"] == direction) {
        sum += std::fabs(run["theta_error_deg"].get<double>() - reference);
        ++n;
      }
    }
    ASSERT_EQ(n, 5);
    figure += sum / n;
  }
  EXPECT_NEAR(j["e_nonsys_deg"].get<double>(), figure, 1e-9 * figure);
  // Same seed, same output.
  std::string again;
  ASSERT_EQ(run_command(odocal + " sim extended --seed 4 --json", again, err), 0) << err;
  EXPECT_EQ(out, again);
}

TEST(OdocalSimExtended, BadInputExitsTwoNamingWhatIsWrong) {
  const std::string odocal = odocal_binary();
  if (odocal.empty()) {
    FAIL() << "odocal not built (cmake --build --preset host builds it)";
  }
  std::string out, err;
  EXPECT_EQ(run_command(odocal + " sim extended --runs 1", out, err), 2);
  EXPECT_NE(err.find("--runs"), std::string::npos) << err;
  EXPECT_EQ(run_command(odocal + " sim extended --side-mm 5", out, err), 2);
  EXPECT_NE(err.find("--side-mm"), std::string::npos) << err;
  const std::string robot = ::testing::TempDir() + "extended_bad_robot.json";
  std::ofstream(robot) << R"({"bump_heigth_mm": 10})";
  EXPECT_EQ(run_command(odocal + " sim extended --robot " + robot, out, err), 2);
  EXPECT_NE(err.find("bump_heigth_mm"), std::string::npos) << err;
  EXPECT_TRUE(out.empty()) << out;
}

}  // namespace
}  // namespace odocal::host
