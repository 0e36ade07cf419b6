// "Sessions on a real robot" (DESIGN): `odocal session --port` driven as a person drives it,
// with Enter before each run, typed readings (one of them wrong), Ctrl-C in the second pass and
// --resume; lockstep simulation (same seed, same session under a busy CPU); results outside the
// formulas' validity refused; the documented order of procedures never making the robot worse.
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "odocal/calib/umbmark.hpp"
#include "session_harness.hpp"
#include "session_person.hpp"

namespace {

using namespace odocal_session_test;

// The hidden robot of these tests: told 60 mm wheels and 150 mm, really 59.85 / 60.15 mm and
// 153 mm; no slip, so its runs repeat and the readings below are what a tape would give.
const char* const hidden_robot =
    R"({"wheel_diameter_mm": 60, "wheelbase_mm": 150, "counts_per_rev": 1440,
        "true_left_diameter_mm": 59.85, "true_right_diameter_mm": 60.15,
        "true_wheelbase_mm": 153, "slip_sigma": 0, "bump_height_mm": 0,
        "measure_sigma_mm": 2})";
constexpr double true_left_mm = 59.85;
constexpr double true_right_mm = 60.15;
constexpr double true_wheelbase_mm = 153.0;

/// What a tape measure gives at the end of the session's latest run of the UMBmark square: the
/// odometry it printed plus the exact square geometry of the hidden robot relative to the
/// factors in force (E_d and E_b of the drive that ran it), plus a small alternating scatter.
std::string reading(const Person& p, double side_mm, bool clockwise, double c_l, double c_r,
                    double b_mm, int run) {
  const std::string& e = p.err;
  const auto at = e.rfind("odometry says x=");
  const double x = std::atof(e.c_str() + at + 16);
  const double y = std::atof(e.c_str() + e.find("y=", at) + 2);
  const double e_d = (true_right_mm / true_left_mm) / (c_r / c_l);
  const double e_b = true_wheelbase_mm / b_mm;
  const odocal::calib::ReturnError r =
      odocal::calib::square_return_error(side_mm, b_mm, e_d, e_b, clockwise);
  const double scatter = (run % 2 == 0 ? 1.0 : -1.0) * 1.5;
  char text[96];
  std::snprintf(text, sizeof text, "%.2f %.2f", x + r.x_mm + scatter, y + r.y_mm - scatter);
  return text;
}

/// --resume of the session interrupted in pass 2: the five runs are taken over, pass 1 applied
/// again, pass 2 finished.
void resume_pass_two(const std::string& pty, const std::string& out, const json& interrupted,
                     double side_mm) {
  double c_l = 1.0, c_r = 1.0, b = 150.0;
  Person p({"--port", pty, "--resume", out, "--json"});
  for (int run = 6; run <= 8; ++run) {
    ASSERT_TRUE(p.wait_for("press Enter to start", static_cast<std::size_t>(run - 5))) << p.err;
    if (run == 6) {
      EXPECT_EQ(p.count("not driven again"), 5u) << p.err;
      const std::string& e = p.err;
      const auto at = e.rfind("Applied on the robot:");
      ASSERT_NE(at, std::string::npos) << e;
      const std::string applied = e.substr(at, e.find('\n', at) - at);
      c_l = value_of(applied, "c_l");
      c_r = value_of(applied, "c_r");
      b = value_of(applied, "wheelbase_mm");
    }
    p.type("");
    ASSERT_TRUE(p.wait_for("Measured stop point", static_cast<std::size_t>(run - 5))) << p.err;
    p.type(reading(p, side_mm, run == 6, c_l, c_r, b, run));
  }
  ASSERT_EQ(p.finish(), 0) << p.err;
  const json done = json::parse(p.out, nullptr, false);
  ASSERT_TRUE(done.is_object()) << p.out << p.err;
  EXPECT_TRUE(done["complete"].get<bool>());
  ASSERT_EQ(done["runs"].size(), 8u);
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_EQ(done["runs"][i], interrupted["runs"][i]) << "run " << i + 1;
  }
  EXPECT_EQ(rows_of(out + "/measurements.csv"), 8u);
  EXPECT_EQ(done["date"], interrupted["date"]);
  // The result is the one of these runs: pass 1 solved again from the same readings.
  ASSERT_EQ(done["result"]["passes"].size(), 2u);
  EXPECT_DOUBLE_EQ(done["result"]["passes"][0]["e_d"].get<double>(),
                   interrupted["result"]["passes"][0]["e_d"].get<double>());
  // The hidden robot's geometry is in force: the readings followed the exact square model, so
  // only the 1.5 mm scatter over a 1 m square and the counts' quantum remain (E_d to
  // b·δ/(2L²) = 1.1e-4 for δ = 3 mm, the wheelbase to (2/π)·δ/(2L)·b = 0.15 mm).
  const double e_d = done["factors"]["c_r"].get<double>() / done["factors"]["c_l"].get<double>();
  EXPECT_NEAR(e_d, true_right_mm / true_left_mm, 3e-4);
  EXPECT_NEAR(done["factors"]["wheelbase_mm"].get<double>(), true_wheelbase_mm, 0.5);
  // Provenance tells the whole truth: all 8 runs, the session's date.
  const std::string provenance = ask_robot(pty, "provenance", "wheel_date");
  EXPECT_EQ(value_of(provenance, "wheel_runs"), 8.0) << provenance;
  EXPECT_EQ(value_of(provenance, "wheel_date"), done["date"].get<double>()) << provenance;
}

