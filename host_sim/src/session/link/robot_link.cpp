// The link's line channel over a file descriptor, and the interrupt a signal leaves for it.

#include "odocal/host/robot_link.hpp"

#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>

#include "link_internal.hpp"

namespace odocal::host {
namespace {

using link_detail::Clock;
using link_detail::remaining_ms;
using link_detail::system_error;

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
  const std::string data = line + line_end_;
  std::size_t done = 0;
  const Clock::time_point deadline = Clock::now() + std::chrono::seconds(5);
  while (done < data.size()) {
    const ssize_t n = ::write(fd_, data.data() + done, data.size() - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && (errno == EIO || errno == ENXIO || errno == ENODEV)) {
      throw LinkLost(system_error(name_ + ": the port hung up: write"));
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
        throw LinkLost(name_ + ": the port hung up (the robot closed the connection)");
      }
    }
    if (remaining_ms(deadline) == 0) {
      return false;
    }
  }
}

}  // namespace odocal::host
