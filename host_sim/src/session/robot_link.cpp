#include "odocal/host/robot_link.hpp"
#include "odocal/toolkit/numbers.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>

namespace odocal::host {
namespace {

using Clock = std::chrono::steady_clock;

int remaining_ms(Clock::time_point deadline) {
  const auto left =
      std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return left > 0 ? static_cast<int>(left) : 0;
}

speed_t baud_constant(std::uint32_t baud) {
  switch (baud) {
    case 9600:
      return B9600;
    case 19200:
      return B19200;
    case 38400:
      return B38400;
    case 57600:
      return B57600;
    case 115200:
      return B115200;
    case 230400:
      return B230400;
    case 460800:
      return B460800;
    case 921600:
      return B921600;
    default:
      return B0;
  }
}

std::string system_error(const std::string& what) {
  return what + ": " + std::strerror(errno);
}

std::atomic<int> pending_signal{0};
std::atomic<bool> interrupt_thrown{false};

}  // namespace

Interrupted::Interrupted(int signal_number)
    : std::runtime_error(std::string("interrupted by ") +
                         (signal_number == SIGINT    ? "SIGINT (Ctrl-C)"
                          : signal_number == SIGTERM ? "SIGTERM"
                                                     : "a signal")),
      signal_number_(signal_number) {}

void note_interrupt(int signal_number) noexcept {
  pending_signal.store(signal_number);
}

int interrupt_signal() noexcept {
  return pending_signal.load();
}

void check_interrupt() {
  const int signal_number = pending_signal.load();
  if (signal_number != 0 && !interrupt_thrown.exchange(true)) {
    throw Interrupted(signal_number);
  }
}

FdChannel::~FdChannel() {
  if (fd_ >= 0) {
    ::close(fd_);
  }
}

void FdChannel::write_line(const std::string& line) {
  const std::string data = line + "\n";
  std::size_t done = 0;
  const Clock::time_point deadline = Clock::now() + std::chrono::seconds(5);
  while (done < data.size()) {
    const ssize_t n = ::write(fd_, data.data() + done, data.size() - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
      throw LinkError(system_error(name_ + ": write"));
    }
    check_interrupt();
    if (remaining_ms(deadline) == 0) {
      throw LinkError(name_ + ": write timed out (the robot does not read its console)");
    }
    pollfd wait{fd_, POLLOUT, 0};
    static_cast<void>(::poll(&wait, 1, 50));
  }
}

bool FdChannel::read_line(std::string& line, int timeout_ms) {
  const Clock::time_point deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    for (;;) {
      const std::size_t end = buffer_.find_first_of("\r\n");
      if (end == std::string::npos) {
        break;
      }
      line = buffer_.substr(0, end);
      buffer_.erase(0, end + 1);
      if (!line.empty()) {
        return true;
      }
    }
    pollfd wait{fd_, POLLIN, 0};
    const int ready = ::poll(&wait, 1, remaining_ms(deadline));
    if (ready < 0 && errno != EINTR) {
      throw LinkError(system_error(name_ + ": poll"));
    }
    check_interrupt();
    if (ready > 0) {
      char chunk[1024];
      const ssize_t n = ::read(fd_, chunk, sizeof chunk);
      if (n > 0) {
        buffer_.append(chunk, static_cast<std::size_t>(n));
        continue;
      }
      if (n == 0 || (n < 0 && errno == EIO) || (wait.revents & POLLHUP) != 0) {
        throw LinkError(name_ + ": the robot closed the connection");
      }
    }
    if (remaining_ms(deadline) == 0) {
      return false;
    }
  }
}

std::vector<std::uint32_t> supported_bauds() {
  return {9600, 19200, 38400, 57600, 115200, 230400, 460800, 921600};
}

