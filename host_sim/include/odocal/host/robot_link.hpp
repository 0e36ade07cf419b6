#pragma once
/// @file
/// The host's end of the robot console (docs/console.md): a serial port (plain termios, 8N1, raw,
/// exclusive) or `odocal-sim` started on a pty, and a line-protocol client on top: send one
/// command line, collect the `#` lines apart, take exactly one `ok`/`err` reply within a timeout,
/// and wait for `# done trial=N path=P`.

#include <sys/types.h>

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace odocal::host {

/// The link failed: port missing, busy or not a tty, the robot went away, a reply did not come.
class LinkError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
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

 private:
  int fd_;
  std::string name_;
  std::string buffer_;
};

/// Opens a serial port: must exist, be a tty and not be held by another program (flock and
/// TIOCEXCL); then 8N1, raw, no flow control, at `baud`. Throws LinkError naming the port and why.
[[nodiscard]] std::unique_ptr<FdChannel> open_serial_port(const std::string& path,
                                                          std::uint32_t baud);

/// The baud rates open_serial_port takes.
[[nodiscard]] std::vector<std::uint32_t> supported_bauds();

/// `odocal-sim` started as a child on a pty; stopped (SIGTERM, then waited for) on destruction.
class SimProcess {
 public:
  /// Starts `program --pty --speed 0 --seed S [--robot FILE] [--store FILE]`, reads the pty path
  /// it prints and opens it. Throws LinkError (program missing, exited, no pty announced).
  SimProcess(const std::string& program, const std::string& robot_file, std::uint64_t seed,
             const std::string& store_file);
  ~SimProcess();
  SimProcess(const SimProcess&) = delete;
  SimProcess& operator=(const SimProcess&) = delete;
  [[nodiscard]] FdChannel& channel() { return *channel_; }
  /// Stops the child now (idempotent).
  void stop();

 private:
  pid_t pid_ = -1;
  std::unique_ptr<FdChannel> channel_;
};

/// `odocal-sim` beside the running executable (/proc/self/exe's directory).
[[nodiscard]] std::string sibling_program(const std::string& name);

/// One reply line, split: `ok k=v ...` or `err code message`.
struct Reply {
  bool ok = false;
  std::string code;     ///< err code (empty for ok)
  std::string message;  ///< err message
  std::map<std::string, std::string> pairs;
  std::string line;  ///< the whole line
  /// The value of `key` as a number; throws LinkError naming the command and key.
  [[nodiscard]] double number(const std::string& key) const;
  [[nodiscard]] const std::string& text(const std::string& key) const;
};

/// Splits "ok a=1 b=2" / "err code text" (false when the line is neither).
[[nodiscard]] bool parse_reply(const std::string& line, Reply& reply);

/// The console client. Every command waits for its one reply; `#` lines seen meanwhile go to the
/// async queue (`# done`, `# trial`) or to the tick handler (`# ticks`).
class RobotClient {
 public:
  explicit RobotClient(LineChannel& channel) : channel_(channel) {}
  /// Sends `line`, returns its reply (ok or err). Throws LinkError on timeout or a closed link.
  /// `listing`, when given, receives the `#` lines printed before the reply (`params`, `help`).
  Reply command(const std::string& line, int timeout_ms = 5000,
                std::vector<std::string>* listing = nullptr);
  /// Like command(), but an `err` reply throws LinkError("`line`: err ...").
  Reply expect_ok(const std::string& line, int timeout_ms = 5000);
  /// Waits for `# done trial=N path=P`; returns its pairs. Throws LinkError on timeout.
  std::map<std::string, std::string> wait_done(int timeout_ms);
  /// Waits at most `timeout_ms` for `# done`: its pairs, or an empty map when it has not come.
  std::map<std::string, std::string> poll_done(int timeout_ms);
  /// Receives every `# ticks ...` line (the whole line) as it arrives.
  void on_ticks(std::function<void(const std::string&)> handler) { ticks_ = std::move(handler); }
  /// Reads and routes one line within `timeout_ms`; false on timeout (for waiting on streams).
  bool pump(int timeout_ms);
  /// Discards queued async lines (e.g. a `# done` of a motion from before the session).
  void drain(int quiet_ms);

 private:
  void route(const std::string& line);
  LineChannel& channel_;
  std::deque<std::string> async_;
  std::function<void(const std::string&)> ticks_;
};

/// `key=value` pairs of a `#` line such as "# done trial=3 path=line".
[[nodiscard]] std::map<std::string, std::string> hash_line_pairs(const std::string& line);

}  // namespace odocal::host
