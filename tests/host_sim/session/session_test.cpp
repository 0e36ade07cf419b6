// `odocal session` end to end: the real `odocal` drives the real `odocal-sim`, with --sim (its
// tape measure) and through a pty used as a serial port (scripted and typed measurements).
// A hidden robot's factors must come back, survive a restart, and bad input must change nothing.
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "odocal/calib/umbmark.hpp"
#include "session_harness.hpp"

namespace {
using namespace odocal_session_test;

using nlohmann::json;

// The hidden robot: told 60 mm wheels and a 150 mm wheelbase; really 59.85 / 60.15 mm (the mean
// is the nominal 60, so UMBmark can recover everything) and 153 mm. No slip or bumps: the run
// scatter is the tape measure's 2 mm and the encoders' quantisation.
constexpr double true_left_mm = 59.85;
constexpr double true_right_mm = 60.15;
constexpr double true_wheelbase_mm = 153.0;
constexpr double nominal_wheelbase_mm = 150.0;
constexpr double measure_sigma_mm = 2.0;
const char* const robot_json =
    R"({"wheel_diameter_mm": 60, "wheelbase_mm": 150, "counts_per_rev": 1440,
        "true_left_diameter_mm": 59.85, "true_right_diameter_mm": 60.15,
        "true_wheelbase_mm": 153, "slip_sigma": 0, "bump_height_mm": 0,
        "measure_sigma_mm": 2})";

/// UMBmark's first-order standard error of β (rad) for a per-axis run scatter `s_mm`, n runs per
/// direction, side L: each of β's x- and y-based estimates is (x_cw − x_ccw)/(−4L), averaged.
double sd_beta(double s_mm, double n, double side_mm) {
  return s_mm / std::sqrt(n) / (4.0 * side_mm);
}

