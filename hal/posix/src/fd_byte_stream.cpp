#include "odocal/posix/fd_byte_stream.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace odocal::posix {

FdByteStream::Side FdByteStream::make_non_blocking(int fd, int access) {
  Side side;
  side.fd = fd;
  struct stat info {};
  if (fd < 0 || ::fstat(fd, &info) != 0 || S_ISREG(info.st_mode)) {
    return side;  // a regular file never blocks
  }
  // A new open file description of the same pipe/tty: O_NONBLOCK on it is ours alone.
  const std::string proc = "/proc/self/fd/" + std::to_string(fd);
  const int reopened = ::open(proc.c_str(), access | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  if (reopened >= 0) {
    side.fd = reopened;
    side.owned = true;
    return side;
  }
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags >= 0 && (flags & O_NONBLOCK) == 0 && ::fcntl(fd, F_SETFL, flags | O_NONBLOCK) == 0) {
    side.restore_flags = flags;
  }
  return side;
}

void FdByteStream::release(Side& side) {
  if (side.owned) {
    ::close(side.fd);
  } else if (side.restore_flags >= 0) {
    (void)::fcntl(side.fd, F_SETFL, side.restore_flags);
  }
  side = Side{};
}

FdByteStream::FdByteStream(int read_fd, int write_fd) {
  read_side_ = make_non_blocking(read_fd, O_RDONLY);
  if (write_fd == read_fd && read_side_.owned) {
    // One descriptor for both directions (a tty or socket): reopen it read-write once.
    release(read_side_);
    read_side_ = make_non_blocking(read_fd, O_RDWR);
    write_side_ = Side{read_side_.fd, false, -1};
  } else if (write_fd == read_fd) {
    write_side_ = Side{read_side_.fd, false, -1};
  } else {
    write_side_ = make_non_blocking(write_fd, O_WRONLY);
  }
  read_fd_ = read_side_.fd;
  write_fd_ = write_side_.fd;
}

FdByteStream::~FdByteStream() {
  if (write_side_.fd != read_side_.fd) {
    release(write_side_);
  }
  release(read_side_);
}

std::size_t FdByteStream::do_read(std::uint8_t* out, std::size_t capacity) {
  if (read_fd_ < 0 || end_of_input_) {
    return 0u;
  }
  for (;;) {
    const ssize_t n = ::read(read_fd_, out, capacity);
    if (n > 0) {
      return static_cast<std::size_t>(n);
    }
    if (n == 0) {
      end_of_input_ = true;
      return 0u;
    }
    if (errno == EINTR) {
      continue;
    }
    if (errno != EAGAIN && errno != EWOULDBLOCK) {
      end_of_input_ = true;
    }
    return 0u;
  }
}

std::size_t FdByteStream::do_write(const std::uint8_t* data, std::size_t size) {
  if (write_fd_ < 0 || output_broken_) {
    return 0u;
  }
  for (;;) {
    const ssize_t n = ::write(write_fd_, data, size);
    if (n >= 0) {
      return static_cast<std::size_t>(n);
    }
    if (errno == EINTR) {
      continue;
    }
    if (errno != EAGAIN && errno != EWOULDBLOCK) {
      output_broken_ = true;
    }
    return 0u;
  }
}

PtyByteStream::~PtyByteStream() {
  if (slave_ >= 0) {
    ::close(slave_);
  }
  if (master_ >= 0) {
    ::close(master_);
  }
}

bool PtyByteStream::open(std::string& error) {
  master_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (master_ < 0 || ::grantpt(master_) != 0 || ::unlockpt(master_) != 0) {
    error = std::string("pseudo-terminal: ") + std::strerror(errno);
    return false;
  }
  char name[128] = {};
  if (::ptsname_r(master_, name, sizeof name) != 0) {
    error = std::string("ptsname: ") + std::strerror(errno);
    return false;
  }
  slave_name_ = name;
  // Hold the slave open (a terminal leaving then does not hang the master up) and make it raw:
  // no echo, no line editing, no CR/LF translation before a terminal program sets its own mode.
  slave_ = ::open(name, O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (slave_ < 0) {
    error = slave_name_ + ": " + std::strerror(errno);
    return false;
  }
  struct termios mode {};
  if (::tcgetattr(slave_, &mode) == 0) {
    ::cfmakeraw(&mode);
    (void)::cfsetspeed(&mode, B115200);
    (void)::tcsetattr(slave_, TCSANOW, &mode);
  }
  return true;
}

std::size_t PtyByteStream::do_read(std::uint8_t* out, std::size_t capacity) {
  if (master_ < 0) {
    return 0u;
  }
  for (;;) {
    const ssize_t n = ::read(master_, out, capacity);
    if (n > 0) {
      return static_cast<std::size_t>(n);
    }
    if (n < 0 && errno == EINTR) {
      continue;
    }
    return 0u;  // EAGAIN: nothing typed; EIO: no terminal attached
  }
}

std::size_t PtyByteStream::do_write(const std::uint8_t* data, std::size_t size) {
  if (master_ < 0) {
    return 0u;
  }
  for (;;) {
    const ssize_t n = ::write(master_, data, size);
    if (n >= 0) {
      return static_cast<std::size_t>(n);
    }
    if (errno == EINTR) {
      continue;
    }
    return 0u;
  }
}

std::uint32_t PosixClock::do_now_us() {
  struct timespec now {};
  ::clock_gettime(CLOCK_MONOTONIC, &now);
  const std::uint64_t us = static_cast<std::uint64_t>(now.tv_sec) * 1000000u +
                           static_cast<std::uint64_t>(now.tv_nsec) / 1000u;
  return static_cast<std::uint32_t>(us);
}

}  // namespace odocal::posix
