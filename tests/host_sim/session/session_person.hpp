#pragma once
// A person at `odocal session --port`: its stdin, stdout and stderr on pipes the test types into
// and reads; the robot's console on its pty asked directly; the session's files read back.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "session_harness.hpp"

namespace odocal_session_test {

/// `odocal session ARGS` with a person at it: stdin, stdout and stderr are pipes the test reads
/// and types into as the session asks.
using PersonClock = std::chrono::steady_clock;

class Person {
 public:
  explicit Person(const std::vector<std::string>& args) {
    int in[2], out[2], err[2];
    EXPECT_EQ(::pipe(in), 0);
    EXPECT_EQ(::pipe(out), 0);
    EXPECT_EQ(::pipe(err), 0);
    pid_ = ::fork();
    if (pid_ == 0) {
      ::dup2(in[0], STDIN_FILENO);
      ::dup2(out[1], STDOUT_FILENO);
      ::dup2(err[1], STDERR_FILENO);
      for (int fd : {in[0], in[1], out[0], out[1], err[0], err[1]}) {
        ::close(fd);
      }
      std::vector<std::string> all = {bin("odocal"), "session"};
      all.insert(all.end(), args.begin(), args.end());
      std::vector<char*> argv;
      for (auto& a : all) {
        argv.push_back(a.data());
      }
      argv.push_back(nullptr);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    ::close(in[0]);
    ::close(out[1]);
    ::close(err[1]);
    in_ = in[1];
    out_ = out[0];
    err_ = err[0];
  }
  ~Person() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      static_cast<void>(finish());
    }
  }
  /// Reads until `text` has appeared `times` times on stderr (false after `timeout_s`).
  bool wait_for(const std::string& text, std::size_t times, double timeout_s = 60.0) {
    const auto deadline = PersonClock::now() + std::chrono::duration<double>(timeout_s);
    while (count(text) < times) {
      if (PersonClock::now() > deadline || read_some(200) < 0) {
        return count(text) >= times;
      }
    }
    return true;
  }
  [[nodiscard]] std::size_t count(const std::string& text) const {
    std::size_t n = 0;
    for (auto at = err.find(text); at != std::string::npos; at = err.find(text, at + 1)) {
      ++n;
    }
    return n;
  }
  void type(const std::string& line) {
    const std::string data = line + "\n";
    EXPECT_EQ(::write(in_, data.data(), data.size()), static_cast<ssize_t>(data.size()));
  }
  void signal(int number) { ::kill(pid_, number); }
  /// Ends the session's input: every prompt from now on meets the end of the input (Ctrl-D).
  void close_input() {
    if (in_ >= 0) {
      ::close(in_);
      in_ = -1;
    }
  }
  /// True once the session closed its stdout and stderr (it ended).
  [[nodiscard]] bool closed() const { return closed_; }
  /// Ends the input, reads everything, returns the exit status (-1 for a crash).
  int finish() {
    if (in_ >= 0) {
      ::close(in_);
      in_ = -1;
    }
    const auto deadline = PersonClock::now() + std::chrono::seconds(120);
    while (PersonClock::now() < deadline && read_some(1000) >= 0) {
    }
    int status = 0;
    if (PersonClock::now() >= deadline && ::waitpid(pid_, &status, WNOHANG) == 0) {
      // Still running after two minutes: a session that hangs is killed (and counts as a crash).
      ::kill(pid_, SIGKILL);
    }
    ::waitpid(pid_, &status, 0);
    pid_ = -1;
    ::close(out_);
    ::close(err_);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  std::string out;
  std::string err;

 private:
  /// 1 when something was read, 0 when nothing came within `timeout_ms`, -1 when both outputs
  /// are closed.
  int read_some(int timeout_ms) {
    pollfd fds[2] = {{out_, POLLIN, 0}, {err_, POLLIN, 0}};
    if (::poll(fds, 2, timeout_ms) <= 0) {
      return 0;
    }
    int closed = 0;
    char buffer[4096];
    for (int i = 0; i < 2; ++i) {
      if (fds[i].revents == 0) {
        continue;
      }
      const ssize_t n = ::read(fds[i].fd, buffer, sizeof buffer);
      if (n > 0) {
        (i == 0 ? out : err).append(buffer, static_cast<std::size_t>(n));
        return 1;
      }
      ++closed;
    }
    closed_ = closed_ || closed == 2;
    return closed == 2 ? -1 : 0;
  }
  pid_t pid_ = -1;
  int in_ = -1, out_ = -1, err_ = -1;
  bool closed_ = false;
};

/// One line to the robot's console on its pty and the reply that has `key=`.
inline std::string ask_robot(const std::string& pty, const std::string& line,
                             const std::string& key) {
  const int fd = ::open(pty.c_str(), O_RDWR | O_NOCTTY);
  EXPECT_GE(fd, 0) << pty;
  termios mode{};
  ::tcgetattr(fd, &mode);
  ::cfmakeraw(&mode);
  ::tcsetattr(fd, TCSANOW, &mode);
  const std::string data = line + "\n";
  EXPECT_EQ(::write(fd, data.data(), data.size()), static_cast<ssize_t>(data.size()));
  std::string got;
  const auto deadline = PersonClock::now() + std::chrono::seconds(10);
  while (got.find(key + "=") == std::string::npos ||
         got.find('\n', got.find(key + "=")) == std::string::npos) {
    pollfd wait{fd, POLLIN, 0};
    if (PersonClock::now() > deadline || ::poll(&wait, 1, 500) < 0) {
      break;
    }
    char buffer[512];
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n > 0) {
      got.append(buffer, static_cast<std::size_t>(n));
    }
  }
  ::close(fd);
  return got;
}