std::unique_ptr<FdChannel> open_serial_port(const std::string& path, std::uint32_t baud) {
  const speed_t speed = baud_constant(baud);
  if (speed == B0) {
    throw LinkError("--baud " + std::to_string(baud) +
                    ": not a supported rate (9600, 19200, 38400, 57600, 115200, 230400, 460800, "
                    "921600)");
  }
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    throw LinkError("port " + path + ": " +
                    (errno == ENOENT ? std::string("does not exist (is the robot plugged in? "
                                                   "ls /dev/ttyUSB* /dev/ttyACM*)")
                                     : std::string(std::strerror(errno))));
  }
  if (!S_ISCHR(info.st_mode)) {
    throw LinkError("port " + path + ": not a serial port (not a character device)");
  }
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    if (errno == EBUSY) {
      throw LinkError("port " + path + ": busy (another program holds it exclusively)");
    }
    if (errno == EACCES) {
      throw LinkError("port " + path +
                      ": permission denied (add yourself to the 'dialout' group, log in again)");
    }
    throw LinkError(system_error("port " + path));
  }
  auto channel = std::make_unique<FdChannel>(fd, path);
  if (::isatty(fd) != 1) {
    throw LinkError("port " + path + ": not a tty");
  }
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    throw LinkError("port " + path +
                    ": busy (another program, e.g. picocom or a second odocal, has it open)");
  }
  static_cast<void>(::ioctl(fd, TIOCEXCL));
  termios mode{};
  if (::tcgetattr(fd, &mode) != 0) {
    throw LinkError(system_error("port " + path + ": tcgetattr"));
  }
  ::cfmakeraw(&mode);
  mode.c_cflag &= ~static_cast<tcflag_t>(CSTOPB | PARENB | CRTSCTS | CSIZE);
  mode.c_cflag |= CS8 | CLOCAL | CREAD;
  mode.c_iflag &= ~static_cast<tcflag_t>(IXON | IXOFF | IXANY);
  mode.c_cc[VMIN] = 0;
  mode.c_cc[VTIME] = 0;
  ::cfsetispeed(&mode, speed);
  ::cfsetospeed(&mode, speed);
  if (::tcsetattr(fd, TCSANOW, &mode) != 0) {
    throw LinkError(system_error("port " + path + ": tcsetattr"));
  }
  static_cast<void>(::tcflush(fd, TCIOFLUSH));
  return channel;
}

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
                       std::uint64_t seed, const std::string& store_file) {
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

bool parse_reply(const std::string& line, Reply& reply) {
  reply = Reply{};
  reply.line = line;
  std::vector<std::string> words;
  std::size_t at = 0;
  while (at < line.size()) {
    const std::size_t start = line.find_first_not_of(" \t", at);
    if (start == std::string::npos) {
      break;
    }
    const std::size_t end = line.find_first_of(" \t", start);
    words.push_back(line.substr(start, end == std::string::npos ? end : end - start));
    at = end == std::string::npos ? line.size() : end;
  }
  if (words.empty()) {
    return false;
  }
  if (words[0] == "ok") {
    reply.ok = true;
    for (std::size_t i = 1; i < words.size(); ++i) {
      const auto eq = words[i].find('=');
      if (eq != std::string::npos) {
        reply.pairs[words[i].substr(0, eq)] = words[i].substr(eq + 1);
      }
    }
    return true;
  }
  if (words[0] == "err" && words.size() >= 2) {
    reply.code = words[1];
    const auto pos = line.find(words[1]) + words[1].size();
    const auto text = line.find_first_not_of(" \t", pos);
    reply.message = text == std::string::npos ? "" : line.substr(text);
    return true;
  }
  return false;
}

const std::string& Reply::text(const std::string& key) const {
  const auto it = pairs.find(key);
  if (it == pairs.end()) {
    throw LinkError("robot reply '" + line + "' has no " + key + "=");
  }
  return it->second;
}

double Reply::number(const std::string& key) const {
  const std::string& value = text(key);
  const auto parsed = toolkit::parse_real(value);
  if (!parsed) {
    throw LinkError("robot reply '" + line + "': " + key + "=" + value + " is not a number");
  }
  return *parsed;
}

std::map<std::string, std::string> hash_line_pairs(const std::string& line) {
  Reply reply;
  std::string rest = line.substr(line.rfind('#') == 0 ? 1 : 0);
  static_cast<void>(parse_reply("ok " + rest, reply));
  return reply.pairs;
}

void RobotClient::route(const std::string& line) {
  if (line.rfind("# ticks", 0) == 0) {
    if (ticks_) {
      ticks_(line);
    }
    return;
  }
  if (line.rfind("# done", 0) == 0) {
    async_.push_back(line);
  }
}

Reply RobotClient::command(const std::string& line, int timeout_ms,
                           std::vector<std::string>* listing) {
  channel_.write_line(line);
  const Clock::time_point deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  std::string received;
  for (;;) {
    if (!channel_.read_line(received, remaining_ms(deadline))) {
      throw LinkError(channel_.name() + ": no reply to '" + line + "' within " +
                      std::to_string(timeout_ms) + " ms (is it an odocal console at this baud?)");
    }
    if (received[0] == '#') {
      route(received);
      if (listing != nullptr) {
        listing->push_back(received);
      }
      continue;
    }
    Reply reply;
    if (parse_reply(received, reply)) {
      return reply;
    }
    // Anything else (an echo of typed text, line noise at start-up) is not a reply.
  }
}

Reply RobotClient::expect_ok(const std::string& line, int timeout_ms) {
  Reply reply = command(line, timeout_ms);
  if (!reply.ok) {
    throw LinkError("robot refused '" + line + "': err " + reply.code + " " + reply.message);
  }
  return reply;
}

std::map<std::string, std::string> RobotClient::poll_done(int timeout_ms) {
  const Clock::time_point deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  for (;;) {
    if (!async_.empty()) {
      const std::string line = async_.front();
      async_.pop_front();
      auto pairs = hash_line_pairs(line);
      pairs.emplace("done", "1");  // never empty, even for a bare `# done`
      return pairs;
    }
    std::string received;
    if (!channel_.read_line(received, remaining_ms(deadline))) {
      return {};
    }
    if (received[0] == '#') {
      route(received);
    }
  }
}

std::map<std::string, std::string> RobotClient::wait_done(int timeout_ms) {
  auto pairs = poll_done(timeout_ms);
  if (pairs.empty()) {
    throw LinkError(channel_.name() + ": the run did not end (no '# done') within " +
                    std::to_string(timeout_ms / 1000) + " s");
  }
  return pairs;
}

bool RobotClient::pump(int timeout_ms) {
  std::string received;
  if (!channel_.read_line(received, timeout_ms)) {
    return false;
  }
  if (received[0] == '#') {
    route(received);
  }
  return true;
}

void RobotClient::drain(int quiet_ms) {
  std::string received;
  while (channel_.read_line(received, quiet_ms)) {
    if (received[0] == '#') {
      route(received);
    }
  }
  async_.clear();
}

}  // namespace odocal::host
