// Robot-file `wiring` faults (DESIGN "Wiring self-test") against the firmware's `wiring_fix`
// parameter: each fault makes the robot misbehave, and the matching fix makes it drive as a
// robot wired right does (the same plant, the same seed: the fixes only re-route signals).

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "odocal/drive/drive_config.hpp"
#include "odocal/host/sim_robot.hpp"

namespace odocal::host {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct Case {
  WiringFault fault;
  std::uint32_t fix;
};
constexpr Case kCases[] = {
    {WiringFault::left_motor_reversed, drive::invert_left_motor},
    {WiringFault::right_motor_reversed, drive::invert_right_motor},
    {WiringFault::left_encoder_reversed, drive::invert_left_encoder},
    {WiringFault::right_encoder_reversed, drive::invert_right_encoder},
    {WiringFault::encoders_swapped, drive::swap_encoders},
    {WiringFault::motors_swapped, drive::swap_motors},
};

RobotSpec quiet_spec(WiringFault wiring) {
  RobotSpec spec = default_robot();
  spec.truth.slip_sigma = 0.0;
  spec.truth.bump_height_m = 0.0;
  spec.wiring = wiring;
  return spec;
}

/// Drives `v`, `w` for `ms` (a console `drive v w ms`), waits until the wheels are at rest (or a
/// fault parks them) and returns the true pose.
sim::WorldPose timed_drive(const RobotSpec& spec, std::uint32_t fix, float v, float w,
                           std::uint32_t ms) {
  SimulatedRobot robot(spec, 1u);
  drive::DriveConfig config = spec.nominal;
  config.wiring_fix = fix;
  EXPECT_TRUE(robot.configure(config));
  robot.tick_once();
  EXPECT_TRUE(robot.loop().drive(drive::Twist{v, w}, ms));
  // The drive, then up to the 1 s the brakes are given.
  robot.run_until_ns(robot.plant().now_ns() + (ms + 1500u) * 1000000ull);
  return robot.plant().pose();
}

TEST(Wiring, RightWiredRobotDrivesTheCommandedLine) {
  // 0.2 m/s for 2 s: 400 mm, less the start-up lag of the speed loop, plus braking (the drive
  // stop test bounds both to a few centimetres at this speed).
  const sim::WorldPose end = timed_drive(quiet_spec(WiringFault::ok), 0u, 0.2f, 0.0f, 2000u);
  EXPECT_NEAR(end.x_m, 0.4, 0.03);
  // E_d = 1.002 bends 0.4 m by about 0.4²·0.002/(2·0.15) ≈ 1 mm.
  EXPECT_NEAR(end.y_m, 0.0, 0.005);
  EXPECT_NEAR(end.theta_rad, 0.0, 2.0 * kPi / 180.0);
}

TEST(Wiring, EveryFaultMisbehavesOnALineOrATurn) {
  const sim::WorldPose line_ok = timed_drive(quiet_spec(WiringFault::ok), 0u, 0.2f, 0.0f, 2000u);
  const sim::WorldPose turn_ok = timed_drive(quiet_spec(WiringFault::ok), 0u, 0.0f, 1.0f, 1000u);
  for (const Case& c : kCases) {
    SCOPED_TRACE(to_string(c.fault));
    const sim::WorldPose line = timed_drive(quiet_spec(c.fault), 0u, 0.2f, 0.0f, 2000u);
    const sim::WorldPose turn = timed_drive(quiet_spec(c.fault), 0u, 0.0f, 1.0f, 1000u);
    // Off by more than a decimetre or ten degrees somewhere: no calibration explains that.
    const double off_m = std::fmax(std::hypot(line.x_m - line_ok.x_m, line.y_m - line_ok.y_m),
                                   std::hypot(turn.x_m - turn_ok.x_m, turn.y_m - turn_ok.y_m));
    const double off_rad = std::fmax(std::fabs(line.theta_rad - line_ok.theta_rad),
                                     std::fabs(turn.theta_rad - turn_ok.theta_rad));
    EXPECT_TRUE(off_m > 0.1 || off_rad > 10.0 * kPi / 180.0)
        << "off " << off_m << " m, " << off_rad << " rad";
  }
}

TEST(Wiring, EachFixMakesTheLineAndTheTurnThoseOfARightWiredRobot) {
  const sim::WorldPose line_ok = timed_drive(quiet_spec(WiringFault::ok), 0u, 0.2f, 0.0f, 2000u);
  const sim::WorldPose turn_ok = timed_drive(quiet_spec(WiringFault::ok), 0u, 0.0f, 1.0f, 1000u);
  for (const Case& c : kCases) {
    SCOPED_TRACE(to_string(c.fault));
    const sim::WorldPose line = timed_drive(quiet_spec(c.fault), c.fix, 0.2f, 0.0f, 2000u);
    const sim::WorldPose turn = timed_drive(quiet_spec(c.fault), c.fix, 0.0f, 1.0f, 1000u);
    // About 400 mm straight ahead, as the right-wired robot; the same robot up to which wheel's
    // encoder edge comes first (a count, 0.13 mm) and, with swapped motors, the wheels' 0.2 %
    // diameter difference acting on the other side.
    EXPECT_NEAR(line.x_m, 0.4, 0.03);
    EXPECT_NEAR(line.x_m, line_ok.x_m, 0.002);
    EXPECT_NEAR(line.y_m, line_ok.y_m, 0.002);
    EXPECT_NEAR(turn.theta_rad, turn_ok.theta_rad, 0.5 * kPi / 180.0);
  }
}

TEST(Wiring, RobotFileTakesEveryFaultAndRefusesAnUnknownOneNamingTheAllowed) {
  for (const Case& c : kCases) {
    RobotSpec spec;
    std::string error;
    ASSERT_TRUE(parse_robot(std::string("{\"wiring\": \"") + to_string(c.fault) + "\"}", "r.json",
                            spec, error))
        << error;
    EXPECT_EQ(spec.wiring, c.fault);
  }
  RobotSpec spec;
  std::string error;
  EXPECT_FALSE(parse_robot(R"({"wiring": "left_wheel_missing"})", "r.json", spec, error));
  EXPECT_NE(error.find("r.json: wiring: must be one of \"ok\", \"left_motor_reversed\""),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("\"motors_swapped\""), std::string::npos) << error;
  EXPECT_FALSE(parse_robot(R"({"wiring": 3})", "r.json", spec, error));
}

}  // namespace
}  // namespace odocal::host
