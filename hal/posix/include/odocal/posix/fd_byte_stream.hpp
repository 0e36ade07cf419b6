#pragma once
/// @file
/// hal::ByteStream over POSIX file descriptors: stdin/stdout, or a pseudo-terminal.

#include <cstddef>
#include <cstdint>
#include <string>

#include "odocal/hal/byte_stream.hpp"
#include "odocal/hal/monotonic_clock.hpp"

namespace odocal::posix {

/// Non-blocking stream over a read descriptor and a write descriptor (they may be the same).
///
/// Pipes, terminals and sockets are made non-blocking without touching the caller's open file
/// description: the descriptor is reopened through /proc/self/fd with O_NONBLOCK (so the shell's
/// terminal is never left non-blocking); when that is impossible the original descriptor's flags
/// are changed and restored by the destructor. Regular files are used as they are (they never
/// block). `read` returns 0 when nothing is waiting, and `end_of_input()` turns true once the
/// writer has closed. Main-loop only.
class FdByteStream final : public hal::ByteStream {
 public:
  FdByteStream(int read_fd, int write_fd);
  ~FdByteStream();
  FdByteStream(const FdByteStream&) = delete;
  FdByteStream& operator=(const FdByteStream&) = delete;

  /// True once a read saw end of file (the input was closed) or an unrecoverable error.
  [[nodiscard]] bool end_of_input() const { return end_of_input_; }
  /// True when the write side failed for good (EPIPE, EIO).
  [[nodiscard]] bool output_broken() const { return output_broken_; }
  /// The descriptor polled for input (for a target's poll()/select() sleep).
  [[nodiscard]] int input_fd() const { return read_fd_; }

 private:
  struct Side {
    int fd = -1;
    bool owned = false;      ///< we reopened it: close it
    int restore_flags = -1;  ///< flags to restore on the caller's descriptor, -1: none
  };
  static Side make_non_blocking(int fd, int access);
  static void release(Side& side);

  std::size_t do_read(std::uint8_t* out, std::size_t capacity) override;
  std::size_t do_write(const std::uint8_t* data, std::size_t size) override;

  Side read_side_;
  Side write_side_;
  int read_fd_ = -1;
  int write_fd_ = -1;
  bool end_of_input_ = false;
  bool output_broken_ = false;
};

/// A pseudo-terminal the robot console listens on: `picocom <slave_name()>` or
/// `screen <slave_name()> 115200` attach to it. The slave is put in raw mode and held open by
/// this object, so nothing echoes before a terminal program attaches and a terminal leaving does
/// not end the stream.
class PtyByteStream final : public hal::ByteStream {
 public:
  PtyByteStream() = default;
  ~PtyByteStream();
  PtyByteStream(const PtyByteStream&) = delete;
  PtyByteStream& operator=(const PtyByteStream&) = delete;

  /// Creates the pair. @return false with `error` set on failure.
  bool open(std::string& error);
  /// Path of the terminal side, e.g. "/dev/pts/3".
  [[nodiscard]] const std::string& slave_name() const { return slave_name_; }
  /// The master descriptor (for a target's poll()/select() sleep).
  [[nodiscard]] int input_fd() const { return master_; }

 private:
  std::size_t do_read(std::uint8_t* out, std::size_t capacity) override;
  std::size_t do_write(const std::uint8_t* data, std::size_t size) override;

  int master_ = -1;
  int slave_ = -1;
  std::string slave_name_;
};

/// CLOCK_MONOTONIC in microseconds, modulo 2^32.
class PosixClock final : public hal::MonotonicClock {
 private:
  std::uint32_t do_now_us() override;
};

}  // namespace odocal::posix
