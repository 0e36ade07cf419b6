// Trials, `# done`, `stream ticks`, `lateral`, `measure` and encoder faults, through odocal-sim's
// stdio exactly as a host program sees them (DESIGN "Trials, logs and the simulated tape measure").

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "sim_process.hpp"

namespace {

constexpr double kPi = 3.14159265358979323846;
// The default robot (host_sim default_robot()): what the firmware is told.
constexpr double kWheelMm = 60.0;
constexpr double kWheelbaseMm = 150.0;
constexpr double kCountsPerRev = 1440.0;
constexpr double kMmPerCount = kPi * kWheelMm / kCountsPerRev;

using odocal::test::sim_program;
using odocal::test::temp_file;

/// Runs odocal-sim on `script`; every output line in order.
int run_sim(const std::string& args, const std::string& script, std::vector<std::string>& lines) {
  const std::string in = temp_file("odocal_sim_trials_in.txt", script);
  const std::string out = ::testing::TempDir() + "odocal_sim_trials_out.txt";
  const std::string err = ::testing::TempDir() + "odocal_sim_trials_err.txt";
  const int status = std::system(
      (sim_program() + " --speed 0 " + args + " <" + in + " >" + out + " 2>" + err).c_str());
  std::ifstream o(out);
  lines.clear();
  for (std::string l; std::getline(o, l);) {
    lines.push_back(l);
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// key=value pairs of a line.
std::map<std::string, std::string> pairs(const std::string& line) {
  std::map<std::string, std::string> out;
  std::istringstream words(line);
  for (std::string w; words >> w;) {
    const auto eq = w.find('=');
    if (eq != std::string::npos) {
      out[w.substr(0, eq)] = w.substr(eq + 1);
    }
  }
  return out;
}

double num(const std::map<std::string, std::string>& p, const std::string& key) {
  const auto it = p.find(key);
  return it == p.end() ? std::nan("") : std::stod(it->second);
}

/// Lines that answer commands (not `#`), in order.
std::vector<std::string> replies(const std::vector<std::string>& lines) {
  std::vector<std::string> out;
  for (const auto& l : lines) {
    if (!l.empty() && l[0] != '#') {
      out.push_back(l);
    }
  }
  return out;
}

#define REQUIRE_SIM()                                                         \
  if (sim_program().empty()) {                                                \
    FAIL() << "odocal-sim not built (cmake --build --preset host builds it)"; \
  }

TEST(OdocalSimTrials, LineTrialAnnouncesDoneBeforeTheNextReplyAndCountsMatchOdometry) {
  REQUIRE_SIM();
  std::vector<std::string> lines;
  ASSERT_EQ(run_sim("", "run line 1\ntrial\n", lines), 0);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0].rfind("ok path=line", 0), 0u) << lines[0];
  EXPECT_EQ(lines[1], "# done trial=1 path=line");
  const auto t = pairs(lines[2]);
  EXPECT_EQ(lines[2].rfind("ok trial=1 path=line ", 0), 0u) << lines[2];
  // Odometry drives the line until the mean wheel travel it sees is 1 m: the counts are that
  // travel at the nominal 60 mm wheel, 1440 counts per turn (plus at most a few counts of
  // creep and coasting past the end, which odometry sees too).
  const double mean_counts = 0.5 * (num(t, "count_l") + num(t, "count_r"));
  const double travel_mm = std::hypot(num(t, "x_mm"), num(t, "y_mm"));
  EXPECT_NEAR(mean_counts * kMmPerCount, travel_mm, 0.5);
  EXPECT_NEAR(travel_mm, 1000.0, 3.0);
  // 1 m at 0.2 m/s cruise, 0.5 m/s² ramps: 5.4 s of motion, plus settling (0.2 s) and rest.
  EXPECT_GT(num(t, "duration_ms"), 5400.0);
  EXPECT_LT(num(t, "duration_ms"), 5400.0 + 200.0 + 3000.0);
}

TEST(OdocalSimTrials, SquareTrialCountsGiveTheTurnOdometrySaw) {
  REQUIRE_SIM();
  std::vector<std::string> lines;
  ASSERT_EQ(run_sim("", "odom reset\nrun umbmark-ccw 0.5\ntrial\n", lines), 0);
  const auto r = replies(lines);
  ASSERT_EQ(r.size(), 3u);
  const auto t = pairs(r[2]);
  EXPECT_EQ(t.at("path"), "umbmark-ccw");
  // Four left turns of 90°: the right wheel runs 2π·b/2 farther than the left over the square,
  // i.e. (count_r − count_l)·mm_per_count = 2π·b (± the end heading odometry reports).
  const double turned_rad = (num(t, "count_r") - num(t, "count_l")) * kMmPerCount / kWheelbaseMm;
  const double end_heading_rad = num(t, "theta_deg") * kPi / 180.0;
  EXPECT_NEAR(turned_rad, 2.0 * kPi + end_heading_rad, 2.0 * kMmPerCount / kWheelbaseMm);
  EXPECT_NEAR(end_heading_rad, 0.0, 0.01);
}

TEST(OdocalSimTrials, TimedDriveIsATrialAndTrialsListsAndForgets) {
  REQUIRE_SIM();
  std::vector<std::string> lines;
  ASSERT_EQ(run_sim("",
                    "drive 0.1 0 1000\ndrive 0.1 0.2 800\ntrials\ntrial 1\ntrial 3\ntrial x\n"
                    "trials clear\ntrial\ntrials\ndrive 0.1 0\nstop\ntrials\n",
                    lines),
            0);
  const auto r = replies(lines);
  ASSERT_EQ(r.size(), 12u);
  int done = 0;
  for (const auto& l : lines) {
    done += l.rfind("# done trial=", 0) == 0 ? 1 : 0;
  }
  EXPECT_EQ(done, 2);  // the open-ended drive (stopped) is no trial
  EXPECT_EQ(r[2], "ok trials=2");
  const auto first = pairs(r[3]);
  EXPECT_EQ(first.at("path"), "drive");
  EXPECT_GE(num(first, "duration_ms"), 1000.0);
  EXPECT_LE(num(first, "duration_ms"), 1000.0 + 3000.0);
  // 1 s at 0.1 m/s (with the acceleration the wheel loop allows and some coasting).
  EXPECT_NEAR(num(first, "x_mm"), 100.0, 15.0);
  EXPECT_EQ(r[4].rfind("err no_trial", 0), 0u) << r[4];
  EXPECT_EQ(r[5].rfind("err bad_number", 0), 0u) << r[5];
  EXPECT_EQ(r[6], "ok trials=0");
  EXPECT_EQ(r[7].rfind("err no_trial", 0), 0u) << r[7];
  EXPECT_EQ(r[8], "ok trials=0");
  EXPECT_EQ(r[11], "ok trials=0");
}

TEST(OdocalSimTrials, StreamTicksGivesCumulativeCountsThatAgreeWithTheTrial) {
  REQUIRE_SIM();
  std::vector<std::string> lines;
  ASSERT_EQ(run_sim("", "stream ticks 100\ndrive 0.2 0 1000\nstream off\ntrial\n", lines), 0);
  std::vector<std::map<std::string, std::string>> ticks;
  for (const auto& l : lines) {
    if (l.rfind("# ticks ", 0) == 0) {
      ticks.push_back(pairs(l));
    }
  }
  ASSERT_GT(ticks.size(), 50u);
  for (std::size_t i = 1; i < ticks.size(); ++i) {
    EXPECT_GT(num(ticks[i], "t_ms"), num(ticks[i - 1], "t_ms"));
    EXPECT_GE(num(ticks[i], "count_l"), num(ticks[i - 1], "count_l"));  // forward only
  }
  const auto t = pairs(replies(lines).back());
  // Counts are cumulative since start-up: over the logged span they cover the trial.
  EXPECT_NEAR(num(ticks.back(), "count_l") - num(ticks.front(), "count_l"), num(t, "count_l"),
              0.05 * num(t, "count_l") + 10.0);
  // 100 Hz: one line per 10 ms of robot time.
  EXPECT_NEAR(num(ticks[1], "t_ms") - num(ticks[0], "t_ms"), 10.0, 1.0);
}

// CRC-16/CCITT-FALSE written out here, bit by bit from the top: the check the docs give for
// `stream ticks <hz> crc` (polynomial 0x1021, initial 0xFFFF, no reflection, no final XOR).
unsigned ccitt_false(const std::string& bytes) {
  unsigned crc = 0xFFFFu;
  for (const char ch : bytes) {
    for (int bit = 7; bit >= 0; --bit) {
      const bool top = ((crc >> 15u) & 1u) != ((static_cast<unsigned char>(ch) >> bit) & 1u);
      crc = ((crc << 1u) & 0xFFFFu) ^ (top ? 0x1021u : 0u);
    }
  }
  return crc;
}

// `stream ticks <hz> crc`: the same lines, each ending with ` crc=N`, N the CRC of the bytes
// before it; `stream ticks <hz>` again streams them without; a fourth word that is not `crc` is
// refused and changes nothing.
TEST(OdocalSimTrials, StreamTicksCrcEndsEachLineWithItsCheck) {
  REQUIRE_SIM();
  ASSERT_EQ(ccitt_false("123456789"), 0x29B1u);  // the standard check value
  std::vector<std::string> lines;
  ASSERT_EQ(run_sim("",
                    "stream ticks 100 sum\nstream ticks 100 crc\ndrive 0.2 0 500\n"
                    "stream ticks 100\ndrive 0.2 0 300\nstream off\n",
                    lines),
            0);
  const std::vector<std::string> r = replies(lines);
  ASSERT_GE(r.size(), 2u);
  EXPECT_EQ(r[0].rfind("err bad_argument", 0), 0u) << r[0];
  EXPECT_EQ(r[1].rfind("ok stream=ticks", 0), 0u) << r[1];
  std::size_t checked = 0, plain = 0;
  for (const std::string& l : lines) {
    if (l.rfind("# ticks ", 0) != 0) {
      continue;
    }
    const std::size_t at = l.find(" crc=");
    if (at == std::string::npos) {
      EXPECT_EQ(pairs(l).size(), 3u) << l;
      ++plain;
      continue;
    }
    EXPECT_EQ(plain, 0u) << "a checked line after the unchecked ones: " << l;
    EXPECT_EQ(pairs(l).size(), 4u) << l;
    EXPECT_EQ(l.substr(at + 5), std::to_string(ccitt_false(l.substr(0, at)))) << l;
    ++checked;
  }
  EXPECT_GT(checked, 30u);  // 0.5 s at 100 Hz, and the time to the next command
  EXPECT_GT(plain, 20u);
}

TEST(OdocalSimTrials, MeasureIsTheTruePoseInTheOdometryFrame) {
  REQUIRE_SIM();
  std::vector<std::string> lines;
  ASSERT_EQ(
      run_sim("", "measure\nrun line 1\nodom\nmeasure\nodom reset\nmeasure\nmeasure now\n", lines),
      0);
  const auto r = replies(lines);
  ASSERT_EQ(r.size(), 7u);
  // At start-up the frames coincide: the measurement is noise only (2 mm, 0.4° sigma; 6 sigma).
  EXPECT_NEAR(num(pairs(r[0]), "x_mm"), 0.0, 12.0);
  EXPECT_NEAR(num(pairs(r[0]), "theta_deg"), 0.0, 2.4);
  // After 1 m the real robot is where odometry thinks, up to its systematic error (E_d 1.002
  // bends a 1 m line by ~ 1000²·0.002/(2·150) ≈ 7 mm) and the noise.
  const auto odom = pairs(r[2]);
  const auto measured = pairs(r[3]);
  EXPECT_NEAR(num(measured, "x_mm"), num(odom, "x_mm"), 15.0);
  EXPECT_NEAR(num(measured, "y_mm"), num(odom, "y_mm"), 20.0);
  // After `odom reset` the odometry frame starts where the robot stands.
  EXPECT_NEAR(num(pairs(r[5]), "x_mm"), 0.0, 12.0);
  EXPECT_NEAR(num(pairs(r[5]), "y_mm"), 0.0, 12.0);
  EXPECT_EQ(r[6].rfind("err wrong_arity", 0), 0u) << r[6];
}

TEST(OdocalSimTrials, LateralOnTheRobotFromLineTrials) {
  REQUIRE_SIM();
  std::string script = "lateral add 990 5\nlateral solve\nlateral apply\n";
  for (int i = 0; i < 3; ++i) {
    script += "odom reset\nrun line 1\n";
    script += "lateral add " + std::to_string(995 + i) + " " + std::to_string(4 + i) + "\n";
  }
  script += "lateral add 990 5\nlateral solve\nlateral apply 1700000000\nprovenance\nget f_lat\n";
  std::vector<std::string> lines;
  ASSERT_EQ(run_sim("", script, lines), 0);
  const auto r = replies(lines);
  ASSERT_EQ(r.size(), 17u);
  EXPECT_EQ(r[0].rfind("err no_trial", 0), 0u) << r[0];
  EXPECT_EQ(r[1].rfind("err lateral_failed", 0), 0u) << r[1];
  EXPECT_EQ(r[2].rfind("err not_solved", 0), 0u) << r[2];
  const auto added = pairs(r[5]);
  EXPECT_EQ(added.at("lateral"), "1");
  // θ_L: the left wheel's turns over the 1 m line, 2·1000/60 rad nominally.
  EXPECT_NEAR(num(added, "theta_l_rad"), 2.0 * 1000.0 / kWheelMm, 0.05);
  EXPECT_EQ(r[12].rfind("err no_trial", 0), 0u) << r[12];  // that trial was added already
  const auto solved = pairs(r[13]);
  // Eq. 4 with equal diameters: F_lat = 1 + 4l·mean(atan(y/x))/(D·θ_L); eq. 5: F_lon = L/|mean|.
  const double theta_l = num(solved, "theta_l_rad");
  const double mean_angle =
      (std::atan(4.0 / 995.0) + std::atan(5.0 / 996.0) + std::atan(6.0 / 997.0)) / 3.0;
  EXPECT_NEAR(num(solved, "f_lat"), 1.0 + 4.0 * kWheelbaseMm * mean_angle / (kWheelMm * theta_l),
              1e-5);
  EXPECT_NEAR(num(solved, "f_lon"), 1000.0 / std::hypot(996.0, 5.0), 1e-5);
  EXPECT_EQ(pairs(r[15]).at("lateral_method"), "maddahi");
  EXPECT_EQ(pairs(r[15]).at("lateral_runs"), "3");
  EXPECT_NEAR(num(pairs(r[16]), "f_lat"), num(solved, "f_lat"), 1e-6);
}

TEST(OdocalSimTrials, ANoisyEncoderTripsTheFaultAndTheTrialIsAbandoned) {
  REQUIRE_SIM();
  const std::string robot = temp_file(
      "noisy_robot.json", R"({"encoder_fault": "left_noisy", "encoder_fault_after_s": 0.5})");
  std::vector<std::string> lines;
  ASSERT_EQ(run_sim("--robot " + robot, "run line 1\nstatus\ntrials\n", lines), 0);
  const auto r = replies(lines);
  ASSERT_EQ(r.size(), 3u);
  EXPECT_NE(pairs(r[1]).at("faults").find("encoder_left"), std::string::npos) << r[1];
  EXPECT_EQ(r[2], "ok trials=0");
}

TEST(OdocalSimTrials, ADeadEncoderChannelStallsTheWheel) {
  REQUIRE_SIM();
  const std::string robot = temp_file("dead_robot.json", R"({"encoder_fault": "right_dead"})");
  std::vector<std::string> lines;
  ASSERT_EQ(run_sim("--robot " + robot, "run line 1\nstatus\n", lines), 0);
  const auto r = replies(lines);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(pairs(r[1]).at("mode"), "fault") << r[1];
  EXPECT_NE(pairs(r[1]).at("faults").find("right"), std::string::npos) << r[1];
}

TEST(OdocalSimTrials, ABadEncoderFaultIsRefusedNamingTheKey) {
  REQUIRE_SIM();
  const std::string robot = temp_file("bad_fault.json", R"({"encoder_fault": "left_wobbly"})");
  std::vector<std::string> lines;
  EXPECT_EQ(run_sim("--robot " + robot, "version\n", lines), 2);
  std::ifstream err(::testing::TempDir() + "odocal_sim_trials_err.txt");
  const std::string text((std::istreambuf_iterator<char>(err)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("encoder_fault"), std::string::npos) << text;
}

}  // namespace