inline double value_of(const std::string& text, const std::string& key) {
  const auto at = text.rfind(key + "=");
  return at == std::string::npos ? NAN : std::atof(text.c_str() + at + key.size() + 1);
}

inline json read_json(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return json::parse(text.str(), nullptr, false);
}

inline std::size_t rows_of(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::size_t rows = 0;
  std::getline(in, line);
  EXPECT_EQ(line, "run,x_mm,y_mm,theta_deg");
  while (std::getline(in, line)) {
    rows += line.empty() ? 0u : 1u;
  }
  return rows;
}

/// What a careful person with a tape reads for the latest run of a robot that barely drifts over
/// short runs: the odometry's pose the session showed.
inline std::string odometry_reading(const Person& p) {
  const std::string& e = p.err;
  const auto at = e.rfind("odometry says x=");
  const double x = std::atof(e.c_str() + at + 16);
  const double y = std::atof(e.c_str() + e.find("y=", at) + 2);
  const double theta = std::atof(e.c_str() + e.find("heading ", at) + 8);
  char text[96];
  std::snprintf(text, sizeof text, "%.1f %.1f %.2f", x, y, theta);
  return text;
}

/// A plain robot, no slip: its runs repeat.
inline constexpr const char* plain_robot =
    R"({"wheel_diameter_mm": 60, "wheelbase_mm": 150, "counts_per_rev": 1440,
        "true_left_diameter_mm": 59.9, "true_right_diameter_mm": 60.1, "true_wheelbase_mm": 152,
        "slip_sigma": 0, "bump_height_mm": 0, "measure_sigma_mm": 0})";

/// What a session must leave as it found it: the factors and settings it may change, and `status`.
struct RobotState {
  std::string factors;  ///< c_l c_r wheelbase_mm wheelbase_arc_mm f_lat f_lon v_max_mps wiring_fix
  std::string status;
};

inline RobotState robot_state(const std::string& pty) {
  RobotState s;
  for (const char* name : {"c_l", "c_r", "wheelbase_mm", "wheelbase_arc_mm", "f_lat", "f_lon",
                           "v_max_mps", "wiring_fix"}) {
    char value[64];
    std::snprintf(value, sizeof value, "%s=%.6f ", name,
                  value_of(ask_robot(pty, std::string("get ") + name, name), name));
    s.factors += value;
  }
  s.status = ask_robot(pty, "status", "unsaved");
  return s;
}

/// Factors of an earlier calibration saved on the robot: what every way out must leave in force.
inline void prepare_store(const std::string& robot, const std::string& store) {
  shell(bin("odocal-sim") + " --robot " + robot + " --store " + store + " <" +
        write("exit_prepare.txt", "set c_l 1.001\nset c_r 0.999\nset wheelbase_mm 151\nsave\n"));
}

}  // namespace odocal_session_test
