// ROS robots (DESIGN "ROS robots"): odocal-sim as a robot running ROSArduinoBridge, and `odocal
// session --protocol ros-arduino-bridge` calibrating such robots with no reflash.
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "session_harness.hpp"
#include "session_person.hpp"

namespace odocal_session_test {
namespace {

/// The reply lines of `odocal-sim --protocol ros-arduino-bridge` to `bytes` on its stdin.
std::vector<std::string> bridge_lines(const std::string& name, const std::string& robot,
                                      const std::string& bytes) {
  const std::string input = write(name, bytes);
  const Result r =
      shell(bin("odocal-sim") + " --protocol ros-arduino-bridge --robot " + robot + " <" + input);
  EXPECT_EQ(r.status, 0) << r.err;
  std::vector<std::string> lines;
  std::string line;
  for (char c : r.out) {
    if (c == '\n') {
      lines.push_back(line);
      line.clear();
    } else if (c != '\r') {
      line += c;
    }
  }
  EXPECT_NE(r.out.find("\r\n"), std::string::npos) << "ROSArduinoBridge ends replies with CR LF";
  return lines;
}

std::pair<long, long> counts(const std::string& line) {
  long l = 0;
  long r = 0;
  EXPECT_EQ(std::sscanf(line.c_str(), "%ld %ld", &l, &r), 2) << line;
  return {l, r};
}

// diffdrive_arduino's bytes, each ended by a bare CR: "\r", "e\r", "m a b\r", "u p:d:i:o\r",
// and the rest of ROSArduinoBridge's base commands.
TEST(SessionBridge, OdocalSimAnswersAsROSArduinoBridge) {
  const std::string robot = write("bridge_robot.json", "{}");
  std::string bytes = "\rb\ru 20:12:0:50\re\rx\rr\rm 30 30\r";
  for (int i = 0; i < 150; ++i) {  // 5 s of frames, one per `e`: the auto-stop comes at 2 s
    bytes += "e\r";
  }
  bytes += "r\re\rmeasure\r";
  const std::vector<std::string> lines = bridge_lines("bridge_in.txt", robot, bytes);
  ASSERT_EQ(lines.size(), 7u + 150u + 3u);
  EXPECT_EQ(lines[0], "Invalid Command");
  EXPECT_EQ(lines[1], "57600");  // ROSArduinoBridge's BAUDRATE
  EXPECT_EQ(lines[2], "OK");
  EXPECT_EQ(lines[3], "0 0");
  EXPECT_EQ(lines[4], "OK");  // `x`: analogWrite
  EXPECT_EQ(lines[5], "OK");
  EXPECT_EQ(lines[6], "OK");
  // Frames 30-59 (1 s to 2 s after the `m`): the PID holds 30 counts per frame; its integer
  // arithmetic leaves an error of up to Ko/Kp = 2.5 counts per frame uncorrected.
  const auto at1 = counts(lines[7 + 29]);
  const auto at2 = counts(lines[7 + 59]);
  EXPECT_NEAR(static_cast<double>(at2.first - at1.first) / 30.0, 30.0, 2.5);
  EXPECT_NEAR(static_cast<double>(at2.second - at1.second) / 30.0, 30.0, 2.5);
  // Stopped after 2 s without an `m`, and at rest a second later: the last 30 frames count
  // nothing.
  const auto late = counts(lines[7 + 119]);
  const auto last = counts(lines[7 + 149]);
  EXPECT_EQ(late, last);
  EXPECT_GT(last.first, at2.first);  // it coasted on after the stop
  // 60 frames of driving at 30 counts per frame, then a coast: far below 150 frames' worth.
  EXPECT_LT(last.first, 150 * 30 / 2);
  EXPECT_EQ(lines[157], "OK");
  EXPECT_EQ(lines[158], "0 0");  // `r`: the counts to zero
  // The tape measures in the frame of the last `r`: the robot stands where that was.
  EXPECT_EQ(lines[159].rfind("ok x_mm=", 0), 0u) << lines[159];
  double x = NAN, y = NAN, theta = NAN;
  ASSERT_EQ(std::sscanf(lines[159].c_str(), "ok x_mm=%lf y_mm=%lf theta_deg=%lf", &x, &y, &theta),
            3);
  EXPECT_LT(std::hypot(x, y), 10.0);  // the default robot's tape noise is a few mm
}

TEST(SessionBridge, OdocalSimsBridgeRobotReadsLinesAsTheFirmwareDoes) {
  // loop() in ROSArduinoBridge.ino: only a CR runs a command; a space steps to the next
  // argument; every other byte is the letter (before a space) or part of an argument, LF too.
  // runCommand reads the arguments with atoi and answers the pin and sonar commands of a
  // USE_BASE build; raw PWM `o` is joshnewans' firmware's.
  const std::string robot = write("bridge_reader.json", "{}");
  const std::string bytes =
      "e\n"        // ended by LF alone: no reply, and its bytes stay in the command...
      "b\r"        // ... whose letter the `b` then replaces: the baud rate
      "m 10 10\n"  // no reply; the `e` after it runs on into the second argument
      "e\r"        // "m 10 10\ne": atoi reads 10 and 10, the firmware answers `m`
      "m 0 0\r"
      "a 3\rd 4\rp 7\rc 13 1\rw 13 1\rx 5 9\ro 0 0\rs 1 90\r"
      "m 1.5 2\re\rm x y\r"  // atoi: 1 and 2; no digits: 0 0, a stop
      "e\r\ne\r";            // CR LF: the LF is the next command's first letter, replaced by `e`
  const std::vector<std::string> lines = bridge_lines("bridge_reader_in.txt", robot, bytes);
  const std::vector<std::string> want = {
      "57600", "OK", "OK", "0", "0", "0", "OK", "OK", "OK", "OK", "Invalid Command"};
  ASSERT_GE(lines.size(), want.size() + 5u);
  for (std::size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(lines[i], want[i]) << "reply " << i;
  }
  EXPECT_EQ(lines[11], "OK");            // m 1.5 2
  static_cast<void>(counts(lines[12]));  // two whole numbers
  EXPECT_EQ(lines[13], "OK");            // m x y
  static_cast<void>(counts(lines[14]));
  static_cast<void>(counts(lines[15]));
  EXPECT_EQ(lines.size(), want.size() + 5u);
}

TEST(SessionBridge, OdocalSimRefusesWhatABridgeRobotHasNot) {
  const std::string robot = write("bridge_miswired.json", "{\"wiring\": \"encoders_swapped\"}");
  Result r =
      shell(bin("odocal-sim") + " --protocol ros-arduino-bridge --robot " + robot + " </dev/null");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("wiring"), std::string::npos) << r.err;
  r = shell(bin("odocal-sim") + " --protocol ros-arduino-bridge --store " + temp("bridge.store") +
            " </dev/null");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--store"), std::string::npos) << r.err;
  r = shell(bin("odocal-sim") + " --protocol ros-bridge </dev/null");
  EXPECT_EQ(r.status, 2);
}

TEST(SessionBridge, RefusesFlagsThatDoNotFit) {
  const std::string robot = write("bridge_flags.json", "{}");
  struct Case {
    std::string args;
    std::string names;
  };
  const Case cases[] = {
      {"--port /dev/null --protocol ros-arduino-bridge --procedure auto --wheelbase-mm 150 "
       "--counts-per-rev 1440",
       "--wheel-diameter-mm"},
      {"--sim " + robot + " --protocol ros-arduino-bridge --procedure umbmark", "--procedure"},
      {"--sim " + robot + " --protocol ros-arduino-bridge --procedure auto --store " +
           temp("bridge_flags.store"),
       "--store"},
      {"--sim " + robot + " --procedure auto --wheelbase-mm 150", "--wheelbase-mm"},
  };
  for (const Case& c : cases) {
    const std::string out = temp("bridge_flags_out");
    const Result r = session(c.args + " --out " + out);
    EXPECT_EQ(r.status, 2) << c.args;
    EXPECT_NE(r.err.find(c.names), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_FALSE(exists(out + "/session.json")) << c.args;  // nothing started
  }
}

/// diff_drive_controller.yaml's `key: value` lines.
std::map<std::string, std::string> yaml_values(const std::string& path) {
  std::ifstream in(path);
  std::map<std::string, std::string> values;
  for (std::string line; std::getline(in, line);) {
    const auto colon = line.find(": ");
    const auto key_start = line.find_first_not_of(' ');
    if (line.empty() || line[0] == '#' || colon == std::string::npos) {
      continue;
    }
    values[line.substr(key_start, colon - key_start)] = line.substr(colon + 2);
  }
  return values;
}

struct BridgeRobot {
  const char* name;
  double diameter_mm, wheelbase_mm, counts_per_rev;             // what the owner says
  double true_left_mm, true_right_mm, true_wheelbase_mm, slip;  // the robot
  unsigned seed;
};

// Robots of several sizes, none the default: each calibrated within the default budget of a
// ROSArduinoBridge session, 12 tape measurements (the self-test needs none on a well-wired robot),
// the YAML's effective geometry within the issue's tolerances of the truth: the wheel ratio within
// 5e-4, the size within 0.2 %, the wheelbase within 0.3 % (a tape of 2 mm over 3 m lines and 6-turn
// spins pins each to about a tenth of that with 10 calibration runs: docs/ros.md).
TEST(SessionBridge, CalibratesROSArduinoBridgeRobotsOfSeveralSizes) {
  const BridgeRobot robots[] = {
      {"micromouse", 32.0, 80.0, 2048.0, 32.21, 32.08, 81.1, 0.002, 3},
      {"lab", 70.0, 180.0, 2000.0, 69.62, 69.9, 177.9, 0.002, 5},
      {"cart", 150.0, 450.0, 4096.0, 151.3, 150.8, 457.0, 0.004, 7},
  };
  for (const BridgeRobot& b : robots) {
    SCOPED_TRACE(b.name);
    const std::string robot = write(std::string("bridge_") + b.name + ".json",
                                    json{{"wheel_diameter_mm", b.diameter_mm},
                                         {"wheelbase_mm", b.wheelbase_mm},
                                         {"counts_per_rev", b.counts_per_rev},
                                         {"true_left_diameter_mm", b.true_left_mm},
                                         {"true_right_diameter_mm", b.true_right_mm},
                                         {"true_wheelbase_mm", b.true_wheelbase_mm},
                                         {"slip_sigma", b.slip}}
                                        .dump());
    const std::string out = temp(std::string("bridge_out_") + b.name);
    static_cast<void>(shell("rm -rf " + out));  // a session of an earlier test run
    // The cart's controller manager runs at 50 Hz and averages 4 velocities; the others keep
    // the controller's defaults (100 Hz, 10).
    const bool cart = std::string(b.name) == "cart";
    const Result r = session("--sim " + robot +
                             " --protocol ros-arduino-bridge --procedure auto --json --seed " +
                             std::to_string(b.seed) + " --out " + out +
                             (cart ? " --ros-update-rate-hz 50 --ros-velocity-window 4" : ""));
    const json doc = parse(r);
    ASSERT_TRUE(doc.is_object());
    EXPECT_LE(doc["measurements"].get<int>(), 12);
    EXPECT_EQ(doc["result"]["max_measurements"].get<int>(), 12);  // the default, said
    EXPECT_TRUE(doc["applied"].get<bool>());
    EXPECT_FALSE(doc["saved"].get<bool>());  // nothing is written to such a robot
    const auto y = yaml_values(out + "/diff_drive_controller.yaml");
    ASSERT_EQ(y.count("wheel_separation_multiplier"), 1u) << r.err;
    const double radius = std::stod(y.at("wheel_radius"));
    const double separation = std::stod(y.at("wheel_separation"));
    EXPECT_DOUBLE_EQ(radius, b.diameter_mm / 2000.0);
    EXPECT_DOUBLE_EQ(separation, b.wheelbase_mm / 1000.0);
    const double left = 2000.0 * radius * std::stod(y.at("left_wheel_radius_multiplier"));
    const double right = 2000.0 * radius * std::stod(y.at("right_wheel_radius_multiplier"));
    const double wheelbase = 1000.0 * separation * std::stod(y.at("wheel_separation_multiplier"));
    EXPECT_NEAR(right / left, b.true_right_mm / b.true_left_mm, 5e-4);
    EXPECT_NEAR((left + right) / (b.true_left_mm + b.true_right_mm), 1.0, 0.002);
    EXPECT_NEAR(wheelbase / b.true_wheelbase_mm, 1.0, 0.003);
    ASSERT_EQ(y.count("pose_covariance_diagonal"), 1u);
    EXPECT_EQ(y.count("twist_covariance_diagonal"), 1u);
    // x and heading variances: positive (a zero would tell ROS the odometry never drifts).
    const json pose = json::parse(y.at("pose_covariance_diagonal"));
    EXPECT_GT(pose[0].get<double>(), 0.0);
    EXPECT_GT(pose[5].get<double>(), 0.0);
    // The twist's as the controller estimates it (docs/ros.md): the mean over W updates of
    // 1/f s, at 0.2 m/s, against the pose's after 1 m: twist / pose = 0.2 f / W for x and yaw.
    const json twist = json::parse(y.at("twist_covariance_diagonal"));
    const double ratio = cart ? 0.2 * 50.0 / 4.0 : 0.2 * 100.0 / 10.0;
    EXPECT_NEAR(twist[0].get<double>() / pose[0].get<double>(), ratio, 1e-9 * ratio);
    EXPECT_NEAR(twist[5].get<double>() / pose[5].get<double>(), ratio, 1e-9 * ratio);
    std::ifstream yaml_file(out + "/diff_drive_controller.yaml");
    const std::string yaml((std::istreambuf_iterator<char>(yaml_file)),
                           std::istreambuf_iterator<char>());
    EXPECT_NE(yaml.find(cart ? "update rate 50 Hz, velocity_rolling_window_size 4"
                             : "update rate 100 Hz, velocity_rolling_window_size 10"),
              std::string::npos)
        << yaml;
    // The same numbers in the session's JSON.
    EXPECT_DOUBLE_EQ(doc["result"]["ros"]["wheel_separation_multiplier"].get<double>(),
                     std::stod(y.at("wheel_separation_multiplier")));
  }
}

/// Whether the bridge robot's wheels stand still: `e` on its pty 45 times (in lockstep, 1.5 s of
/// robot time: the wheels coast to rest after a stop, and a robot still told to move would still
/// move, its 2 s auto-stop not yet due), the last two readings equal.
bool wheels_still(const std::string& pty) {
  const int fd = ::open(pty.c_str(), O_RDWR | O_NOCTTY);
  EXPECT_GE(fd, 0) << pty;
  termios raw{};
  ::tcgetattr(fd, &raw);
  ::cfmakeraw(&raw);
  ::tcsetattr(fd, TCSANOW, &raw);
  const auto ask = [fd] {
    static_cast<void>(::write(fd, "e\r", 2));
    std::string reply;
    char c = 0;
    while (reply.find('\n') == std::string::npos) {
      pollfd wait{fd, POLLIN, 0};
      if (::poll(&wait, 1, 2000) <= 0 || ::read(fd, &c, 1) != 1) {
        break;
      }
      reply += c;
    }
    return reply;
  };
  std::string previous, last;
  for (int frame = 0; frame < 45; ++frame) {
    previous = last;
    last = ask();
  }
  ::close(fd);
  EXPECT_FALSE(last.empty());
  return !last.empty() && last == previous;
}

// The robot of the way-out and reset tests: 60 mm wheels 0.33 % apart, a wheelbase 1.3 % wider
// than told, no slip, an exact tape (the faults are what the tests are about).
constexpr const char* kSmallBridgeRobot =
    R"({"wheel_diameter_mm": 60, "wheelbase_mm": 150, "counts_per_rev": 1440,
        "true_left_diameter_mm": 59.9, "true_right_diameter_mm": 60.1, "true_wheelbase_mm": 152,
        "slip_sigma": 0, "measure_sigma_mm": 0})";