TEST(Session, SimUmbmarkRecoversTheHiddenRobotAndTheFactorsSurviveARestart) {
  const std::string robot = write("robot.json", robot_json);
  const std::string store = temp("recover.store");
  const std::string out = temp("recover_out");
  std::remove(store.c_str());
  std::system(("rm -rf " + out).c_str());
  const double side_mm = 2000.0;
  const double n = 5.0;
  const json doc = parse(session("--sim " + robot + " --store " + store +
                                 " --seed 3 --procedure umbmark "
                                 "--side-m 2 --runs 5 --yes --json --out " +
                                 out));
  ASSERT_TRUE(doc.is_object());
  for (const char* key : {"procedure", "runs", "result", "applied", "saved", "factors"}) {
    EXPECT_TRUE(doc.contains(key)) << key;
  }
  EXPECT_EQ(doc["procedure"], "umbmark");
  EXPECT_TRUE(doc["applied"].get<bool>());
  EXPECT_TRUE(doc["saved"].get<bool>());
  ASSERT_GE(doc["runs"].size(), 10u);
  const json& run = doc["runs"][0];
  for (const char* key :
       {"trial", "path", "duration_ms", "count_l", "count_r", "odom", "measured"}) {
    EXPECT_TRUE(run.contains(key)) << key;
  }
  EXPECT_EQ(run["path"], "umbmark-cw");
  EXPECT_EQ(doc["runs"][5]["path"], "umbmark-ccw");
  // Counts against geometry: a 2 m square is 8 m of mean wheel travel plus four quarter turns;
  // 1440 counts per turn of a ~60 mm wheel is 7.64 counts/mm (the right wheel, larger, turns less).
  const double counts_per_mm = 1440.0 / (3.14159265358979 * 60.0);
  const double mean_counts = 0.5 * (run["count_l"].get<double>() + run["count_r"].get<double>());
  EXPECT_NEAR(mean_counts, 4.0 * side_mm * counts_per_mm, 0.01 * 4.0 * side_mm * counts_per_mm);

  // Tolerances: the per-axis run scatter is the tape measure (2 mm) and the encoders' heading
  // quantum (π·60/1440 mm over 150 mm = 8.7e-4 rad) acting over a 2 m leg (±0.9 mm at the end,
  // uniform: 0.5 mm rms per segment, 8 segments: 1.4 mm): s ≈ sqrt(2² + 1.4²) = 2.5 mm; allow 3.
  // E_d ≈ 1 + bβ/L, E_b ≈ 1 + α/(π/2), α and β share the same standard error; 5σ bounds.
  const double sd = sd_beta(3.0, n, side_mm);
  const double e_d = true_right_mm / true_left_mm;
  const double c_l = 2.0 / (e_d + 1.0);
  const double c_r = 2.0 / (1.0 / e_d + 1.0);
  const double tol_c = 5.0 * 0.5 * nominal_wheelbase_mm * sd / side_mm + 1e-6;
  const double tol_b = 5.0 * nominal_wheelbase_mm * sd * 2.0 / 3.14159265358979 + 1e-3;
  const json& f = doc["factors"];
  EXPECT_NEAR(f["c_l"].get<double>(), c_l, tol_c);
  EXPECT_NEAR(f["c_r"].get<double>(), c_r, tol_c);
  EXPECT_NEAR(f["wheelbase_mm"].get<double>(), true_wheelbase_mm, tol_b);
  EXPECT_EQ(f["f_lat"].get<double>(), 1.0);
  // The first pass's estimate of E_d and E_b (the robot's errors before any correction).
  EXPECT_NEAR(doc["result"]["e_d"].get<double>(), e_d, 2.0 * tol_c + 2e-4);
  EXPECT_NEAR(doc["result"]["e_b"].get<double>(), true_wheelbase_mm / nominal_wheelbase_mm,
              2e-3);  // first pass: small-angle formulas on a 2 % error leave ~1e-3
  EXPECT_TRUE(doc["result"]["second_pass_recommended"].get<bool>());
  EXPECT_TRUE(doc["result"]["second_pass_run"].get<bool>());
  EXPECT_EQ(doc["runs"].size(), 20u);

  for (const char* file : {"session.json", "runs.csv", "runs.svg", "measurements.csv",
                           "umbmark_cw.csv", "umbmark_ccw.csv"}) {
    EXPECT_TRUE(exists(out + "/" + file)) << file;
  }
  // The CSVs are what `odocal umbmark` reads, and give the same first-pass answer.
  // (With the solver the session used for that pass.)
  const bool exact = doc["result"]["passes"][0]["solver"] == "exact";
  const Result again =
      shell(bin("odocal") + " umbmark --side-mm 2000 --wheelbase-mm 150 --cw " + out +
            "/umbmark_cw.csv --ccw " + out + "/umbmark_ccw.csv --json" + (exact ? " --exact" : ""));
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_NEAR(json::parse(again.out)["e_d"].get<double>(), doc["result"]["e_d"].get<double>(),
              1e-9);

  // A restart with the same store keeps what the session saved.
  EXPECT_NEAR(stored(robot, store, "c_l"), f["c_l"].get<double>(), 1e-6);
  EXPECT_NEAR(stored(robot, store, "c_r"), f["c_r"].get<double>(), 1e-6);
  EXPECT_NEAR(stored(robot, store, "wheelbase_mm"), f["wheelbase_mm"].get<double>(), 1e-5);

  // The same --out again is refused before anything runs.
  const Result twice = session("--sim " + robot + " --procedure umbmark --out " + out);
  EXPECT_EQ(twice.status, 2);
  EXPECT_NE(twice.err.find("already holds a session"), std::string::npos) << twice.err;
}

TEST(Session, WithoutYesOrATerminalNothingIsSaved) {
  const std::string robot = write("robot.json", robot_json);
  const std::string store = temp("nosave.store");
  const std::string out = temp("nosave_out");
  std::remove(store.c_str());
  std::system(("rm -rf " + out).c_str());
  const Result r = session("--sim " + robot + " --store " + store +
                           " --procedure umbmark --side-m 1 --runs 2 --json --out " + out);
  const json doc = parse(r);
  EXPECT_TRUE(doc["applied"].get<bool>());
  EXPECT_FALSE(doc["saved"].get<bool>());
  EXPECT_NE(r.err.find("Not saved"), std::string::npos) << r.err;
  EXPECT_NE(doc["factors"]["c_l"].get<double>(), 1.0);  // in force...
  EXPECT_EQ(stored(robot, store, "c_l"), 1.0);          // ...but not kept
}

