// The console's `selftest` on odocal-sim with every robot-file `wiring` fault (DESIGN "Wiring
// self-test"): it names the fault, `wiring_fix` fixes it, and a robot wired right passes and
// barely moves.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "sim_process.hpp"

namespace {

constexpr double kPi = 3.14159265358979323846;
// The default robot: 60 mm wheels, 150 mm wheelbase, 1440 counts per turn.
constexpr double kMmPerCount = kPi * 60.0 / 1440.0;
constexpr double kWheelbaseMm = 150.0;
// The test turns a wheel at a tenth of max_wheel_radps (25 rad/s) for 300 ms.
constexpr double kTestCounts = 0.1 * 25.0 * 0.3 * 1440.0 / (2.0 * kPi);
// The simulated tape measure's noise (2 mm, 0.4°): six sigma.
constexpr double kMeasureMm = 12.0;
constexpr double kMeasureDeg = 2.4;

using odocal::test::sim_program;
using odocal::test::temp_file;

std::vector<std::string> run_sim(const std::string& wiring, const std::string& script) {
  const std::string robot =
      temp_file("selftest_robot.json", "{\"wiring\": \"" + wiring + "\", \"slip_sigma\": 0}");
  return odocal::test::sim_replies("selftest", "--robot " + robot, script, true);
}

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

double num(const std::string& line, const std::string& key) {
  const auto p = pairs(line);
  const auto it = p.find(key);
  return it == p.end() ? std::nan("") : std::stod(it->second);
}

#define REQUIRE_SIM()                                                         \
  if (sim_program().empty()) {                                                \
    FAIL() << "odocal-sim not built (cmake --build --preset host builds it)"; \
  }

TEST(OdocalSimSelftest, RightWiredRobotHasNoFaultAndBarelyMoves) {
  REQUIRE_SIM();
  const auto r = run_sim("ok", "selftest\nmeasure\nstatus\n");
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(pairs(r[0]).at("faults"), "none") << r[0];
  // Each wheel turned forward about the commanded amount (plus its coasting), the other stood.
  const double ll = num(r[0], "ll");
  const double rr = num(r[0], "rr");
  EXPECT_GT(ll, 0.5 * kTestCounts);
  EXPECT_LT(ll, 2.0 * kTestCounts);
  EXPECT_GT(rr, 0.5 * kTestCounts);
  EXPECT_LT(rr, 2.0 * kTestCounts);
  EXPECT_LE(std::fabs(num(r[0], "lr")), 2.0);
  EXPECT_LE(std::fabs(num(r[0], "rl")), 2.0);
  // Barely moved: turning about one wheel moves the centre half that wheel's travel, so at most
  // half of both wheels' travel; the two turns cancel but for the difference of the wheels.
  const double travel_mm = 0.5 * (ll + rr) * kMmPerCount;
  EXPECT_LT(travel_mm, 30.0);
  EXPECT_LT(std::hypot(num(r[1], "x_mm"), num(r[1], "y_mm")), travel_mm + kMeasureMm);
  EXPECT_NEAR(num(r[1], "theta_deg"), 0.0,
              std::fabs(ll - rr) * kMmPerCount / kWheelbaseMm * 180.0 / kPi + kMeasureDeg);
  EXPECT_EQ(pairs(r[2]).at("mode"), "idle") << r[2];
  EXPECT_EQ(pairs(r[2]).at("faults"), "none") << r[2];
}

struct Fault {
  const char* wiring;
  const char* named;  ///< what the console calls it
  int fix;            ///< wiring_fix bits
  double turn_sign;   ///< heading change of `selftest <side>`: which wheel turned which way
  const char* side;
};
constexpr Fault kFaults[] = {
    // Left wheel backwards: the robot turns counter-clockwise; forward (the encoder is the one
    // reversed): clockwise.
    {"left_motor_reversed", "left_reversed", 1, +1.0, "left"},
    {"left_encoder_reversed", "left_reversed", 4, -1.0, "left"},
    // Right wheel backwards: clockwise; forward: counter-clockwise.
    {"right_motor_reversed", "right_reversed", 2, -1.0, "right"},
    {"right_encoder_reversed", "right_reversed", 8, +1.0, "right"},
    // Driving "left": the left wheel turns (its edges reach the right decoder): clockwise; the
    // right wheel turns (the left output drives it): counter-clockwise.
    {"encoders_swapped", "crossed", 16, -1.0, "left"},
    {"motors_swapped", "crossed", 32, +1.0, "left"},
};

TEST(OdocalSimSelftest, EveryWiringFaultIsNamedAndItsFixPassesTheNextTest) {
  REQUIRE_SIM();
  for (const Fault& f : kFaults) {
    SCOPED_TRACE(f.wiring);
    const auto r = run_sim(f.wiring, "selftest\nmeasure\nset wiring_fix " + std::to_string(f.fix) +
                                         "\nselftest\nstatus\n");
    ASSERT_EQ(r.size(), 5u);
    EXPECT_EQ(pairs(r[0]).at("faults"), f.named) << r[0];
    // Released as soon as the wrong count showed: the wheels turned less than a turn.
    EXPECT_LT(std::hypot(num(r[1], "x_mm"), num(r[1], "y_mm")), kPi * 60.0) << r[1];
    EXPECT_EQ(r[2].rfind("ok", 0), 0u) << r[2];
    EXPECT_EQ(pairs(r[3]).at("faults"), "none") << r[3];
    EXPECT_EQ(pairs(r[4]).at("mode"), "idle") << r[4];
  }
}

TEST(OdocalSimSelftest, OneWheelAloneTurnsTheRobotTheWayThatTellsMotorFromEncoder) {
  REQUIRE_SIM();
  for (const Fault& f : kFaults) {
    SCOPED_TRACE(f.wiring);
    const auto r = run_sim(f.wiring, std::string("selftest ") + f.side + "\nmeasure\n");
    ASSERT_EQ(r.size(), 2u);
    EXPECT_EQ(pairs(r[0]).at("faults"), f.named) << r[0];
    // At least a quarter of the test's counts on one wheel turns the robot by that travel over
    // the wheelbase: far above the tape measure's noise.
    const double min_deg = 0.25 * kTestCounts * kMmPerCount / kWheelbaseMm * 180.0 / kPi;
    EXPECT_GT(f.turn_sign * num(r[1], "theta_deg"), min_deg) << r[1];
  }
}

TEST(OdocalSimSelftest, ABadWheelIsRefused) {
  REQUIRE_SIM();
  const auto r = run_sim("ok", "selftest up\nselftest left right\n");
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].rfind("err bad_argument", 0), 0u) << r[0];
  EXPECT_EQ(r[1].rfind("err wrong_arity", 0), 0u) << r[1];
}

}  // namespace
