// ROSArduinoBridge's commands through odocal-sim, on a pty as diffdrive_arduino opens a serial
// port, with the exact bytes its ArduinoComms writes (joshnewans/diffdrive_arduino,
// hardware/include/diffdrive_arduino/arduino_comms.hpp): each command ended by a bare CR, one
// line read back up to its LF; and on scripted stdin (DESIGN.md "ROS robots", docs/ros.md).

#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "sim_process.hpp"

namespace {

using odocal::test::sim_program;
using odocal::test::temp_file;

#define REQUIRE_SIM()                                                         \
  if (sim_program().empty()) {                                                \
    FAIL() << "odocal-sim not built (cmake --build --preset host builds it)"; \
  }

/// odocal-sim on a pty in lockstep (speed 0), the test on its other side in raw mode.
class SimPort {
 public:
  /// `protocol`: odocal-sim's --protocol (the odocal robot, or a robot running ROSArduinoBridge).
  explicit SimPort(const char* protocol = "odocal") {
    int out[2];
    EXPECT_EQ(::pipe(out), 0);
    const std::string store = ::testing::TempDir() + "odocal_sim_bridge_store.bin";
    std::remove(store.c_str());
    pid_ = ::fork();
    if (pid_ == 0) {
      ::dup2(out[1], STDOUT_FILENO);
      ::close(out[0]);
      if (std::string(protocol) == "odocal") {
        ::execl(sim_program().c_str(), "odocal-sim", "--pty", "--speed", "0", "--store",
                store.c_str(), static_cast<char*>(nullptr));
      } else {
        ::execl(sim_program().c_str(), "odocal-sim", "--pty", "--speed", "0", "--protocol",
                protocol, static_cast<char*>(nullptr));
      }
      ::_exit(127);
    }
    ::close(out[1]);
    std::string line;
    char c = 0;
    while (::read(out[0], &c, 1) == 1 && c != '\n') {
      line += c;
    }
    ::close(out[0]);
    fd_ = ::open(line.c_str(), O_RDWR | O_NOCTTY);
    EXPECT_GE(fd_, 0) << "pty: " << line;
    termios mode{};
    if (fd_ >= 0 && ::tcgetattr(fd_, &mode) == 0) {
      ::cfmakeraw(&mode);
      ::tcsetattr(fd_, TCSANOW, &mode);
    }
  }
  ~SimPort() {
    if (fd_ >= 0) {
      ::close(fd_);
    }
    ::kill(pid_, SIGTERM);
    int status = 0;
    ::waitpid(pid_, &status, 0);
  }

  /// Writes `bytes` in one write, as ArduinoComms::send_msg does, and reads one line up to and
  /// including its LF ("" after 10 s without one).
  std::string send_msg(const std::string& bytes) {
    EXPECT_EQ(::write(fd_, bytes.data(), bytes.size()), static_cast<ssize_t>(bytes.size()));
    return read_line();
  }
  std::string read_line() {
    std::string line;
    while (line.empty() || line.back() != '\n') {
      pollfd wait{fd_, POLLIN, 0};
      char c = 0;
      if (::poll(&wait, 1, 10000) <= 0 || ::read(fd_, &c, 1) != 1) {
        return line;
      }
      line += c;
    }
    return line;
  }
  /// True when nothing more arrives within `ms`.
  bool quiet_for(int ms) {
    pollfd wait{fd_, POLLIN, 0};
    return ::poll(&wait, 1, ms) == 0;
  }