TEST(Session, ThroughAPtyWithScriptedMeasurements) {
  const std::string robot = write("robot.json", robot_json);
  const std::string store = temp("pty.store");
  std::remove(store.c_str());
  SimOnPty sim(robot, store);
  ASSERT_FALSE(sim.path().empty());
  // The tape-measure readings a person would take on this robot: the exact square geometry
  // (core's square_return_error) for its E_d and E_b, 2 runs each way on a 1 m square.
  const double side_mm = 1000.0;
  const double e_d = true_right_mm / true_left_mm;
  const double e_b = true_wheelbase_mm / nominal_wheelbase_mm;
  std::string csv = "x_mm,y_mm\n";
  std::vector<odocal::calib::ReturnError> cw, ccw;
  for (int i = 0; i < 4; ++i) {
    const auto e =
        odocal::calib::square_return_error(side_mm, nominal_wheelbase_mm, e_d, e_b, i < 2);
    (i < 2 ? cw : ccw).push_back(e);
    csv += std::to_string(e.x_mm) + "," + std::to_string(e.y_mm) + "\n";
  }
  const std::string out = temp("pty_out");
  std::system(("rm -rf " + out).c_str());
  const json doc = parse(session("--port " + sim.path() +
                                 " --procedure umbmark --side-m 1 --runs 2 --no-wait "
                                 "--json --out " +
                                 out + " --measurements " + write("pty.csv", csv)));
  ASSERT_TRUE(doc.is_object());
  EXPECT_EQ(doc["runs"].size(), 4u);  // no rows for a second pass: not run
  EXPECT_FALSE(doc["saved"].get<bool>());
  // The session solves measured − odometry; the odometry ends within a few mm of the start
  // (segment ends quantised to one count: ±0.9 mm per segment at 1 m), so allow δ = 5 mm in each
  // centre: β and α move by up to δ/(2L), E_d by b·δ/(2L²), E_b by (2/π)·δ/(2L).
  odocal::calib::UmbmarkInput input{cw.data(), 2, ccw.data(), 2, side_mm, nominal_wheelbase_mm};
  odocal::calib::UmbmarkResult expected;
  ASSERT_EQ(odocal::calib::solve_umbmark(input, expected), odocal::calib::UmbmarkStatus::ok);
  const double angle = 5.0 / (2.0 * side_mm);
  EXPECT_NEAR(doc["result"]["e_d"].get<double>(), expected.e_d,
              nominal_wheelbase_mm * angle / side_mm);
  EXPECT_NEAR(doc["result"]["e_b"].get<double>(), expected.e_b, angle * 2.0 / 3.14159265358979);
  EXPECT_EQ(doc["runs"][0]["measured"]["theta_deg"], nullptr);
}

