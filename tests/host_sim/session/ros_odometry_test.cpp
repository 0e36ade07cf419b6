// An odocal robot driven by ROS gets calibrated odometry (DESIGN "ROS robots"; docs/ros.md): a
// ROS stack that sends diffdrive_arduino's bytes to odocal-sim's pty and turns the replies into
// odometry with diff_drive_controller's equations, configured with the values odocal writes into
// diff_drive_controller.yaml for the robot, ends a commanded 1 m line and a 360-degree turn where
// the simulator's truth says, within 0.1 %, on three generated robots.

#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>
#include <utility>

#include "model_in_force.hpp"
#include "session_harness.hpp"

namespace odocal_session_test {
namespace {

using odocal::host::session::Factors;
using odocal::host::session::RosGeometry;

/// The serial port as diffdrive_arduino's ArduinoComms uses it: raw, one write per command, one
/// line read back per command.
class Port {
 public:
  explicit Port(const std::string& path) : fd_(::open(path.c_str(), O_RDWR | O_NOCTTY)) {
    termios mode{};
    if (fd_ >= 0 && ::tcgetattr(fd_, &mode) == 0) {
      ::cfmakeraw(&mode);
      ::tcsetattr(fd_, TCSANOW, &mode);
    }
  }
  ~Port() {
    if (fd_ >= 0) {
      ::close(fd_);
    }
  }
  [[nodiscard]] bool open() const { return fd_ >= 0; }
  /// Writes `bytes`, returns the next line without its CR LF ("" after 10 s without one).
  std::string send_msg(const std::string& bytes) {
    EXPECT_EQ(::write(fd_, bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size()));
    std::string line;
    for (;;) {
      pollfd wait{fd_, POLLIN, 0};
      char c = 0;
      if (::poll(&wait, 1, 10000) <= 0 || ::read(fd_, &c, 1) != 1) {
        return line;
      }
      if (c == '\n') {
        return line;
      }
      if (c != '\r') {
        line += c;
      }
    }
  }

 private:
  int fd_ = -1;
};

/// diff_drive_controller as its source describes it (the ros2_controllers package: the wheel
/// commands of update(), odometry.cpp's update from positions and its exact integration), for
/// one wheel a side, written for this test.
class DiffDriveController {
 public:
  explicit DiffDriveController(const RosGeometry& g)
      : separation_(g.wheel_separation_m * g.separation_multiplier),
        left_radius_(g.wheel_radius_m * g.left_multiplier),
        right_radius_(g.wheel_radius_m * g.right_multiplier) {}

  /// The wheels' angular velocities (rad/s) for a body twist (cmd_vel).
  [[nodiscard]] std::pair<double, double> wheel_velocities(double linear, double angular) const {
    return {(linear - angular * separation_ / 2.0) / left_radius_,
            (linear + angular * separation_ / 2.0) / right_radius_};
  }

  /// One update from the wheels' positions (rad): each wheel's travel since the last update, the
  /// body's increment, integrated exactly (Runge-Kutta 2 when it hardly turns).
  void update(double left_rad, double right_rad) {
    const double left = left_rad * left_radius_;
    const double right = right_rad * right_radius_;
    const double linear = 0.5 * ((left - left_old_) + (right - right_old_));
    const double angular = ((right - right_old_) - (left - left_old_)) / separation_;
    left_old_ = left;
    right_old_ = right;
    if (std::fabs(angular) < 1e-6) {
      const double direction = heading_ + 0.5 * angular;
      x_ += linear * std::cos(direction);
      y_ += linear * std::sin(direction);
      heading_ += angular;
    } else {
      const double heading_old = heading_;
      const double r = linear / angular;
      heading_ += angular;
      x_ += r * (std::sin(heading_) - std::sin(heading_old));
      y_ += -r * (std::cos(heading_) - std::cos(heading_old));
    }
  }
  [[nodiscard]] double x() const { return x_; }
  [[nodiscard]] double y() const { return y_; }
  [[nodiscard]] double heading() const { return heading_; }

