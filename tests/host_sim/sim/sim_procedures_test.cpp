// End-to-end: the firmware control loop on the simulated robot, through the procedures.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "odocal/host/sim_procedures.hpp"
#include "odocal/host/sim_robot.hpp"

namespace odocal::host {
namespace {

constexpr double pi = 3.14159265358979323846;

RobotSpec robot_with_errors(double e_d, double wheelbase_mm) {
  RobotSpec spec = default_robot();
  // Mean diameter kept at the nominal 60 mm so E_b is the wheelbase ratio alone.
  spec.truth.left_diameter_m = 0.060 * 2.0 / (1.0 + e_d);
  spec.truth.right_diameter_m = 0.060 * 2.0 * e_d / (1.0 + e_d);
  spec.truth.wheelbase_m = wheelbase_mm * 1e-3;
  return spec;
}

TEST(SimUmbmark, CalibrationRecoversKnownErrorsAndImprovesTheRobot) {
  constexpr double e_d = 1.003;          // D_R/D_L
  constexpr double e_b = 148.5 / 150.0;  // true over nominal wheelbase: 0.99
  const RobotSpec spec = robot_with_errors(e_d, 148.5);
  UmbmarkOptions options;  // 4 m square, 5 + 5 runs, as the paper
  const UmbmarkReport report = run_umbmark(spec, 7u, options);
  ASSERT_TRUE(report.ok) << report.error;
  // Before: E_d bends each 4 m leg by β ≈ (E_d − 1)·L/b = 0.08 rad and E_b turns each corner
  // α = 0.9° short; the return errors are hundreds of mm.
  const UmbmarkPass& before = report.passes.front();
  EXPECT_GT(before.result.e_max_syst_mm, 300.0);
  // Where they are: the runs return where a robot with these errors must, by the square's exact
  // geometry (calib::square_return_error: each leg and corner driven until odometry says it is
  // done), up to the run-to-run scatter. The scatter (slip, 2 mm measurement) is σ ≤ 20 mm
  // radially (20-run passes of this robot, seeds 7-9: σ 16-18 mm, centres within 2 mm of the
  // model), so a centre of gravity of 5 runs lies within 3·σ/√5 = 27 mm of it. A robot that
  // missed either error would be far off: without E_b the cw centre is ~180 mm away, without E_d
  // ~800 mm.
  const double cg_bound_mm = 3.0 * 20.0 / std::sqrt(static_cast<double>(options.runs));
  for (const bool clockwise : {true, false}) {
    const calib::ReturnError expected =
        calib::square_return_error(options.side_m * 1e3, 150.0, e_d, e_b, clockwise);
    const double x_cg = clockwise ? before.result.x_cg_cw : before.result.x_cg_ccw;
    const double y_cg = clockwise ? before.result.y_cg_cw : before.result.y_cg_ccw;
    EXPECT_LT(std::hypot(x_cg - expected.x_mm, y_cg - expected.y_mm), cg_bound_mm)
        << (clockwise ? "cw" : "ccw") << ": centre (" << x_cg << ", " << y_cg << ") mm, expected ("
        << expected.x_mm << ", " << expected.y_mm << ") mm";
  }
  // The return errors scatter with σ ≈ 10-20 mm (slip, 2 mm measurement), so a centre of gravity
  // of 5 runs is known to 3·SEM ≈ 25 mm. On a 4 m square that bounds
  // δβ ≈ √2·25 mm/(4L) = 2.2 mrad -> δE_d = 2b·δβ/L ≈ 1.7e-4, and δα ≈ 2.2 mrad ->
  // δE_b = δα/(π/2) ≈ 1.4e-3.
  EXPECT_NEAR(report.recovered_e_d, e_d, 3e-4);
  EXPECT_NEAR(report.recovered_e_b, e_b, 2e-3);
  // After: only the c.g. uncertainty is left, so the fold improvement is several-fold at least.
  EXPECT_GT(report.improvement_fold, 5.0);
  EXPECT_LT(report.passes.back().result.e_max_syst_mm, 60.0);
}

TEST(SimUmbmark, ACoarseEncoderStillFinishesItsSquaresInNominalTime) {
  // 400 counts per turn: at the 2 % creep speed (4 mm/s) a wheel would see an edge only every
  // 0.12 s and its speed loop would hunt against dry friction (the squares then took 3-6 times
  // as long). The creep speed rises so each wheel gets an edge every 20 ms: the squares take
  // about as long as with a fine encoder.
  UmbmarkOptions options;
  options.side_m = 1.0;
  RobotSpec coarse = default_robot();
  std::string error;
  ASSERT_TRUE(parse_robot(R"({"counts_per_rev": 400})", "coarse.json", coarse, error)) << error;
  const UmbmarkReport fine_report = run_umbmark(default_robot(), 1u, options);
  const UmbmarkReport coarse_report = run_umbmark(coarse, 1u, options);
  ASSERT_TRUE(fine_report.ok) << fine_report.error;
  ASSERT_TRUE(coarse_report.ok) << coarse_report.error;
  EXPECT_LT(coarse_report.simulated_s, 1.25 * fine_report.simulated_s);
}

UmbmarkReport short_umbmark(std::uint64_t seed) {
  UmbmarkOptions options;
  options.side_m = 1.0;
  options.runs = 3;
  options.max_passes = 1;
  return run_umbmark(default_robot(), seed, options);
}

TEST(SimUmbmark, SameSeedSameReportAnotherSeedDiffers) {
  const std::string a = umbmark_report_json(short_umbmark(5u)).dump();
  const std::string b = umbmark_report_json(short_umbmark(5u)).dump();
  const std::string c = umbmark_report_json(short_umbmark(6u)).dump();
  EXPECT_EQ(a, b);
  EXPECT_NE(a, c);
}

TEST(SimMonteCarlo, ThreadCountDoesNotChangeTheResult) {
  MonteCarloOptions options;
  options.robots = 4;
  options.umbmark.side_m = 0.5;
  options.umbmark.runs = 2;
  options.umbmark.max_passes = 1;
  options.threads = 1;
  const std::string one =
      montecarlo_report_json(run_montecarlo(default_robot(), 3u, options)).dump();
  options.threads = 2;
  const std::string two =
      montecarlo_report_json(run_montecarlo(default_robot(), 3u, options)).dump();
  EXPECT_EQ(one, two);
}

TEST(SimRobot, UnseenPathEndsWhereMaddahiFigure9Says) {
  const PathEnd end = path_end(drive::make_unseen_path());
  EXPECT_NEAR(end.x_m, 0.0, 1e-6);
  EXPECT_NEAR(end.y_m, 1.6, 1e-6);
  EXPECT_NEAR(end.theta_rad, 5.0 * pi, 1e-5);  // 4·90° + 3·120° + 180°
}

TEST(SimRobot, FirmwareOdometryOfAPerfectRobotMatchesTheTruth) {
  RobotSpec spec = robot_with_errors(1.0, 150.0);
  spec.truth.slip_sigma = 0.0;
  spec.truth.measure_sigma_m = 0.0;
  spec.truth.measure_heading_sigma_rad = 0.0;
  SimulatedRobot robot(spec, 1u);
  const RunOutcome out = robot.run_path(drive::make_umbmark_square(true, 1.0f));
  ASSERT_TRUE(out.completed);
  // Same geometry in firmware and plant: truth and belief differ only by the encoder
  // quantisation (one count = π·60/1440 = 0.13 mm of wheel travel).
  EXPECT_NEAR(out.truth.x_m, static_cast<double>(out.odometry.x_m), 1e-3);
  EXPECT_NEAR(out.truth.y_m, static_cast<double>(out.odometry.y_m), 1e-3);
}

struct BadRobot {
  const char* text;
  const char* key;
};

TEST(RobotFile, RefusesBadRobotsNamingTheKey) {
  const BadRobot cases[] = {
      {R"({"wheel_diameter_mm": 60, "tyre_pressure": 2})", "tyre_pressure"},
      {R"({"true_left_diameter_mm": 0})", "true_left_diameter_mm"},
      {R"({"true_right_diameter_mm": -60})", "true_right_diameter_mm"},
      {R"({"wheel_diameter_mm": -1})", "wheel_diameter_mm"},
      {R"({"true_wheelbase_mm": 50})", "true_wheelbase_mm"},
      {R"({"wheelbase_mm": 40})", "wheelbase_mm"},
      {R"({"counts_per_rev": 1442})", "counts_per_rev"},
      {R"({"slip_sigma": "high"})", "slip_sigma"},
      {R"({"bump_height_mm": 40})", "bump_height_mm"},
  };
  for (const BadRobot& c : cases) {
    RobotSpec spec;
    std::string error;
    EXPECT_FALSE(parse_robot(c.text, "r.json", spec, error)) << c.text;
    EXPECT_NE(error.find(c.key), std::string::npos) << error;
    EXPECT_EQ(error.rfind("r.json", 0), 0u) << error;
  }
  RobotSpec spec;
  std::string error;
  EXPECT_FALSE(parse_robot("{\"wheelbase_mm\": ", "r.json", spec, error));
  EXPECT_FALSE(parse_robot("[1, 2]", "r.json", spec, error));
}

TEST(RobotFile, ANominalOnlyFileKeepsTheDefaultErrorsAroundTheNewGeometry) {
  RobotSpec spec;
  std::string error;
  ASSERT_TRUE(
      parse_robot(R"({"wheel_diameter_mm": 80, "wheelbase_mm": 200})", "r.json", spec, error))
      << error;
  const RobotSpec base = default_robot();
  // Same E_d = D_R/D_L and E_b = b_true/b_nominal as the default robot, scaled to 80 mm / 200 mm.
  EXPECT_NEAR(spec.truth.right_diameter_m / spec.truth.left_diameter_m,
              base.truth.right_diameter_m / base.truth.left_diameter_m, 1e-12);
  EXPECT_NEAR(spec.truth.wheelbase_m / 0.200, base.truth.wheelbase_m / 0.150, 1e-12);
  EXPECT_NEAR(0.5 * (spec.truth.left_diameter_m + spec.truth.right_diameter_m),
              0.080 * 0.5 * (base.truth.left_diameter_m + base.truth.right_diameter_m) / 0.060,
              1e-12);
  // A true key the file does give is taken as it is.
  ASSERT_TRUE(parse_robot(R"({"wheel_diameter_mm": 80, "true_left_diameter_mm": 79})", "r.json",
                          spec, error))
      << error;
  EXPECT_DOUBLE_EQ(spec.truth.left_diameter_m, 0.079);
}

TEST(RobotFile, RangeErrorsNameTheKeyThatIsWrong) {
  const BadRobot cases[] = {
      // Numbers a double cannot hold: refused, not thrown.
      {R"({"wheel_diameter_mm": 1e400})", "wheel_diameter_mm"},
      {R"({"slip_sigma": -1e400})", "slip_sigma"},
      // Outside the firmware's ranges: the key at fault, not the wheel diameter.
      {R"({"counts_per_rev": 4000000})", "counts_per_rev"},
      {R"({"counts_per_rev": 1e9})", "counts_per_rev"},
      {R"({"wheelbase_mm": 1e9})", "wheelbase_mm"},
      // Accepted before, but the firmware could not run them.
      {R"({"counts_per_rev": 4})", "counts_per_rev"},
      {R"({"counts_per_rev": 8})", "counts_per_rev"},
      {R"({"measure_sigma_mm": 1e9})", "measure_sigma_mm"},
      {R"({"wheel_diameter_mm": 5, "wheelbase_mm": 10})", "wheelbase_mm"},
      {R"({"wheel_diameter_mm": 5, "wheelbase_mm": 20, "true_left_diameter_mm": 6})",
       "true_left_diameter_mm"},
      {R"({"wheel_diameter_mm": 1000, "wheelbase_mm": 5000})", "wheelbase_mm"},
      {R"({"true_left_diameter_mm": 30, "true_right_diameter_mm": 90})", "true_left_diameter_mm"},
      {R"({"true_right_diameter_mm": 63.1})", "true_right_diameter_mm"},
      {R"({"true_wheelbase_mm": 166})", "true_wheelbase_mm"},
      // The last of two equal keys used to win silently.
      {R"({"wheelbase_mm": 150, "wheelbase_mm": 160})", "wheelbase_mm"},
  };
  for (const BadRobot& c : cases) {
    RobotSpec spec;
    std::string error;
    EXPECT_FALSE(parse_robot(c.text, "r.json", spec, error)) << c.text;
    EXPECT_EQ(error.rfind(std::string("r.json: ") + c.key + ": ", 0), 0u)
        << c.text << " -> " << error;
  }
  // The edges of the ranges are accepted: 100 counts, 100 mm noise, real wheels within 5 % and
  // wheelbase within 10 % of what the firmware is told, 12-4000 mm wheelbase.
  RobotSpec spec;
  std::string error;
  EXPECT_TRUE(parse_robot(R"({"counts_per_rev": 100, "measure_sigma_mm": 100,
                              "true_left_diameter_mm": 57, "true_right_diameter_mm": 63,
                              "true_wheelbase_mm": 165})",
                          "r.json", spec, error))
      << error;
  EXPECT_TRUE(parse_robot(R"({"wheel_diameter_mm": 1000, "wheelbase_mm": 4000,
                              "true_left_diameter_mm": 1000, "true_right_diameter_mm": 1000,
                              "true_wheelbase_mm": 4000})",
                          "r.json", spec, error))
      << error;
}