TEST(Session, TypedMeasurementsAreAskedAgainUntilTheyMakeSense) {
  const std::string robot = write("robot.json", robot_json);
  const std::string store = temp("typed.store");
  std::remove(store.c_str());
  SimOnPty sim(robot, store);
  ASSERT_FALSE(sim.path().empty());
  // Enter before each run (the user's moment), then the reading after it.
  const std::string typed = write("typed.txt",
                                  "\n"
                                  "abc\n"
                                  "abc 2\n"
                                  "1 2 3 4\n"
                                  "\n"
                                  "-40 -45\n"  // scattered about the origin: no second
                                  "\n"
                                  "41, 44\n"  // pass is expected to help
                                  "y\n"       // a comma is shown back: taken as read
                                  "\n"
                                  "-5 8 0.5\n"
                                  "\n"
                                  "6 -9\n");
  const std::string out = temp("typed_out");
  std::system(("rm -rf " + out).c_str());
  const Result r = session("--port " + sim.path() +
                               " --procedure umbmark --side-m 1 --runs 2 "
                               "--json --out " +
                               out,
                           typed);
  const json doc = parse(r);
  EXPECT_NE(r.err.find("Not taken: x_mm 'abc' is not a number"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Not taken: expected 2 or 3 numbers, got 1 word"), std::string::npos);
  EXPECT_NE(r.err.find("expected 2 or 3 numbers, got 4 words"), std::string::npos);
  EXPECT_NE(r.err.find("Not taken: empty line"), std::string::npos);
  EXPECT_NE(r.err.find("read as x 41.0, y 44.0 (a comma separates numbers here"), std::string::npos)
      << r.err;
  ASSERT_EQ(doc["runs"].size(), 4u);
  EXPECT_EQ(doc["runs"][0]["measured"]["x_mm"], -40.0);
  EXPECT_EQ(doc["runs"][2]["measured"]["theta_deg"], 0.5);
  EXPECT_FALSE(doc["saved"].get<bool>());

  // Input ends before the last run: exit 2, nothing saved.
  std::system(("rm -rf " + temp("typed_out2")).c_str());
  const Result short_input = session("--port " + sim.path() +
                                         " --procedure umbmark --side-m 1 "
                                         "--runs 2 --yes --out " +
                                         temp("typed_out2"),
                                     write("typed2.txt", "\n1 2\n\n"));
  EXPECT_EQ(short_input.status, 2);
  EXPECT_NE(short_input.err.find("no measurement for run 2"), std::string::npos) << short_input.err;
}

TEST(Session, BadFlagsAndPortsAreRefusedBeforeAnythingMoves) {
  const std::string robot = write("robot.json", robot_json);
  const std::string store = temp("bad.store");
  std::remove(store.c_str());
  const std::string sim = "--sim " + robot + " --store " + store + " ";
  const std::pair<std::string, std::string> cases[] = {
      {"--procedure umbmark", "give --port DEV"},
      {sim + "--procedure square", "--procedure"},
      {sim + "", "--procedure is required"},
      {sim + "--procedure umbmark --runs 1", "--runs"},
      {sim + "--procedure umbmark --runs 17", "from 2 to 16"},
      {sim + "--procedure umbmark --runs abc", "--runs"},
      {sim + "--procedure umbmark --runs -3", "--runs"},
      {sim + "--procedure umbmark --side-m nan", "--side-m"},
      {sim + "--procedure umbmark --side-m 0", "--side-m"},
      {sim + "--procedure verify --side-m 2", "--side-m does not apply"},
      {sim + "--procedure lateral --passes 2", "only for --procedure umbmark"},
      {sim + "--procedure umbmark --seed -1", "--seed"},
      {"--port /dev/null --sim " + robot + " --procedure umbmark", "excludes"},
      {"--port /dev/ttyNOPE0 --procedure umbmark", "does not exist"},
      {"--port /dev/null --procedure umbmark", "not a tty"},
      {"--port /dev/ttyNOPE0 --baud 12 --procedure umbmark", "--baud"},
      {"--port /dev/ttyNOPE0 --store x --procedure umbmark", "--store"},
      {"--sim " + temp("no_robot.json") + " --procedure umbmark", "cannot read"},
      {sim + "--procedure umbmark --measurements " + temp("no_such.csv"), "no_such.csv"},
      {sim + "--procedure umbmark --runs 2 --measurements " +
           write("short.csv", "x_mm,y_mm\n1,2\n3,4\n5,6\n"),
       "too few rows"},
      {sim + "--procedure umbmark --measurements " + write("garbage.csv", "x_mm,y_mm\n1,2\n3,zz\n"),
       "garbage.csv:3: field 'y_mm'"},
  };
  for (const auto& [args, message] : cases) {
    const std::string out = temp("bad_out");
    std::system(("rm -rf " + out).c_str());
    const Result r = session(args + " --out " + out);
    EXPECT_EQ(r.status, 2) << args;
    EXPECT_NE(r.err.find(message), std::string::npos) << args << "\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << args;
    EXPECT_FALSE(exists(out + "/session.json")) << args;
    EXPECT_FALSE(exists(store)) << args << ": the simulated robot's store was written";
  }
}

TEST(Session, ABusyPortIsRefused) {
  const std::string robot = write("robot.json", robot_json);
  SimOnPty sim(robot, temp("busy.store"));
  ASSERT_FALSE(sim.path().empty());
  const int held = ::open(sim.path().c_str(), O_RDWR | O_NOCTTY);
  ASSERT_GE(held, 0);
  ASSERT_EQ(::flock(held, LOCK_EX | LOCK_NB), 0);  // as picocom or a second odocal would
  const Result r =
      session("--port " + sim.path() + " --procedure umbmark --out " + temp("busy_out"));
  ::close(held);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("busy"), std::string::npos) << r.err;
}

}  // namespace

