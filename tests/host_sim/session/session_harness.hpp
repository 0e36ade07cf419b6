#pragma once
// What the session tests share: the programs under test, temporary files, running a command
// with its output, and odocal-sim on a pty as a robot on a serial port would be.
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace odocal_session_test {

using nlohmann::json;

inline std::string bin(const std::string& name) {
  return std::string(ODOCAL_SESSION_BIN_DIR) + "/" + name;
}

/// The running test's own directory under TempDir() (created when first asked): each test is a
/// ctest entry of its own and runs beside others, and the tests' file names are fixed.
inline std::string test_dir() {
  std::string dir = ::testing::TempDir();
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  if (info == nullptr) {
    return dir;
  }
  std::string name = std::string(info->test_suite_name()) + "." + info->name();
  std::replace(name.begin(), name.end(), '/', '_');  // parameterised tests' names
  dir += name + "/";
  ::mkdir(dir.c_str(), 0755);
  return dir;
}

inline std::string temp(const std::string& name) {
  return test_dir() + "odocal_session_" + name;
}

inline std::string write(const std::string& name, const std::string& content) {
  const std::string path = temp(name);
  std::ofstream(path, std::ios::binary) << content;
  return path;
}

inline bool exists(const std::string& path) {
  struct stat info {};
  return ::stat(path.c_str(), &info) == 0;
}

struct Result {
  int status = -1;
  std::string out;
  std::string err;
};

inline Result shell(const std::string& command) {
  const std::string err_file = temp("stderr.txt");
  Result r;
  FILE* pipe = popen((command + " 2>" + err_file).c_str(), "r");
  if (pipe == nullptr) {
    return r;
  }
  char buffer[4096];
  std::size_t n = 0;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) {
    r.out.append(buffer, n);
  }
  const int raw = pclose(pipe);
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::ifstream err(err_file);
  std::stringstream text;
  text << err.rdbuf();
  r.err = text.str();
  return r;
}

/// `odocal session ARGS`, stdin from `input` (a file; /dev/null by default: no terminal).
inline Result session(const std::string& args, const std::string& input = "/dev/null") {
  return shell(bin("odocal") + " session " + args + " <" + input);
}

inline json parse(const Result& r) {
  EXPECT_EQ(r.status, 0) << r.err;
  json doc = json::parse(r.out, nullptr, false);
  EXPECT_TRUE(doc.is_object()) << r.out << r.err;
  return doc;
}

/// What a restarted odocal-sim with `store` holds: `get NAME` through scripted stdin.
inline double stored(const std::string& robot, const std::string& store, const std::string& name) {
  const std::string script = write("get.txt", "get " + name + "\n");
  const Result r =
      shell(bin("odocal-sim") + " --robot " + robot + " --store " + store + " <" + script);
  const auto at = r.out.find(name + "=");
  EXPECT_NE(at, std::string::npos) << r.out << r.err;
  return at == std::string::npos ? NAN : std::atof(r.out.c_str() + at + name.size() + 1);
}

/// odocal-sim on a pty, as a robot on a serial port would be: in lockstep with its host (speed
/// 0), or in real time (speed 1: a run takes the seconds it takes on the floor).
class SimOnPty {
 public:
  /// odocal-sim on a pty; `protocol` (e.g. "ros-arduino-bridge") runs that firmware instead, and
  /// an empty `store` runs without one.
  SimOnPty(const std::string& robot, const std::string& store, const std::string& speed = "0",
           const std::string& protocol = "", const std::vector<std::string>& extra = {}) {
    int out[2];
    EXPECT_EQ(::pipe(out), 0);
    std::vector<std::string> args = {bin("odocal-sim"), "--pty", "--speed", speed,
                                     "--robot",         robot};
    if (!store.empty()) {
      args.insert(args.end(), {"--store", store});
    }
    if (!protocol.empty()) {
      args.insert(args.end(), {"--protocol", protocol});
    }
    args.insert(args.end(), extra.begin(), extra.end());
    pid_ = ::fork();
    if (pid_ == 0) {
      ::dup2(out[1], STDOUT_FILENO);
      ::close(out[0]);
      std::vector<char*> argv;
      for (std::string& a : args) {
        argv.push_back(a.data());
      }
      argv.push_back(nullptr);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    ::close(out[1]);
    std::string line;
    char c = 0;
    while (::read(out[0], &c, 1) == 1 && c != '\n') {
      line += c;
    }
    ::close(out[0]);
    const auto at = line.find("/dev/");
    path_ = at == std::string::npos ? "" : line.substr(at);
  }
  ~SimOnPty() {
    ::kill(pid_, SIGTERM);
    int status = 0;
    ::waitpid(pid_, &status, 0);
  }
  const std::string& path() const { return path_; }
  /// Sends `number` to the simulator (SIGUSR1: its MCU resets, docs/simulation.md).
  void signal(int number) const { ::kill(pid_, number); }

 private:
  pid_t pid_ = -1;
  std::string path_;
};

}  // namespace odocal_session_test