TEST(SessionOnARealRobot, EnterBeforeEachRunCtrlCInPassTwoPutsBackAndResumeFinishes) {
  const std::string robot = write("real_robot.json", hidden_robot);
  const std::string store = temp("real.store");
  std::remove(store.c_str());
  SimOnPty sim(robot, store);
  ASSERT_FALSE(sim.path().empty());
  const std::string out = temp("real_out");
  std::system(("rm -rf " + out).c_str());
  const double side_mm = 1000.0;
  double c_l = 1.0, c_r = 1.0, b = 150.0;
  {
    Person p({"--port", sim.path(), "--procedure", "umbmark", "--side-m", "1", "--runs", "2",
              "--passes", "2", "--out", out});
    // Nothing moves before the person says so.
    ASSERT_TRUE(p.wait_for("press Enter to start", 1)) << p.err;
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    p.wait_for("Run 1/4:", 1, 0.2);
    EXPECT_EQ(p.count("Run 1/4:"), 0u) << "a run started before Enter:\n" << p.err;
    for (int run = 1; run <= 5; ++run) {
      ASSERT_TRUE(p.wait_for("press Enter to start", static_cast<std::size_t>(run))) << p.err;
      p.type("");
      ASSERT_TRUE(p.wait_for("Measured stop point", p.count("Measured stop point") + 1)) << p.err;
      if (run == 2) {  // a slip of the finger: asked again, nothing lost
        p.type("12,5 oops");
        ASSERT_TRUE(p.wait_for("Not taken", 1)) << p.err;
      }
      if (run == 5) {  // pass 2 runs with pass 1's factors
        const std::string& e = p.err;
        const auto at = e.rfind("Applied on the robot:");
        ASSERT_NE(at, std::string::npos) << e;
        c_l = value_of(e.substr(at, e.find('\n', at) - at), "c_l");
        c_r = value_of(e.substr(at, e.find('\n', at) - at), "c_r");
        b = value_of(e.substr(at, e.find('\n', at) - at), "wheelbase_mm");
      }
      p.type(reading(p, side_mm, run == 1 || run == 2 || run == 5, c_l, c_r, b, run));
    }
    // Run 6's moment: Ctrl-C.
    ASSERT_TRUE(p.wait_for("press Enter to start", 6)) << p.err;
    EXPECT_NE(p.err.find("Run 6/8 (pass2-cw)"), std::string::npos) << p.err;
    p.signal(SIGINT);
    EXPECT_EQ(p.finish(), 130) << p.err;
    EXPECT_NE(p.err.find("interrupted by SIGINT"), std::string::npos) << p.err;
    EXPECT_NE(p.err.find("put back"), std::string::npos) << p.err;
    EXPECT_NE(p.err.find("--resume " + out), std::string::npos) << p.err;
  }
  // The journal has every reading taken; session.json says it is not complete.
  EXPECT_EQ(rows_of(out + "/measurements.csv"), 5u);
  const json interrupted = read_json(out + "/session.json");
  ASSERT_TRUE(interrupted.is_object());
  EXPECT_FALSE(interrupted["complete"].get<bool>());
  EXPECT_EQ(interrupted["runs"].size(), 5u);
  EXPECT_EQ(interrupted["result"]["passes"].size(), 1u);
  // Pass 1 was applied, then put back: the robot is as before the session, and saved nothing.
  EXPECT_DOUBLE_EQ(value_of(ask_robot(sim.path(), "get c_l", "c_l"), "c_l"), 1.0);
  EXPECT_DOUBLE_EQ(
      value_of(ask_robot(sim.path(), "get wheelbase_mm", "wheelbase_mm"), "wheelbase_mm"), 150.0);
  EXPECT_EQ(ask_robot(sim.path(), "provenance", "wheel_date").find("wheel_method=umbmark"),
            std::string::npos);

  // A conflicting option is refused; nothing is driven.
  const Result conflict = session("--port " + sim.path() + " --resume " + out + " --runs 3");
  EXPECT_EQ(conflict.status, 2);
  EXPECT_NE(conflict.err.find("--runs"), std::string::npos) << conflict.err;

  resume_pass_two(sim.path(), out, interrupted, side_mm);
  // A complete session is not resumed.
  const Result again = session("--port " + sim.path() + " --resume " + out);
  EXPECT_EQ(again.status, 2);
  EXPECT_NE(again.err.find("complete"), std::string::npos) << again.err;
}