// A ROSArduinoBridge robot on a serial port, the person at the session interrupting it while it
// drives (SIGINT), at a reading (SIGTERM) and at the Enter before a run (end of input): each time
// the wheels are stopped, every reading kept, and `--resume` goes on; the last session ends
// complete with the YAML, and nothing was ever written to the robot (it has nowhere to).
TEST(SessionBridge, EveryWayOutStopsTheRobotKeepsItsReadingsAndResumes) {
  ::signal(SIGPIPE, SIG_IGN);
  const std::string robot = write("bridge_exit.json", kSmallBridgeRobot);
  SimOnPty sim(robot, "", "0", "ros-arduino-bridge");
  ASSERT_FALSE(sim.path().empty());
  const std::string out = temp("bridge_exit_out");
  static_cast<void>(shell("rm -rf " + out));
  enum class Way { sigint_driving, sigterm_reading, end_of_input_enter, none };
  const Way ways[] = {Way::sigint_driving, Way::sigterm_reading, Way::end_of_input_enter,
                      Way::none};
  std::size_t kept = 0;
  for (const Way way : ways) {
    SCOPED_TRACE(static_cast<int>(way));
    std::vector<std::string> args = {"--port", sim.path(), "--json"};
    if (kept == 0 && way == Way::sigint_driving) {
      args.insert(args.end(), {"--protocol", "ros-arduino-bridge", "--wheel-diameter-mm", "60",
                               "--wheelbase-mm", "150", "--counts-per-rev", "1440", "--procedure",
                               "fit", "--runs", "4", "--side-m", "0.4", "--out", out});
    } else {
      args.insert(args.end(), {"--resume", out});
    }
    Person p(args);
    std::size_t enters = 0, readings = 0;
    bool stopped = false;
    const auto deadline = PersonClock::now() + std::chrono::seconds(180);
    while (!stopped && !p.closed() && PersonClock::now() < deadline) {
      if (p.count("press Enter to start") > enters) {
        if (way == Way::end_of_input_enter) {
          p.close_input();
          stopped = true;
          break;
        }
        p.type("");
        ++enters;
      } else if (p.count("Measured stop point") > readings) {
        if (way == Way::sigterm_reading) {
          p.signal(SIGTERM);
          stopped = true;
          break;
        }
        p.type(odometry_reading(p));
        ++readings;
      } else if (way == Way::sigint_driving && enters == 1 && p.count("Run ") >= 2) {
        ::usleep(500000);  // half a second into the run
        p.signal(SIGINT);
        stopped = true;
        break;
      }
      static_cast<void>(p.wait_for("\x01", 1, 0.05));
    }
    const int status = p.finish();
    const json doc = read_json(out + "/session.json");
    ASSERT_TRUE(doc.is_object()) << p.err;
    ASSERT_EQ(doc["runs"].size(), kept + readings) << p.err;
    kept = doc["runs"].size();
    if (way == Way::none) {
      ASSERT_EQ(status, 0) << p.err;
      EXPECT_TRUE(doc["complete"].get<bool>());
      EXPECT_EQ(kept, 4u);
      EXPECT_TRUE(exists(out + "/diff_drive_controller.yaml")) << p.err;
      EXPECT_FALSE(doc["saved"].get<bool>());
      break;
    }
    EXPECT_EQ(status, way == Way::end_of_input_enter ? 2 : 130) << p.err;
    EXPECT_NE(p.err.find("The robot is stopped"), std::string::npos) << p.err;
    EXPECT_EQ(p.err.find("did not answer"), std::string::npos) << p.err;
    EXPECT_FALSE(doc["complete"].get<bool>());
    EXPECT_TRUE(wheels_still(sim.path()));
  }
}