namespace {
using namespace odocal_session_test;

TEST(Session, LateralRecoversTheWheelRatioAndTheDistanceScale) {
  // A robot whose wheels differ but whose wheelbase is right (what UMBmark leaves to Maddahi):
  // straight ahead the smaller left wheel must turn D_R/D_L faster, F_lat = D_R/D_L, and the
  // distance scale is the right wheel's, F_lon = D/D_R (eq. 7 with nominal D for both wheels).
  const std::string robot =
      write("lateral_robot.json",
            R"({"wheel_diameter_mm": 60, "wheelbase_mm": 150, "counts_per_rev": 1440,
          "true_left_diameter_mm": 59.85, "true_right_diameter_mm": 60.15,
          "true_wheelbase_mm": 150, "slip_sigma": 0, "bump_height_mm": 0,
          "measure_sigma_mm": 2})");
  const std::string out = temp("lateral_out");
  std::system(("rm -rf " + out).c_str());
  const json doc = parse(session("--sim " + robot + " --procedure lateral --json --out " + out));
  ASSERT_TRUE(doc.is_object());
  const json& r = doc["result"];
  EXPECT_FALSE(r["degenerate"].get<bool>());
  EXPECT_EQ(r["applied_from"], "bootstrap");
  EXPECT_EQ(doc["runs"].size(), 14u);  // 10 straight trials + 4 arcs
  EXPECT_EQ(doc["runs"][0]["path"], "line");
  EXPECT_EQ(doc["runs"][13]["path"], "drive");
  // Tolerances from the 2 mm tape measure over 1 m trials: a chord angle of 2e-3 rad per trial,
  // F_lat − 1 ≈ 2lφ/L, so σ ≈ 2·150·2e-3/1000/√10 = 1.9e-4; ẋ to 2e-3 per trial, F_lon to
  // 2e-3/√14 = 5e-4. 5σ bounds.
  EXPECT_NEAR(r["bootstrap"]["f_lat"].get<double>(), true_right_mm / true_left_mm, 1e-3);
  EXPECT_NEAR(r["eq45"]["f_lat_in_force"].get<double>(), true_right_mm / true_left_mm, 1e-3);
  EXPECT_NEAR(r["bootstrap"]["f_lon"].get<double>(), 60.0 / true_right_mm, 2.7e-3);
  const json& ci = r["bootstrap"]["ci_f_lat"];
  EXPECT_LT(ci[0].get<double>(), r["bootstrap"]["f_lat"].get<double>());
  EXPECT_GT(ci[1].get<double>(), r["bootstrap"]["f_lat"].get<double>());
  EXPECT_NEAR(doc["factors"]["f_lat"].get<double>(), r["bootstrap"]["f_lat"].get<double>(), 1e-6);
  for (const char* file : {"lateral.csv", "training.csv", "unknowns.csv"}) {
    EXPECT_TRUE(exists(out + "/" + file)) << file;
  }
  // The files are what `odocal lateral` reads.
  const Result again = shell(bin("odocal") + " lateral --trials " + out +
                             "/lateral.csv --length-mm 1000 --wheelbase-mm 150 --dl-mm 60 "
                             "--dr-mm 60 --json");
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_NEAR(json::parse(again.out)["f_lat"].get<double>(), true_right_mm / true_left_mm, 1e-3);
}