TEST(SessionOnARealRobot, EndOfInputAtTheMomentBeforeARunStopsAndPutsBack) {
  const std::string robot = write("real_robot.json", hidden_robot);
  SimOnPty sim(robot, temp("eof.store"));
  ASSERT_FALSE(sim.path().empty());
  const std::string out = temp("eof_out");
  std::system(("rm -rf " + out).c_str());
  const double cruise = value_of(ask_robot(sim.path(), "get v_max_mps", "v_max_mps"), "v_max_mps");
  // Enter, a reading, then the input ends where the next Enter should come.
  const Result r = session("--port " + sim.path() + " --procedure lateral --runs 3 --out " + out,
                           write("eof.txt", "\n1001 -3\n"));
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("end of input while waiting for Enter before run 2"), std::string::npos)
      << r.err;
  EXPECT_EQ(rows_of(out + "/measurements.csv"), 1u);
  EXPECT_FALSE(read_json(out + "/session.json")["complete"].get<bool>());
  // The lateral procedure changes the cruise speed per trial: it is back too.
  EXPECT_DOUBLE_EQ(value_of(ask_robot(sim.path(), "get v_max_mps", "v_max_mps"), "v_max_mps"),
                   cruise);
}

/// Burns one core until destroyed (a busy machine).
class BusyCpu {
 public:
  BusyCpu() {
    pid_ = ::fork();
    if (pid_ == 0) {
      volatile unsigned long spin = 0;
      for (;;) {
        spin = spin + 1;
      }
    }
  }
  ~BusyCpu() {
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
  }

 private:
  pid_t pid_ = -1;
};

TEST(SessionOnARealRobot, SameSeedSameSessionUnderABusyCpu) {
  // The fit logs every run through `stream ticks`: a simulator that ran on while the host was
  // slow would log other rows and end elsewhere. Slip and tape noise are on, so the seed matters.
  const std::string robot = write("busy_robot.json",
                                  R"({"true_left_diameter_mm": 59.9, "true_right_diameter_mm": 60.1,
                "slip_sigma": 0.003, "measure_sigma_mm": 2})");
  json first;
  for (int attempt = 0; attempt < 2; ++attempt) {
    const std::string out = temp("busy_out_" + std::to_string(attempt));
    std::system(("rm -rf " + out).c_str());
    Result r;
    if (attempt == 0) {
      r = session("--sim " + robot + " --seed 7 --procedure fit --runs 3 --json --out " + out);
    } else {
      BusyCpu a, b, c;
      r = session("--sim " + robot + " --seed 7 --procedure fit --runs 3 --json --out " + out);
    }
    json doc = parse(r);
    ASSERT_TRUE(doc.is_object());
    doc.erase("date");
    if (attempt == 0) {
      first = doc;
    } else {
      EXPECT_EQ(doc, first);
    }
  }
  // Another seed is another robot's noise.
  const std::string out = temp("busy_out_other");
  std::system(("rm -rf " + out).c_str());
  json other =
      parse(session("--sim " + robot + " --seed 8 --procedure fit --runs 3 --json --out " + out));
  other.erase("date");
  EXPECT_NE(other["runs"], first["runs"]);
}

