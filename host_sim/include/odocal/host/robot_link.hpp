#pragma once
/// @file
/// The host's end of the robot console (docs/console.md), the part every way of reaching the
/// robot shares: a line channel over a file descriptor, the errors of the link, and the interrupt
/// a signal leaves for it. The channels: a serial port (serial_port.hpp) or `odocal-sim` on a pty
/// (sim_process.hpp); the line-protocol client on top: robot_client.hpp.

#include <stdexcept>
#include <string>
#include <utility>

namespace odocal::host {

/// The link failed: port missing, busy or not a tty, the robot went away, a reply did not come.
class LinkError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The line went away: the port hung up (a USB adapter unplugged, a cable pulled, the simulator
/// gone). Nothing more can be sent to the robot.
class LinkLost : public LinkError {
 public:
  using LinkError::LinkError;
};

/// A signal (SIGINT, SIGTERM) asked the program to stop; thrown once, from the first blocking
/// read or wait after it came, so that the session can stop the robot and put things back.
class Interrupted : public std::runtime_error {
 public:
  explicit Interrupted(int signal_number);
  [[nodiscard]] int signal_number() const { return signal_number_; }

 private:
  int signal_number_;
};

/// Records that `signal_number` arrived. Async-signal-safe: only an atomic store.
void note_interrupt(int signal_number) noexcept;
/// The signal recorded by note_interrupt(), 0 when none.
[[nodiscard]] int interrupt_signal() noexcept;
/// Throws Interrupted the first time it is called after a signal was recorded; later calls return
/// (the clean-up that follows must be able to talk to the robot).
void check_interrupt();

/// A byte channel that yields whole lines.
class LineChannel {
 public:
  virtual ~LineChannel() = default;
  /// Sends `line` followed by LF. Throws LinkError.
  virtual void write_line(const std::string& line) = 0;
  /// Next non-empty line (terminator removed) within `timeout_ms`; false on timeout. Throws
  /// LinkError when the other end closed.
  virtual bool read_line(std::string& line, int timeout_ms) = 0;
  /// What to call the other end in messages ("/dev/ttyUSB0", "odocal-sim on /dev/pts/3").
  [[nodiscard]] virtual std::string name() const = 0;
};

/// A line channel over one file descriptor (a tty), which it owns.
class FdChannel : public LineChannel {
 public:
  FdChannel(int fd, std::string name) : fd_(fd), name_(std::move(name)) {}
  ~FdChannel() override;
  FdChannel(const FdChannel&) = delete;
  FdChannel& operator=(const FdChannel&) = delete;
  void write_line(const std::string& line) override;
  bool read_line(std::string& line, int timeout_ms) override;
  [[nodiscard]] std::string name() const override { return name_; }
  /// The descriptor (for a signal handler's last `stop`).
  [[nodiscard]] int fd() const { return fd_; }
  /// What ends each line written (LF; ROSArduinoBridge reads a bare CR).
  void set_line_end(std::string end) { line_end_ = std::move(end); }

 private:
  int fd_;
  std::string name_;
  std::string buffer_;
  std::string line_end_ = "\n";
};

}  // namespace odocal::host