TEST(Session, VerifyAfterUmbmarkShowsTheImprovementAndKeepsTheFactors) {
  // The unseen path turns left only: its legs must curve right (left wheel the larger) for the
  // leg curvature to add to the short turns rather than cancel them, as on the other robot.
  const std::string robot =
      write("verify_robot.json",
            R"({"wheel_diameter_mm": 60, "wheelbase_mm": 150, "counts_per_rev": 1440,
          "true_left_diameter_mm": 60.15, "true_right_diameter_mm": 59.85,
          "true_wheelbase_mm": 153, "slip_sigma": 0, "bump_height_mm": 0,
          "measure_sigma_mm": 2})");
  const std::string store = temp("verify.store");
  std::remove(store.c_str());
  for (const char* dir : {"verify_umbmark", "verify_out"}) {
    std::system(("rm -rf " + temp(dir)).c_str());
  }
  const json calibrated = parse(session("--sim " + robot + " --store " + store +
                                        " --procedure umbmark --side-m 2 --yes --json --out " +
                                        temp("verify_umbmark")));
  const json doc =
      parse(session("--sim " + robot + " --store " + store +
                    " --procedure verify --runs 3 --json --out " + temp("verify_out")));
  ASSERT_TRUE(doc.is_object());
  const json& s = doc["result"]["scenarios"];
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0]["name"], "before");
  EXPECT_EQ(s[1]["name"], "after");
  EXPECT_EQ(doc["runs"][0]["path"], "unseen");
  // A 2 % wheelbase and 0.5 % diameter error put the unseen path's end hundreds of mm off
  // (each of its ~1.5 turns is 2 % short: ~50 mm per metre); calibrated, what is left is the
  // tape measure and quantisation (mm). Half is a generous bound.
  EXPECT_GT(s[0]["rms_mm"].get<double>(), 50.0);
  EXPECT_LT(s[1]["rms_mm"].get<double>(), 0.5 * s[0]["rms_mm"].get<double>());
  EXPECT_GT(s[1]["improvement_pct"].get<double>(), 50.0);
  EXPECT_FALSE(doc["applied"].get<bool>());
  EXPECT_EQ(doc["factors"], calibrated["factors"]);  // put back exactly
  EXPECT_TRUE(exists(temp("verify_out") + "/accuracy.csv"));
  const Result accuracy =
      shell(bin("odocal") + " accuracy " + temp("verify_out") + "/accuracy.csv --json");
  ASSERT_EQ(accuracy.status, 0) << accuracy.err;
  EXPECT_NEAR(json::parse(accuracy.out)["scenarios"][1]["rms_mm"].get<double>(),
              s[1]["rms_mm"].get<double>(), 1e-2);
}

}  // namespace

namespace {
using namespace odocal_session_test;

TEST(Session, FitFromLoggedRunsRecoversTheTrueGeometry) {
  const std::string robot = write("robot.json", robot_json);
  const std::string out = temp("fit_out");
  std::system(("rm -rf " + out).c_str());
  const json doc = parse(session("--sim " + robot + " --procedure fit --json --out " + out));
  ASSERT_TRUE(doc.is_object());
  const json& r = doc["result"];
  ASSERT_EQ(doc["runs"].size(), 6u);
  EXPECT_EQ(doc["runs"][1]["path"], "drive");
  // The truth lies inside the fit's own 95 % intervals...
  const std::pair<const char*, double> truth[] = {{"wheel_diameter_left_mm", true_left_mm},
                                                  {"wheel_diameter_right_mm", true_right_mm},
                                                  {"wheelbase_mm", true_wheelbase_mm}};
  for (const auto& [key, value] : truth) {
    EXPECT_LE(r["ci"][key][0].get<double>(), value) << key;
    EXPECT_GE(r["ci"][key][1].get<double>(), value) << key;
    // ...and close in absolute terms: 2 mm end points over ~1.5 m of travel are ~0.13 % of the
    // scale (0.08 mm of diameter) per run; 6 runs, 5σ: 0.2 mm; the wheelbase from ~140° arcs of
    // 0.3 m radius: 2 mm over a 0.7 m arc is 0.3 % (0.45 mm) per arc, 4 arcs, 5σ: 1.1 mm.
    EXPECT_NEAR(r[key].get<double>(), value, std::string(key) == "wheelbase_mm" ? 1.1 : 0.2) << key;
  }
  // Applied by parts (docs/calibration.md, "The recommended order"); this robot's 0.5 % wheel
  // difference is far outside the fit's interval, so its ratio is applied whatever else is kept.
  const json& shown = r["shown"];
  EXPECT_TRUE(shown.value("wheel_ratio", false)) << r.dump();
  const double fl = r["c_l"].get<double>(), fr = r["c_r"].get<double>();
  const double al = doc["factors"]["c_l"].get<double>(), ar = doc["factors"]["c_r"].get<double>();
  EXPECT_NEAR(ar / al, fr / fl, 1e-5);
  EXPECT_NEAR(std::sqrt(al * ar), shown.value("scale", false) ? std::sqrt(fl * fr) : 1.0, 1e-5);
  // The tick logs are what `odocal fit` reads, and it agrees.
  std::string logs;
  for (int i = 1; i <= 6; ++i) {
    logs += " " + out + "/fit_run_0" + std::to_string(i) + ".csv";
  }
  const Result again = shell(bin("odocal") + " fit --log" + logs +
                             " --wheel-diameter-mm 60 --wheelbase-mm 150 --counts-per-rev 1440 "
                             "--json");
  ASSERT_EQ(again.status, 0) << again.err;
  EXPECT_NEAR(json::parse(again.out)["wheelbase_mm"].get<double>(), r["wheelbase_mm"].get<double>(),
              1e-6);
}

}  // namespace