TEST(SessionOnARealRobot, SquaresFarTooBigForTheRobotAreRefusedAndNothingStays) {
  // A small robot (48 mm wheels, 92 mm wheelbase, wheels 0.6 % apart): its legs curve by about
  // 15° on a 4 m square (the exact solve handles that) and wrap past 90° on 12 m and 20 m ones.
  const std::string robot =
      write("small_robot.json",
            R"({"wheel_diameter_mm": 48, "wheelbase_mm": 92, "true_left_diameter_mm": 47.85,
          "true_right_diameter_mm": 48.15, "true_wheelbase_mm": 94.2})");
  for (const char* side : {"12", "20"}) {
    const std::string store = temp(std::string("big_") + side + ".store");
    std::remove(store.c_str());
    const std::string out = temp(std::string("big_out_") + side);
    std::system(("rm -rf " + out).c_str());
    const Result r = session("--sim " + robot + " --store " + store + " --side-m " + side +
                             " --procedure umbmark --runs 2 --yes --out " + out);
    EXPECT_EQ(r.status, 2) << side << r.err;
    EXPECT_NE(r.err.find("--side-m"), std::string::npos) << r.err;
    const json doc = read_json(out + "/session.json");
    EXPECT_FALSE(doc["complete"].get<bool>());
    EXPECT_FALSE(doc["saved"].get<bool>());
    EXPECT_EQ(stored(robot, store, "wheelbase_mm"), 92.0);  // nothing saved
  }
  // The default square: the small-angle formulas are off by far more than the noise, so the
  // exact solve is used, and the wheelbase comes out right (the first-order interval of E_b at
  // 2 runs is about ±0.1 %: 0.3 mm).
  const std::string out = temp("big_out_4");
  std::system(("rm -rf " + out).c_str());
  const json doc = parse(
      session("--sim " + robot + " --procedure umbmark --runs 2 --passes 1 --json --out " + out));
  ASSERT_TRUE(doc.is_object());
  EXPECT_EQ(doc["result"]["solver"], "exact");
  EXPECT_NEAR(doc["factors"]["wheelbase_mm"].get<double>(), 94.2, 0.3);
  EXPECT_NEAR(doc["factors"]["c_r"].get<double>() / doc["factors"]["c_l"].get<double>(),
              48.15 / 47.85, 1e-4);
}

/// The unseen path's end error (RMS over runs, mm) with the factors in `store`, and the spread of
/// the runs' radial errors.
struct Unseen {
  double rms_mm = 0.0;
  double sd_mm = 0.0;
};

Unseen verify(const std::string& robot, const std::string& store, const std::string& out) {
  std::system(("rm -rf " + out).c_str());
  const json doc = parse(
      session("--sim " + robot + " --store " + store + " --procedure verify --json --out " + out));
  Unseen u;
  std::vector<double> r;
  for (const json& s : doc["result"]["scenarios"]) {
    if (s["name"] == "after") {
      u.rms_mm = s["rms_mm"].get<double>();
    }
  }
  std::ifstream csv(out + "/accuracy.csv");
  std::string line;
  std::getline(csv, line);
  while (std::getline(csv, line)) {
    if (line.rfind("after,", 0) == 0) {
      double x = 0, y = 0;
      std::sscanf(line.c_str() + line.find(',', 6) + 1, "%lf,%lf", &x, &y);
      r.push_back(std::hypot(x, y));
    }
  }
  double mean = 0;
  for (double v : r) {
    mean += v / static_cast<double>(r.size());
  }
  for (double v : r) {
    u.sd_mm += (v - mean) * (v - mean) / static_cast<double>(r.size() - 1);
  }
  u.sd_mm = std::sqrt(u.sd_mm);
  return u;
}