 private:
  double separation_;
  double left_radius_;
  double right_radius_;
  double left_old_ = 0.0;
  double right_old_ = 0.0;
  double x_ = 0.0;
  double y_ = 0.0;
  double heading_ = 0.0;
};

/// A robot: what the firmware is told and what it really is.
struct Robot {
  double diameter_mm;
  double wheelbase_mm;
  double counts_per_rev;
  double left_mm;  ///< true diameters and wheelbase
  double right_mm;
  double true_wheelbase_mm;
};

/// Three robots from a small generator: diameters 40 to 100 mm, wheelbases 2.5 to 3 diameters,
/// the true wheels off the nominal one by up to 1.5 % (ratios 1.005 to 1.015, either side larger)
/// and the true wheelbase by up to 2 %.
Robot generated_robot(int i) {
  const double diameter = 40.0 + 30.0 * i;
  const double wheelbase = diameter * (2.5 + 0.25 * i);
  const double ratio = 1.005 + 0.005 * i;
  const double sign = i % 2 == 0 ? 1.0 : -1.0;
  const double left = diameter * (1.0 - sign * 0.5 * (ratio - 1.0));
  const double right = diameter * (1.0 + sign * 0.5 * (ratio - 1.0));
  return Robot{diameter, wheelbase, 1440.0 + 560.0 * i, left, right, wheelbase * (0.98 + 0.02 * i)};
}

/// What a ROS stack on diffdrive_arduino (main branch) does with the robot on `port`: `e` read
/// at each update, turned into wheel angles (enc_counts_per_rev), the controller's odometry
/// updated; the twist asked turned into counts per 1/loop_rate s (loop_rate 30), `m` written.
class RosStack {
 public:
  RosStack(Port& port, const RosGeometry& g, double counts_per_rev)
      : port_(port), controller_(g), rads_per_count_(2.0 * std::numbers::pi / counts_per_rev) {
    EXPECT_EQ(port_.send_msg("\r"), "Invalid Command");
    EXPECT_EQ(port_.send_msg("u 30:20:0:100\r"), "OK");
  }
  /// One read() / update() / write() of the controller manager, asking for (linear, angular).
  void cycle(double linear, double angular) {
    const std::string counts = port_.send_msg("e\r");
    long left = 0;
    long right = 0;
    ASSERT_EQ(std::sscanf(counts.c_str(), "%ld %ld", &left, &right), 2) << counts;
    controller_.update(static_cast<double>(left) * rads_per_count_,
                       static_cast<double>(right) * rads_per_count_);
    const auto [left_radps, right_radps] = controller_.wheel_velocities(linear, angular);
    const int left_counts = static_cast<int>(left_radps / rads_per_count_ / 30.0);
    const int right_counts = static_cast<int>(right_radps / rads_per_count_ / 30.0);
    ASSERT_EQ(port_.send_msg("m " + std::to_string(left_counts) + " " +
                             std::to_string(right_counts) + "\r"),
              "OK");
  }
  /// The twist zero for 2 s (the controller's command after cmd_vel stops), the wheels at rest.
  void settle() {
    for (int i = 0; i < 20; ++i) {
      cycle(0.0, 0.0);
    }
  }
  [[nodiscard]] const DiffDriveController& odometry() const { return controller_; }

