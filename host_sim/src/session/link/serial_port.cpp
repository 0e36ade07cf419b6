// A serial port as the robot link's line channel: checked, locked, 8N1 raw.

#include "odocal/host/serial_port.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "link_internal.hpp"

namespace odocal::host {
namespace {

using link_detail::system_error;

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

}  // namespace

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

}  // namespace odocal::host