TEST(SessionOnARealRobot, TheDocumentedOrderNeverMakesTheUnseenPathWorse) {
  struct Robot {
    const char* name;
    const char* json;
    double d, d_l, d_r, b;
  };
  const Robot robots[] = {
      {"micromouse",
       R"({"wheel_diameter_mm": 48, "wheelbase_mm": 92, "true_left_diameter_mm": 47.85,
           "true_right_diameter_mm": 48.15, "true_wheelbase_mm": 94.2})",
       48.0, 47.85, 48.15, 94.2},
      {"lab",
       R"({"wheel_diameter_mm": 100, "wheelbase_mm": 300, "counts_per_rev": 2048,
           "true_left_diameter_mm": 100.3, "true_right_diameter_mm": 99.8,
           "true_wheelbase_mm": 306, "slip_sigma": 0.002})",
       100.0, 100.3, 99.8, 306.0},
  };
  for (const Robot& robot : robots) {
    SCOPED_TRACE(robot.name);
    const std::string file = write(std::string(robot.name) + ".json", robot.json);
    const std::string store = temp(std::string(robot.name) + "_order.store");
    std::remove(store.c_str());
    std::vector<Unseen> after;
    after.push_back(verify(file, store, temp("order_v0")));
    for (const char* procedure : {"umbmark", "lateral", "fit"}) {
      const std::string out = temp(std::string("order_") + procedure);
      std::system(("rm -rf " + out).c_str());
      const Result r = session("--sim " + file + " --store " + store + " --procedure " + procedure +
                               " --yes --json --out " + out);
      ASSERT_EQ(r.status, 0) << procedure << r.err;
      if (std::string(procedure) == "lateral") {
        // Eq. 4-5 for the drive that ran the trials: the wheel ratio UMBmark put in force shaped
        // them already, so the session's correction is `odocal lateral` with equal diameters.
        const json doc = json::parse(r.out);
        const json& eq45 = doc["result"]["eq45"];
        char args[512];
        std::snprintf(args, sizeof args,
                      " lateral --trials %s/lateral.csv --length-mm 1000 --wheelbase-mm %.6f "
                      "--dl-mm %.1f --dr-mm %.1f --theta-l-rad %.9f --json",
                      out.c_str(), doc["factors"]["wheelbase_mm"].get<double>(), robot.d, robot.d,
                      eq45["theta_l_rad"].get<double>());
        const Result cli = shell(bin("odocal") + args);
        ASSERT_EQ(cli.status, 0) << cli.err;
        EXPECT_NEAR(json::parse(cli.out)["f_lat"].get<double>(), eq45["f_lat"].get<double>(), 1e-6);
        // After UMBmark the wheel ratio is UMBmark's: f_lat stays.
        EXPECT_EQ(doc["factors"]["f_lat"].get<double>(), 1.0);
      }
      after.push_back(verify(file, store, temp(std::string("order_v_") + procedure)));
    }
    // The oracle: the robot's true geometry in force.
    const std::string oracle_store = temp(std::string(robot.name) + "_oracle.store");
    std::remove(oracle_store.c_str());
    char script[256];
    std::snprintf(script, sizeof script,
                  "set c_l %.6f\nset c_r %.6f\nset wheelbase_mm %.4f\nsave\n", robot.d_l / robot.d,
                  robot.d_r / robot.d, robot.b);
    shell(bin("odocal-sim") + " --robot " + file + " --store " + oracle_store + " <" +
          write("oracle.txt", script));
    const Unseen oracle = verify(file, oracle_store, temp("order_oracle"));
    // Tolerance: two RMS figures of n = 5 runs differ by their sampling scatter, about
    // sd·sqrt(2/n); 3 of those.
    for (std::size_t step = 1; step < after.size(); ++step) {
      const double tol =
          3.0 * std::max(after[step].sd_mm, after[step - 1].sd_mm) * std::sqrt(2.0 / 5.0);
      EXPECT_LE(after[step].rms_mm, after[step - 1].rms_mm + tol)
          << "step " << step << ": " << after[step - 1].rms_mm << " -> " << after[step].rms_mm;
    }
    // And the end comes near what the true geometry reaches.
    const double tol = 3.0 * std::max(after.back().sd_mm, oracle.sd_mm) * std::sqrt(2.0 / 5.0);
    EXPECT_LE(after.back().rms_mm, 1.5 * oracle.rms_mm + tol)
        << "end " << after.back().rms_mm << " oracle " << oracle.rms_mm;
    EXPECT_LT(after.back().rms_mm, 0.1 * after.front().rms_mm);
  }
}

TEST(SessionOnARealRobot, AMistypedRobotFileKeySaysWhichWasMeant) {
  const Result r = shell(bin("odocal-sim") + " --robot " +
                         write("typo.json", R"({"true_left_diamter_mm": 59.9})") + " </dev/null");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("did you mean \"true_left_diameter_mm\""), std::string::npos) << r.err;
}

TEST(SessionOnARealRobot, ABadStoreFileIsNamedOnce) {
  const std::string store = write("bad.store", "not a store");
  const Result r = shell(bin("odocal-sim") + " --store " + store + " </dev/null");
  EXPECT_EQ(r.status, 2);
  const auto first = r.err.find(store);
  ASSERT_NE(first, std::string::npos) << r.err;
  EXPECT_EQ(r.err.find(store, first + 1), std::string::npos) << r.err;
}

TEST(SessionOnARealRobot, NoMinusZeroAndNoOneRuns) {
  // A robot whose wheels and wheelbase are what it is told: its return errors are about zero.
  const std::string robot = write(
      "exact_robot.json",
      R"({"slip_sigma": 0, "measure_sigma_mm": 0, "wheel_diameter_mm": 60, "wheelbase_mm": 150,
      "true_left_diameter_mm": 60, "true_right_diameter_mm": 60, "true_wheelbase_mm": 150})");
  const std::string out = temp("zero_out");
  std::system(("rm -rf " + out).c_str());
  const Result r =
      session("--sim " + robot + " --procedure umbmark --side-m 1 --runs 2 --out " + out);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.find(" -0.0 "), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("1 runs"), std::string::npos) << r.err;
}

}  // namespace
