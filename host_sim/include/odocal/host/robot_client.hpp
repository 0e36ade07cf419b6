#pragma once
/// @file
/// The line-protocol client of the robot console (docs/console.md) on a robot link's channel:
/// send one command line, collect the `#` lines apart, take exactly one `ok`/`err` reply within a
/// timeout, and wait for `# done trial=N path=P`.

#include <deque>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "odocal/host/robot_link.hpp"

namespace odocal::host {

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
/// The robot restarted in the middle of the session (a brown-out, a watchdog): its console printed
/// its start-up line, or its tick count went back. What the MCU held in RAM is gone.
class RobotRestarted : public LinkError {
 public:
  using LinkError::LinkError;
};

class RobotClient {
 public:
  explicit RobotClient(LineChannel& channel) : channel_(channel) {}
  /// Sends `line`, returns its reply (ok or err). Throws LinkError on timeout or a closed link.
  /// `listing`, when given, receives the `#` lines printed before the reply (`params`, `help`).
  Reply command(const std::string& line, int timeout_ms = 5000,
                std::vector<std::string>* listing = nullptr);
  /// Like command(), but an `err` reply throws LinkError("`line`: err ...").
  Reply expect_ok(const std::string& line, int timeout_ms = 5000);
  /// A question whose answer does not change when asked again (`get`, `trial N`, `measure` of
  /// odocal-sim): asked until two answers agree, twelve times at most, so that a reply damaged
  /// on the line (a flipped digit still reads as a number) never becomes a value. Throws
  /// LinkError when no two agree.
  /// `get NAME` is answered from the client's snapshot of the robot's parameters when it holds
  /// NAME: only this client talks to the robot, so a value stays what it was read or set to
  /// until a line that may change it (see `remember`).
  Reply query(const std::string& line, int timeout_ms = 5000);
  /// Notes `value` as what the robot holds for parameter `name` (a `set` whose reply was checked
  /// against what was sent). The snapshot forgets a parameter when a `set` of it is sent, and
  /// everything when any line that may change parameters is (`load`, `defaults`, an `apply`, a
  /// `selftest`, a command it does not know) or the robot restarted.
  void remember(const std::string& name, double value);
  /// Forgets every parameter the snapshot holds (the next `get` of each asks the robot).
  void forget_parameters() { snapshot_.clear(); }
  /// `status`, asked again (five times at most) until its reply reads whole: ok, with `mode` one of
  /// the console's modes, `unsaved` 0 or 1 and `ticks` a whole number (when it has them). A
  /// flipped digit in `ticks` still reads: the caller asks again before it believes a tick count
  /// that went back. Throws LinkError.
  Reply status();
  /// Lines that were neither a reply nor a `#` line (damaged on the line) since the session began
  /// watching (watch_restarts).
  [[nodiscard]] std::size_t garbled_lines() const { return garbled_; }
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
  /// From now on the robot's start-up line (`# odocal ... console ...`) throws RobotRestarted
  /// from whatever read meets it (once: the clean-up that follows must talk to the robot).
  void watch_restarts(bool on) {
    watch_restarts_ = on;
    in_session_ = in_session_ || on;
  }
  /// After every command's reply, also sends `query` and drops its reply: a question that
  /// changes nothing, so that a test can show that what the session measures does not depend on
  /// how much it talks (empty: none, the default).
  void chatter(std::string query) { chatter_ = std::move(query); }
  /// Command lines sent (each line again after a damaged reply counts), and of them `get` lines.
  [[nodiscard]] std::size_t lines_sent() const { return lines_sent_; }
  [[nodiscard]] std::size_t gets_sent() const { return gets_sent_; }

 private:
  void route(const std::string& line);
  /// After a reply that did not come, while watching for restarts: `status` once, so that a
  /// robot that restarted meanwhile prints its start-up line (it waits for a command) and
  /// RobotRestarted is thrown; returns when nothing says so.
  void probe_restart();
  void send(const std::string& line);
  void say_chatter();
  /// What sending `line` does to the snapshot (forgets what it may change).
  void before_sending(const std::string& line);
  LineChannel& channel_;
  std::deque<std::string> async_;
  std::function<void(const std::string&)> ticks_;
  bool watch_restarts_ = false;
  bool in_session_ = false;
  std::size_t garbled_ = 0;
  std::map<std::string, Reply> snapshot_;  ///< `get NAME` line -> its agreed reply
  std::string chatter_;
  bool in_chatter_ = false;
  std::size_t lines_sent_ = 0;
  std::size_t gets_sent_ = 0;
};

/// `key=value` pairs of a `#` line such as "# done trial=3 path=line".
[[nodiscard]] std::map<std::string, std::string> hash_line_pairs(const std::string& line);

}  // namespace odocal::host