TEST(SimUmbmark, AFailedRunSaysWhereAndKeepsTheTimeSimulated) {
  // 8 counts per turn (a robot file refuses it): the wheel loop cannot finish a square.
  RobotSpec spec = default_robot();
  spec.nominal.counts_per_rev = 8.0f;
  spec.truth.counts_per_rev = 8u;
  UmbmarkOptions options;
  options.side_m = 0.5;
  options.runs = 2;
  const UmbmarkReport report = run_umbmark(spec, 1u, options);
  ASSERT_FALSE(report.ok);
  EXPECT_NE(report.error.find("pass 1, cw run 1: the square did not complete"), std::string::npos)
      << report.error;
  // It ran at least until the first square gave up.
  EXPECT_GT(report.simulated_s, 1.0);
  EXPECT_GT(umbmark_report_json(report).at("simulated_s").get<double>(), 1.0);
}

TEST(RobotFile, EveryKeyIsOptionalAndFallsBackToTheDefaultRobot) {
  RobotSpec spec;
  std::string error;
  ASSERT_TRUE(parse_robot("{}", "r.json", spec, error)) << error;
  EXPECT_EQ(spec.truth.left_diameter_m, default_robot().truth.left_diameter_m);
  ASSERT_TRUE(parse_robot(R"({"true_left_diameter_mm": 59.5, "bump_height_mm": 10,
                              "measure_sigma_mm": 1})",
                          "r.json", spec, error))
      << error;
  EXPECT_DOUBLE_EQ(spec.truth.left_diameter_m, 0.0595);
  EXPECT_DOUBLE_EQ(spec.truth.bump_height_m, 0.010);
  EXPECT_DOUBLE_EQ(spec.truth.measure_sigma_m, 0.001);
  EXPECT_EQ(spec.truth.right_diameter_m, default_robot().truth.right_diameter_m);
}