 private:
  Port& port_;
  DiffDriveController controller_;
  double rads_per_count_;
};

/// The simulator's truth: the robot's pose in the odometry frame (the tape without noise), m, rad.
struct Truth {
  double x = NAN;
  double y = NAN;
  double theta = NAN;
};
Truth truth(Port& port) {
  const std::string reply = port.send_msg("measure\n");
  Truth t;
  double theta_deg = NAN;
  EXPECT_EQ(
      std::sscanf(reply.c_str(), "ok x_mm=%lf y_mm=%lf theta_deg=%lf", &t.x, &t.y, &theta_deg), 3)
      << reply;
  t.x *= 1e-3;
  t.y *= 1e-3;
  t.theta = theta_deg * std::numbers::pi / 180.0;
  return t;
}

TEST(RosOdometry, AnOdocalRobotDrivenByRosEndsWhereItsOdometrySaysOnThreeRobots) {
  for (int i = 0; i < 3; ++i) {
    const Robot r = generated_robot(i);
    SCOPED_TRACE("robot " + std::to_string(i) + ": D " + std::to_string(r.diameter_mm) + " mm, b " +
                 std::to_string(r.wheelbase_mm) + " mm");
    const std::string robot =
        write("ros_robot_" + std::to_string(i) + ".json",
              "{\"wheel_diameter_mm\": " + std::to_string(r.diameter_mm) +
                  ", \"wheelbase_mm\": " + std::to_string(r.wheelbase_mm) +
                  ", \"counts_per_rev\": " + std::to_string(r.counts_per_rev) +
                  ", \"true_left_diameter_mm\": " + std::to_string(r.left_mm) +
                  ", \"true_right_diameter_mm\": " + std::to_string(r.right_mm) +
                  ", \"true_wheelbase_mm\": " + std::to_string(r.true_wheelbase_mm) +
                  ", \"slip_sigma\": 0, \"bump_height_mm\": 0, \"measure_sigma_mm\": 0}");
    // The robot calibrated: its factors in force are its true geometry (what a perfect
    // calibration reaches; the calibrations' own precision is tested elsewhere), saved.
    Factors f;
    f.c_l = r.left_mm / r.diameter_mm;
    f.c_r = r.right_mm / r.diameter_mm;
    f.wheelbase_mm = r.true_wheelbase_mm;
    const std::string store = temp("ros_robot_" + std::to_string(i) + ".store");
    std::remove(store.c_str());
    char apply[160];
    std::snprintf(apply, sizeof apply, "fit apply %.9f %.9f %.6f\nsave\n", f.c_l, f.c_r,
                  f.wheelbase_mm);
    ASSERT_EQ(shell(bin("odocal-sim") + " --robot " + robot + " --store " + store + " <" +
                    write("ros_apply.txt", apply))
                  .status,
              0);
    // The values odocal writes into diff_drive_controller.yaml for this robot.
    const RosGeometry g = odocal::host::session::ros_geometry_for_odocal(f, r.diameter_mm);
    EXPECT_EQ(g.left_multiplier, 1.0);
    EXPECT_EQ(g.right_multiplier, 1.0);
    EXPECT_EQ(g.separation_multiplier, 1.0);
    for (const bool turn : {false, true}) {
      SimOnPty sim(robot, store);
      Port port(sim.path());
      ASSERT_TRUE(port.open()) << sim.path();
      RosStack ros(port, g, r.counts_per_rev);
      if (!turn) {
        // cmd_vel 0.2 m/s ahead until the odometry says 1 m.
        for (int n = 0; n < 2000 && ros.odometry().x() < 1.0; ++n) {
          ros.cycle(0.2, 0.0);
        }
      } else {
        // cmd_vel 1 rad/s until the odometry says a whole turn.
        for (int n = 0; n < 2000 && ros.odometry().heading() < 2.0 * std::numbers::pi; ++n) {
          ros.cycle(0.0, 1.0);
        }
      }
      ros.settle();
      const Truth t = truth(port);
      const DiffDriveController& odom = ros.odometry();
      // 0.1 %: of the 1 m line for positions, of the whole turn for the heading.
      EXPECT_NEAR(odom.x(), t.x, 0.001) << (turn ? "turn" : "line");
      EXPECT_NEAR(odom.y(), t.y, 0.001) << (turn ? "turn" : "line");
      EXPECT_NEAR(std::remainder(odom.heading() - t.theta, 2.0 * std::numbers::pi), 0.0,
                  0.001 * 2.0 * std::numbers::pi)
          << (turn ? "turn" : "line");
      // It did what was asked (the odometry said so, and the truth agrees above): a metre ahead,
      // or a whole turn, and some more while the wheels braked (in lockstep the robot runs on
      // while it moves and the host computes its next line: how far depends on the host).
      if (!turn) {
        EXPECT_GE(odom.x(), 1.0);
      } else {
        EXPECT_GE(odom.heading(), 2.0 * std::numbers::pi);
      }
    }
  }
}

TEST(RosOdometry, AnOdocalSessionWritesTheYamlOfTheRobotInForce) {
  // Whatever the procedure leaves in force, the YAML is what ros_geometry_for_odocal says for it:
  // the nominal wheel, the wheelbase in force, multipliers 1.0, and it says it is a snippet.
  const std::string robot = write("ros_session_robot.json",
                                  "{\"true_left_diameter_mm\": 59.8, \"true_right_diameter_mm\": "
                                  "60.2, \"true_wheelbase_mm\": 152, \"slip_sigma\": 0}");
  const std::string out = temp("ros_session_out");
  static_cast<void>(shell("rm -rf " + out));
  const json doc = parse(session("--sim " + robot +
                                 " --procedure umbmark --side-m 1 --runs 2 --passes 1 --yes "
                                 "--json --out " +
                                 out));
  ASSERT_TRUE(doc.is_object());
  ASSERT_TRUE(doc["saved"].get<bool>());
  Factors f;
  f.c_l = doc["factors"]["c_l"].get<double>();
  f.c_r = doc["factors"]["c_r"].get<double>();
  f.wheelbase_mm = doc["factors"]["wheelbase_mm"].get<double>();
  f.f_lat = doc["factors"]["f_lat"].get<double>();
  f.f_lon = doc["factors"]["f_lon"].get<double>();
  const RosGeometry g = odocal::host::session::ros_geometry_for_odocal(f, 60.0);
  std::ifstream in(out + "/diff_drive_controller.yaml");
  const std::string yaml((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(yaml.find("A snippet: merge these keys"), std::string::npos) << yaml;
  const auto value = [&yaml](const std::string& key) {
    const auto at = yaml.find("    " + key + ": ");
    return at == std::string::npos ? NAN : std::stod(yaml.substr(at + key.size() + 6));
  };
  EXPECT_EQ(value("wheel_separation"), g.wheel_separation_m);
  EXPECT_NEAR(value("wheel_separation"), f.wheelbase_mm / 1000.0, 1e-12);
  EXPECT_EQ(value("wheel_radius"), 0.030);
  for (const char* key : {"wheel_separation_multiplier", "left_wheel_radius_multiplier",
                          "right_wheel_radius_multiplier"}) {
    EXPECT_EQ(value(key), 1.0) << key;
  }
  EXPECT_EQ(doc["result"]["ros"]["wheel_separation"].get<double>(), g.wheel_separation_m);
}

}  // namespace
}  // namespace odocal_session_test
