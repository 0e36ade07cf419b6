// `odocal session --procedure selftest` end to end on odocal-sim (DESIGN "Wiring self-test"):
// every wiring fault the simulator builds is named, its fix applied with --yes and saved, and the
// next self-test finds nothing; a robot wired right gets no fault; without --yes or a terminal
// the fix is only proposed.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "session_harness.hpp"

namespace {

using nlohmann::json;
// The programs under test and running them: the session tests' shared harness.
using odocal_session_test::bin;
using odocal_session_test::Result;
using odocal_session_test::shell;

std::string temp(const std::string& name) {
  return odocal_session_test::test_dir() + "odocal_selftest_" + name;
}

/// A session on a fresh simulated robot with `wiring`; its JSON.
json selftest_session(const std::string& wiring, const std::string& flags, Result& r) {
  const std::string robot = temp(wiring + ".json");
  std::ofstream(robot) << R"({"slip_sigma": 0, "bump_height_mm": 0, "wiring": ")" << wiring
                       << "\"}";
  const std::string store = temp(wiring + ".store");
  const std::string out = temp(wiring + "_out");
  std::remove(store.c_str());
  std::system(("rm -rf " + out).c_str());
  r = shell(bin("odocal") + " session --sim " + robot + " --store " + store +
            " --procedure selftest --json --out " + out + " " + flags + " </dev/null");
  EXPECT_EQ(r.status, 0) << r.err;
  json doc = json::parse(r.out, nullptr, false);
  EXPECT_TRUE(doc.is_object()) << r.out << r.err;
  return doc;
}

TEST(SessionSelftest, ARightWiredRobotHasNoFaultAndNothingIsChanged) {
  Result r;
  const json doc = selftest_session("ok", "--yes", r);
  ASSERT_TRUE(doc.is_object());
  EXPECT_EQ(doc["procedure"], "selftest");
  EXPECT_EQ(doc["result"]["faults"], json::array());
  EXPECT_EQ(doc["result"]["fixed"], json::object());
  EXPECT_FALSE(doc["applied"].get<bool>());
  EXPECT_EQ(doc["runs"].size(), 0u);  // nothing to tell apart: no measured run
}

TEST(SessionSelftest, EveryWiringFaultIsNamedFixedSavedAndGoneOnTheNextTest) {
  const struct {
    const char* wiring;
    int fix;
  } cases[] = {{"left_motor_reversed", 1},   {"right_motor_reversed", 2},
               {"left_encoder_reversed", 4}, {"right_encoder_reversed", 8},
               {"encoders_swapped", 16},     {"motors_swapped", 32}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.wiring);
    Result r;
    const json doc = selftest_session(c.wiring, "--yes", r);
    ASSERT_TRUE(doc.is_object());
    EXPECT_EQ(doc["result"]["faults"], json::array({c.wiring})) << doc["result"].dump();
    EXPECT_EQ(doc["result"]["fixed"], json({{"wiring_fix", c.fix}}));
    EXPECT_EQ(doc["result"]["after"], json::array());
    EXPECT_TRUE(doc["applied"].get<bool>());
    EXPECT_TRUE(doc["saved"].get<bool>());
    // One wheel alone, measured, told the look-alikes apart; the same wheel again with the fix
    // turned the robot the way the fix predicts.
    EXPECT_EQ(doc["runs"].size(), 2u);
    const std::string side = std::string(c.wiring).rfind("right", 0) == 0 ? "right" : "left";
    EXPECT_EQ(doc["result"]["checked_by_motion"], json::array({side}));
    EXPECT_NE(r.err.find("Fault: " + std::string(c.wiring)), std::string::npos) << r.err;
  }
}

TEST(SessionSelftest, WithoutYesOrATerminalTheFixIsOnlyProposed) {
  Result r;
  const json doc = selftest_session("left_encoder_reversed", "", r);
  ASSERT_TRUE(doc.is_object());
  EXPECT_EQ(doc["result"]["faults"], json::array({"left_encoder_reversed"}));
  EXPECT_EQ(doc["result"]["fixed"], json::object());
  EXPECT_FALSE(doc["applied"].get<bool>());
  EXPECT_NE(r.err.find("set wiring_fix 4"), std::string::npos) << r.err;
}

TEST(SessionSelftest, AHeadingTypedWithTheWrongSignIsCaughtByTheMotionTheFixPredicts) {
  // A reversed left encoder. The person types the diagnosis run's heading with the wrong sign:
  // the session proposes a reversed left motor, and the check motion (the left wheel driven
  // again, with that fix) turns the robot counter-clockwise, where a fixed robot turns
  // clockwise. The fix is taken back; exit 2.
  const std::string robot = temp("wrong_sign.json");
  std::ofstream(robot) << R"({"slip_sigma": 0, "bump_height_mm": 0, "wiring": )"
                       << R"("left_encoder_reversed"})";
  const std::string store = temp("wrong_sign.store");
  std::remove(store.c_str());
  // What the tape shows: the left wheel alone turned the robot clockwise (a reversed encoder,
  // the wheel went forward); typed +12.0 instead of -12.0. Then, the wrong fix applied, the
  // left wheel goes backwards: counter-clockwise, +12.0.
  const std::string readings = temp("wrong_sign.csv");
  std::ofstream(readings) << "x_mm,y_mm,theta_deg\n-2.0,3.0,12.0\n2.0,-3.0,12.0\n";
  const std::string out = temp("wrong_sign_out");
  std::system(("rm -rf " + out).c_str());
  const Result r = shell(bin("odocal") + " session --sim " + robot + " --store " + store +
                         " --procedure selftest --yes --measurements " + readings + " --out " +
                         out + " </dev/null");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("the fix does not hold"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("wrong sign"), std::string::npos) << r.err;
  // Nothing kept: the robot's wiring_fix is what it was (0).
  EXPECT_EQ(odocal_session_test::stored(robot, store, "wiring_fix"), 0.0);
}

}  // namespace