// A ROSArduinoBridge robot that resets in the middle of a run (a brown-out: its counts start
// again from 0, its motors stop): the counts' jump, read twice, stops the session with exit 2, the
// run under way not counted and every reading kept; --resume on the same robot ends it.
TEST(SessionBridge, AResetMidRunStopsTheSessionAndResumeEndsIt) {
  ::signal(SIGPIPE, SIG_IGN);
  const std::string robot = write("bridge_reset.json", kSmallBridgeRobot);
  // In lockstep, the reset at a set robot time (--reset-after): the robot's clock moves one PID
  // frame per `e` and stands while the person measures, so 4.5 s of robot time is about 1.6 s
  // into the second run (a 5 s arc from about 2.9 s: some 2,400 counts driven, where a frame at
  // the wheel speed limit is under 200), on any machine and under any load.
  SimOnPty sim(robot, "", "0", "ros-arduino-bridge", {"--reset-after", "4.5"});
  ASSERT_FALSE(sim.path().empty());
  const std::string out = temp("bridge_reset_out");
  static_cast<void>(shell("rm -rf " + out));
  const auto answer = [](Person& p) {
    std::size_t enters = 0, readings = 0;
    const auto deadline = PersonClock::now() + std::chrono::seconds(180);
    while (!p.closed() && PersonClock::now() < deadline) {
      if (p.count("press Enter to start") > enters) {
        p.type("");
        ++enters;
      } else if (p.count("Measured stop point") > readings) {
        p.type(odometry_reading(p));
        ++readings;
      }
      static_cast<void>(p.wait_for("\x01", 1, 0.05));
    }
    return readings;
  };
  {
    Person p({"--port", sim.path(), "--json", "--protocol", "ros-arduino-bridge",
              "--wheel-diameter-mm", "60", "--wheelbase-mm", "150", "--counts-per-rev", "1440",
              "--procedure", "fit", "--runs", "4", "--side-m", "0.4", "--out", out});
    EXPECT_EQ(answer(p), 1u);
    EXPECT_EQ(p.finish(), 2) << p.err;
    EXPECT_NE(p.err.find("it restarted"), std::string::npos) << p.err;
    EXPECT_EQ(p.err.find("had applied"), std::string::npos) << p.err;  // nothing applied yet
    EXPECT_NE(p.err.find("is not counted"), std::string::npos) << p.err;
    EXPECT_NE(p.err.find("--resume " + out), std::string::npos) << p.err;
    const json doc = read_json(out + "/session.json");
    ASSERT_TRUE(doc.is_object()) << p.err;
    EXPECT_FALSE(doc["complete"].get<bool>());
    EXPECT_EQ(doc["runs"].size(), 1u);
    EXPECT_EQ(rows_of(out + "/measurements.csv"), 1u);
    EXPECT_TRUE(wheels_still(sim.path()));
  }
  Person p({"--port", sim.path(), "--resume", out, "--json"});
  EXPECT_EQ(answer(p), 3u);
  ASSERT_EQ(p.finish(), 0) << p.err;
  const json done = json::parse(p.out, nullptr, false);
  ASSERT_TRUE(done.is_object()) << p.err;
  EXPECT_TRUE(done["complete"].get<bool>());
  EXPECT_EQ(done["runs"].size(), 4u);
  // The geometry from the four runs (odometry typed as the readings): the nominal one.
  EXPECT_NEAR(done["result"]["wheelbase_mm"].get<double>(), 150.0, 0.3);
}

}  // namespace
}  // namespace odocal_session_test