/// Runs a shell command; returns its exit status and stderr.
int run(const std::string& command, std::string& err) {
  const std::string err_file = ::testing::TempDir() + "odocal_sim_err.txt";
  const int status = std::system((command + " >/dev/null 2>" + err_file).c_str());
  std::ifstream in(err_file);
  err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(OdocalSimCommand, BadRobotFileExitsTwoNamingFileAndKey) {
  const char* bin = std::getenv("ODOCAL_BIN_DIR");
  const std::string odocal = bin != nullptr ? std::string(bin) + "/odocal" : "";
  if (odocal.empty() || !std::ifstream(odocal)) {
    FAIL() << "odocal not built (cmake --build --preset host builds it)";
  }
  const std::string file = ::testing::TempDir() + "bad_robot.json";
  std::ofstream(file) << R"({"true_wheelbase_mm": 30})";
  std::string err;
  EXPECT_EQ(run(odocal + " sim umbmark --robot " + file, err), 2);
  EXPECT_NE(err.find("true_wheelbase_mm"), std::string::npos) << err;
  EXPECT_NE(err.find(file), std::string::npos) << err;
  EXPECT_EQ(run(odocal + " sim validate --robot /nonexistent/robot.json", err), 2);
  EXPECT_NE(err.find("/nonexistent/robot.json"), std::string::npos) << err;
}

std::string odocal_program() {
  const char* bin = std::getenv("ODOCAL_BIN_DIR");
  const std::string odocal = bin != nullptr ? std::string(bin) + "/odocal" : "";
  return odocal.empty() || !std::ifstream(odocal) ? std::string() : odocal;
}

/// Runs a shell command; returns its exit status, `out` its stdout and `err` its stderr.
int run_both(const std::string& command, std::string& out, std::string& err) {
  const std::string out_file = ::testing::TempDir() + "odocal_sim_out2.txt";
  const std::string err_file = ::testing::TempDir() + "odocal_sim_err2.txt";
  const int status = std::system((command + " >" + out_file + " 2>" + err_file).c_str());
  std::ifstream o(out_file);
  out.assign(std::istreambuf_iterator<char>(o), std::istreambuf_iterator<char>());
  std::ifstream e(err_file);
  err.assign(std::istreambuf_iterator<char>(e), std::istreambuf_iterator<char>());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(OdocalSimCommand, NumericFlagsAreReadStrictlyAndRefusedNamingFlagAndRange) {
  const std::string odocal = odocal_program();
  if (odocal.empty()) {
    FAIL() << "odocal not built (cmake --build --preset host builds it)";
  }
  struct Bad {
    const char* args;
    const char* flag;
  };
  const Bad cases[] = {
      {"umbmark --side-mm abc", "--side-mm"},
      {"umbmark --side-mm 1e400", "--side-mm"},
      {"umbmark --side-mm 4000x", "--side-mm"},
      {"umbmark --side-mm nan", "--side-mm"},
      {"umbmark --side-mm 50", "--side-mm"},
      {"umbmark --side-mm 20001", "--side-mm"},
      {"umbmark --runs 3x", "--runs"},
      {"umbmark --seed -1", "--seed"},
      {"umbmark --seed 0x10", "--seed"},
      {"umbmark --seed 18446744073709551616", "--seed"},
      {"montecarlo --side-mm abc --robots 1", "--side-mm"},
      {"montecarlo --robots -1", "--robots"},
      {"montecarlo --robots 1e3", "--robots"},
      {"montecarlo --robots 1 --threads 0", "--threads"},
      {"validate --trials 5", "--trials"},
      {"validate --replicates 1e3", "--replicates"},
  };
  for (const Bad& c : cases) {
    std::string out;
    std::string err;
    EXPECT_EQ(run_both(odocal + " sim " + c.args + " --json", out, err), 2) << c.args;
    EXPECT_TRUE(out.empty()) << c.args << ": " << out;
    EXPECT_EQ(err.rfind(c.flag, 0), 0u) << c.args << ": " << err;
  }
  // The side is checked and shown in mm (not in metres).
  std::string out;
  std::string err;
  EXPECT_EQ(run_both(odocal + " sim umbmark --side-mm 50", out, err), 2);
  EXPECT_NE(err.find("100 to 20000 mm"), std::string::npos) << err;
  // A valid side reaches the procedure in metres: the report gives it back in mm.
  ASSERT_EQ(run_both(odocal + " sim umbmark --side-mm 250.5 --runs 2 --json", out, err), 0) << err;
  EXPECT_EQ(nlohmann::json::parse(out).at("side_mm").get<double>(), 250.5);
}

TEST(OdocalSimCommand, AnUnwritablePictureIsAnErrorBeforeAnyResult) {
  const std::string odocal = odocal_program();
  if (odocal.empty()) {
    FAIL() << "odocal not built (cmake --build --preset host builds it)";
  }
  std::string out;
  std::string err;
  EXPECT_EQ(run_both(odocal + " sim umbmark --side-mm 200 --runs 2 --json --svg /nonexistent/x.svg",
                     out, err),
            2);
  EXPECT_TRUE(out.empty()) << out;
  EXPECT_NE(err.find("/nonexistent/x.svg"), std::string::npos) << err;
  // A writable one is written, and the result printed.
  const std::string svg = ::testing::TempDir() + "odocal_sim_picture.svg";
  std::remove(svg.c_str());
  ASSERT_EQ(run_both(odocal + " sim umbmark --side-mm 200 --runs 2 --json --svg " + svg, out, err),
            0)
      << err;
  EXPECT_FALSE(out.empty());
  std::ifstream picture(svg);
  const std::string text((std::istreambuf_iterator<char>(picture)),
                         std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("<svg"), std::string::npos);
}

TEST(OdocalSimCommand, ProcedureFailureExitsTwoWithTheTimeSimulated) {
  const std::string odocal = odocal_program();
  if (odocal.empty()) {
    FAIL() << "odocal not built (cmake --build --preset host builds it)";
  }
  // A tiny robot the file accepts (5 mm wheels, 12 mm wheelbase, each true value at the edge of
  // its tolerance) whose straight trials leave the regression degenerate.
  const std::string file = ::testing::TempDir() + "tiny_robot.json";
  std::ofstream(file) << R"({"wheel_diameter_mm": 5, "wheelbase_mm": 12,
                             "true_left_diameter_mm": 5.25, "true_right_diameter_mm": 4.75,
                             "true_wheelbase_mm": 10.8})";
  const std::string svg = ::testing::TempDir() + "odocal_sim_failed.svg";
  std::remove(svg.c_str());
  std::string out;
  std::string err;
  EXPECT_EQ(
      run_both(odocal + " sim validate --replicates 100 --json --svg " + svg + " --robot " + file,
               out, err),
      2);
  // The error is a line of its own (progress lines may come before it on a slow machine).
  EXPECT_TRUE(err.rfind("odocal sim: validate: ", 0) == 0 ||
              err.find("\nodocal sim: validate: ") != std::string::npos)
      << err;
  const nlohmann::json j = nlohmann::json::parse(out);
  EXPECT_TRUE(j.contains("error"));
  // The straight trials ran: 20 of 1.5 m at 0.1-0.3 m/s, some 150 s of robot time at least.
  EXPECT_GT(j.at("simulated_s").get<double>(), 100.0) << out;
  // No picture is left behind by a failed run.
  EXPECT_FALSE(std::ifstream(svg).good());
}

}  // namespace
}  // namespace odocal::host