 private:
  pid_t pid_ = -1;
  int fd_ = -1;
};

/// The two counts of an `e` reply.
bool counts(const std::string& reply, long& left, long& right) {
  std::istringstream in(reply);
  std::string rest;
  return static_cast<bool>(in >> left >> right) && !(in >> rest);
}

TEST(OdocalSimBridge, DiffdriveArduinosBytesOnAPtyGetTheFirmwaresAnswersUnechoed) {
  REQUIRE_SIM();
  SimPort port;
  // send_empty_msg: "\r". Its answer comes first: no banner, no note, nothing before it.
  EXPECT_EQ(port.send_msg("\r"), "Invalid Command\r\n");
  // on_activate: set_pid_values; then read() and write() at the controller's rate.
  EXPECT_EQ(port.send_msg("u 30:20:0:100\r"), "OK\r\n");
  EXPECT_EQ(port.send_msg("e\r"), "0 0\r\n");
  EXPECT_EQ(port.send_msg("m 20 20\r"), "OK\r\n");
  long left = 0;
  long right = 0;
  // Lockstep: each line gets 50 ms of robot time, so the wheels have turned by the next `e`.
  std::string reply = port.send_msg("e\r");
  ASSERT_TRUE(counts(reply, left, right)) << reply;
  EXPECT_GT(left, 0);
  EXPECT_GT(right, 0);
  EXPECT_EQ(port.send_msg("m -20 20\r"), "OK\r\n");
  EXPECT_EQ(port.send_msg("m 0 0\r"), "OK\r\n");
  EXPECT_EQ(port.send_msg("b\r"), "115200\r\n");
  EXPECT_EQ(port.send_msg("r\r"), "OK\r\n");
  EXPECT_EQ(port.send_msg("x 3 100\r"), "OK\r\n");
  EXPECT_EQ(port.send_msg("a 3\r"), "0\r\n");
  EXPECT_EQ(port.send_msg("z\r"), "Invalid Command\r\n");
  // Nothing else came: no echo of any line, no second reply.
  EXPECT_TRUE(port.quiet_for(300));
  // The robot's own console is still there, unechoed for a program's line (odocal's host ends
  // its lines with LF); after a ROSArduinoBridge line its banner never comes.
  reply = port.send_msg("status\n");
  EXPECT_EQ(reply.rfind("ok mode=idle ", 0), 0u) << reply;
}

TEST(OdocalSimBridge, OnAPtyAnOdocalLineFirstGetsTheBannerBeforeItsReply) {
  REQUIRE_SIM();
  SimPort port;
  const std::string banner = port.send_msg("version\n");
  EXPECT_EQ(banner.rfind("# odocal ", 0), 0u) << banner;
  EXPECT_NE(banner.find(" console "), std::string::npos) << banner;
  const std::string reply = port.read_line();
  EXPECT_EQ(reply.rfind("ok name=odocal ", 0), 0u) << reply;
  EXPECT_TRUE(port.quiet_for(300));
}

/// diffdrive_arduino's main-branch client for a thousand cycles (hardware/src/arduino_comms.cpp:
/// no flush, exactly one line read per command): "\r", the PID gains, then `e` and `m` each
/// cycle. Every `e` must be two whole numbers that move on as the wheels turn, every `m` `OK`.
/// @return the left and right counts of each `e`.
std::vector<std::pair<long, long>> no_flush_client(SimPort& port, const char* first_reply) {
  std::vector<std::pair<long, long>> seen;
  EXPECT_EQ(port.send_msg("\r"), first_reply);
  EXPECT_EQ(port.send_msg("u 30:20:0:100\r"), "OK\r\n");
  for (int cycle = 0; cycle < 1000; ++cycle) {
    const std::string reply = port.send_msg("e\r");
    long left = 0;
    long right = 0;
    if (!counts(reply, left, right) || reply.size() < 2u ||
        reply.compare(reply.size() - 2u, 2u, "\r\n") != 0) {
      ADD_FAILURE() << "cycle " << cycle << ": `e` answered '" << reply << "'";
      return seen;
    }
    seen.emplace_back(left, right);
    const std::string ok = port.send_msg("m 20 20\r");
    if (ok != "OK\r\n") {
      ADD_FAILURE() << "cycle " << cycle << ": `m` answered '" << ok << "'";
      return seen;
    }
  }
  EXPECT_TRUE(port.quiet_for(300)) << "a line nobody asked for";
  return seen;
}

/// The counts never go back, and they move on: over the last 900 cycles each wheel advances by
/// at least `least_per_cycle` counts a cycle on average.
void expect_counts_follow_the_wheels(const std::vector<std::pair<long, long>>& seen,
                                     double least_per_cycle) {
  ASSERT_EQ(seen.size(), 1000u);
  for (std::size_t i = 1; i < seen.size(); ++i) {
    ASSERT_GE(seen[i].first, seen[i - 1].first) << "cycle " << i;
    ASSERT_GE(seen[i].second, seen[i - 1].second) << "cycle " << i;
  }
  EXPECT_GE(static_cast<double>(seen[999].first - seen[99].first), 900.0 * least_per_cycle);
  EXPECT_GE(static_cast<double>(seen[999].second - seen[99].second), 900.0 * least_per_cycle);
}

TEST(OdocalSimBridge, AClientThatNeverFlushesGetsItsOwnReplyForAThousandCyclesOnAPty) {
  REQUIRE_SIM();
  // The odocal robot in lockstep: each line gets at least 50 ms of robot time (more while the
  // wheels turn and the host is slow to send the next line), so a cycle at least 100 ms; the
  // loop holds each wheel at 20 counts per 1/30 s (600 counts/s, the factors at 1): at least
  // 60 counts a cycle once up to speed. Half of that leaves room for the ramp and the ripple.
  SimPort port;
  expect_counts_follow_the_wheels(no_flush_client(port, "Invalid Command\r\n"), 30.0);
}

TEST(OdocalSimBridge, AClientThatNeverFlushesGetsItsOwnReplyFromTheBridgeRobotOnAPty) {
  REQUIRE_SIM();
  // odocal-sim's ROSArduinoBridge robot in lockstep: exactly one 1/30 s PID frame per `e`. Its
  // integer PID leaves up to Ko/Kp = 2.5 counts per frame uncorrected (session_bridge_test):
  // at least 17.5 counts a cycle.
  SimPort port("ros-arduino-bridge");
  expect_counts_follow_the_wheels(no_flush_client(port, "Invalid Command\r\n"), 17.5);
}

/// Runs odocal-sim on scripted stdin; every output line.
std::vector<std::string> run_script(const std::string& script) {
  const std::string in = temp_file("odocal_sim_bridge_in.txt", script);
  const std::string out = ::testing::TempDir() + "odocal_sim_bridge_out.txt";
  const int status =
      std::system((sim_program() + " --speed 0 <" + in + " >" + out + " 2>/dev/null").c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  std::ifstream o(out);
  std::vector<std::string> lines;
  for (std::string l; std::getline(o, l);) {
    if (l.empty() || l[0] != '#') {
      lines.push_back(l);
    }
  }
  return lines;
}

TEST(OdocalSimBridge, AnMDrivesTheSimulatedRobotAndStopsItAfterTwoSeconds) {
  REQUIRE_SIM();
  // Scripted: the next line waits until the motion is over, so the `e` after `m` comes once the
  // 2 s auto-stop has stopped the wheels. 30 counts per 1/30 s is 900 counts/s: about 2 s of it
  // (less the acceleration ramp, plus the braking) on each wheel.
  const auto lines = run_script("e\rm 30 30\re\re\rr\re\rodom\r");
  ASSERT_EQ(lines.size(), 7u);
  EXPECT_EQ(lines[0], "0 0");
  EXPECT_EQ(lines[1], "OK");
  long left = 0;
  long right = 0;
  ASSERT_TRUE(counts(lines[2], left, right)) << lines[2];
  EXPECT_GT(left, 1500);
  EXPECT_LT(left, 2100);
  EXPECT_GT(right, 1500);
  EXPECT_LT(right, 2100);
  // Stopped: the counts stay, but for a count of the wheels settling after the brake.
  long later_left = 0;
  long later_right = 0;
  ASSERT_TRUE(counts(lines[3], later_left, later_right)) << lines[3];
  EXPECT_NEAR(later_left, left, 2);
  EXPECT_NEAR(later_right, right, 2);
  EXPECT_EQ(lines[4], "OK");
  ASSERT_TRUE(counts(lines[5], left, right)) << lines[5];
  EXPECT_NEAR(left, 0, 2);
  EXPECT_NEAR(right, 0, 2);
  EXPECT_EQ(lines[6].rfind("ok x_mm=", 0), 0u) << lines[6];
}

}  // namespace
