// odocal-sim started as a child process on a pty, as the robot link's line channel.

#include "odocal/host/sim_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "link_internal.hpp"

namespace odocal::host {

using link_detail::Clock;
using link_detail::remaining_ms;
using link_detail::system_error;

std::string sibling_program(const std::string& name) {
  char self[4096];
  const ssize_t n = ::readlink("/proc/self/exe", self, sizeof self - 1);
  if (n <= 0) {
    return name;
  }
  std::string dir(self, static_cast<std::size_t>(n));
  const auto slash = dir.rfind('/');
  return slash == std::string::npos ? name : dir.substr(0, slash + 1) + name;
}

SimProcess::SimProcess(const std::string& program, const std::string& robot_file,
                       std::uint64_t seed, const std::string& store_file,
                       const std::string& protocol) {
  if (::access(program.c_str(), X_OK) != 0) {
    throw LinkError(program + ": cannot run odocal-sim (" + std::strerror(errno) +
                    "); it is built beside odocal (cmake --build --preset host --target "
                    "odocal-sim)");
  }
  int out[2];
  if (::pipe2(out, O_CLOEXEC) != 0) {
    throw LinkError(system_error("pipe"));
  }
  std::vector<std::string> args = {program, "--pty",  "--speed",
                                   "0",     "--seed", std::to_string(seed)};
  if (!robot_file.empty()) {
    args.insert(args.end(), {"--robot", robot_file});
  }
  if (!store_file.empty()) {
    args.insert(args.end(), {"--store", store_file});
  }
  if (!protocol.empty()) {
    args.insert(args.end(), {"--protocol", protocol});
  }
  pid_ = ::fork();
  if (pid_ < 0) {
    ::close(out[0]);
    ::close(out[1]);
    throw LinkError(system_error("fork"));
  }
  if (pid_ == 0) {
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);  // no orphaned simulator when odocal is killed
    // Its own process group: Ctrl-C at the terminal reaches odocal, which stops the robot and
    // puts its factors back before it lets the simulator go.
    static_cast<void>(::setpgid(0, 0));
    ::dup2(out[1], STDOUT_FILENO);
    const int null_fd = ::open("/dev/null", O_RDONLY);
    if (null_fd >= 0) {
      ::dup2(null_fd, STDIN_FILENO);
    }
    std::vector<char*> argv;
    for (auto& a : args) {
      argv.push_back(a.data());
    }
    argv.push_back(nullptr);
    ::execv(program.c_str(), argv.data());
    ::_exit(127);
  }
  ::close(out[1]);
  FdChannel announce(out[0], program);
  std::string line;
  std::string pty_path;
  const Clock::time_point deadline = Clock::now() + std::chrono::seconds(20);
  try {
    while (pty_path.empty() && announce.read_line(line, remaining_ms(deadline))) {
      const auto at = line.find("/dev/");
      if (at != std::string::npos) {
        pty_path = line.substr(at);
      }
    }
  } catch (const LinkError&) {
    // odocal-sim exited (bad robot file, store...): its message went to stderr.
  }
  if (pty_path.empty()) {
    stop();
    throw LinkError(program + " did not start (see its message above)");
  }
  const int fd = ::open(pty_path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    stop();
    throw LinkError(system_error(pty_path));
  }
  termios mode{};
  if (::tcgetattr(fd, &mode) == 0) {
    ::cfmakeraw(&mode);
    static_cast<void>(::tcsetattr(fd, TCSANOW, &mode));
  }
  channel_ = std::make_unique<FdChannel>(fd, "odocal-sim on " + pty_path);
}

SimProcess::~SimProcess() {
  stop();
}

void SimProcess::stop() {
  if (pid_ <= 0) {
    return;
  }
  ::kill(pid_, SIGTERM);
  int status = 0;
  for (int i = 0; i < 300; ++i) {
    if (::waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ::kill(pid_, SIGKILL);
  static_cast<void>(::waitpid(pid_, &status, 0));
  pid_ = -1;
}

}  // namespace odocal::host