namespace {
using namespace odocal_session_test;

TEST(Session, AtATerminalItAsksBeforeSavingAndSavesOnYes) {
  // The person's terminal is a pty too: odocal's stdin is its slave, the test types on the master.
  const std::string robot = write("robot.json", robot_json);
  const std::string store = temp("confirm.store");
  std::remove(store.c_str());
  SimOnPty sim(robot, store);
  ASSERT_FALSE(sim.path().empty());
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  ASSERT_GE(master, 0);
  ASSERT_EQ(::grantpt(master), 0);
  ASSERT_EQ(::unlockpt(master), 0);
  const std::string slave = ::ptsname(master);
  const std::string typed = "\n-40 -45\n\n41 44\n\n-5 8\n\n6 -9\nmaybe\ny\n";
  ASSERT_EQ(::write(master, typed.data(), typed.size()), static_cast<ssize_t>(typed.size()));
  const std::string out = temp("confirm_out");
  std::system(("rm -rf " + out).c_str());
  const Result r = session("--port " + sim.path() +
                               " --procedure umbmark --side-m 1 --runs 2 "
                               "--json --out " +
                               out,
                           slave);
  ::close(master);
  const json doc = parse(r);
  EXPECT_NE(r.err.find("Save these factors on the robot? [y/n]"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Please answer y or n (got 'maybe')"), std::string::npos) << r.err;
  EXPECT_TRUE(doc["saved"].get<bool>());
  EXPECT_NEAR(stored(robot, store, "c_l"), doc["factors"]["c_l"].get<double>(), 1e-6);
}

}  // namespace

namespace {
using namespace odocal_session_test;

TEST(Session, LateralSaysSoWhenItsDesignIsDegenerate) {
  // Every stop point typed as the start itself: the trials' body velocities are all zero, so
  // eq. 10 has nothing to fit and eq. 4-5 has no chord; nothing may be applied.
  const std::string robot = write("robot.json", robot_json);
  SimOnPty sim(robot, temp("degenerate.store"));
  ASSERT_FALSE(sim.path().empty());
  std::string csv = "x_mm,y_mm,theta_deg\n";
  for (int i = 0; i < 6; ++i) {
    csv += "0,0,0\n";
  }
  const std::string out = temp("degenerate_out");
  std::system(("rm -rf " + out).c_str());
  // Such readings cannot be (the odometry says each line ended 1 m ahead): the reading check
  // shows each back, and --yes takes them as the file has them.
  const Result r = session("--port " + sim.path() +
                           " --procedure lateral --runs 2 --no-wait --json --yes "
                           "--out " +
                           out + " --measurements " + write("zeros.csv", csv));
  EXPECT_NE(r.err.find("Check this reading"), std::string::npos) << r.err;
  const json doc = parse(r);
  ASSERT_TRUE(doc.is_object());
  EXPECT_TRUE(doc["result"]["degenerate"].get<bool>());
  EXPECT_NE(r.err.find("design is degenerate"), std::string::npos) << r.err;
  EXPECT_FALSE(doc["applied"].get<bool>());
  EXPECT_EQ(doc["factors"]["f_lat"].get<double>(), 1.0);
  EXPECT_EQ(doc["factors"]["f_lon"].get<double>(), 1.0);
}

}  // namespace