namespace odocal::host {
namespace {

/// Runs odocal-sim with `script` on stdin; returns its stdout.
int run_sim(const std::string& sim, const std::string& args, const std::string& script,
            std::string& output) {
  const std::string in = ::testing::TempDir() + "odocal_sim_in.txt";
  const std::string out = ::testing::TempDir() + "odocal_sim_out.txt";
  std::ofstream(in) << script;
  const int status = std::system((sim + " " + args + " <" + in + " >" + out).c_str());
  std::ifstream o(out);
  output.assign(std::istreambuf_iterator<char>(o), std::istreambuf_iterator<char>());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(OdocalSimProgram, ScriptedSessionDrivesTheRobotAndKeepsWhatWasSaved) {
  const char* bin = std::getenv("ODOCAL_BIN_DIR");
  const std::string sim = bin != nullptr ? std::string(bin) + "/odocal-sim" : "";
  if (sim.empty() || !std::ifstream(sim)) {
    FAIL() << "odocal-sim not built (cmake --build --preset host builds it)";
  }
  const std::string store = ::testing::TempDir() + "odocal_sim_test.store";
  std::remove(store.c_str());
  std::string out;
  ASSERT_EQ(run_sim(sim, "--speed 0 --store " + store,
                    "odom\nrun line 0.5\nodom\nset c_l 0.998\nsave\n", out),
            0);
  // One reply per line; the run finished before `odom` was read: x is the 0.5 m line
  // (odometry ends the segment within a tick at most of travel, < 1 mm at 0.2 m/s).
  std::istringstream lines(out);
  std::vector<std::string> replies;
  for (std::string l; std::getline(lines, l);) {
    if (!l.empty() && l[0] != '#')
      replies.push_back(l);
  }
  ASSERT_EQ(replies.size(), 5u) << out;
  EXPECT_EQ(replies[1].rfind("ok", 0), 0u);
  double x_mm = 0.0;
  ASSERT_EQ(std::sscanf(replies[2].c_str(), "ok x_mm=%lf", &x_mm), 1) << replies[2];
  EXPECT_NEAR(x_mm, 500.0, 2.0);
  // Restart with the same store: the saved c_l is back.
  ASSERT_EQ(run_sim(sim, "--speed 0 --store " + store, "get c_l\n", out), 0);
  EXPECT_NE(out.find("c_l=0.998"), std::string::npos) << out;
}

}  // namespace
}  // namespace odocal::host
