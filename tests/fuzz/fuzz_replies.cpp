// libFuzzer target: arbitrary bytes as what the robot's console sends back (docs/console.md).
// Each line (split at CR or LF, empty lines dropped, as a serial line yields them) goes through
// parse_reply, Reply::text/number and hash_line_pairs: parse_reply keeps the whole line, an `ok`
// has no code, an `err` a code without blanks; text() of a key the reply has returns its value,
// of any other throws LinkError; number() is a finite double or LinkError. Then the same lines
// answer a session's commands through a RobotClient (restart watch on, `# ticks` lines logged as
// a run logs them): every reply returned is an `ok` or an `err` line, the only exceptions are
// LinkError's, and the `trial` reply's values go where a session puts them, session.json.
// The `trial` reply is read as a session reads it (read_trial), and session.json is written as a
// session writes it (any byte the robot sent, UTF-8 or not).

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "odocal/host/robot_client.hpp"
#include "odocal/host/session.hpp"
#include "odocal/toolkit/numbers.hpp"
#include "session_internal.hpp"

namespace {

using odocal::host::LinkError;
using odocal::host::Reply;

// The robot's side of the line: the input's lines, one per read; none left is a timeout.
class ScriptedChannel final : public odocal::host::LineChannel {
 public:
  explicit ScriptedChannel(const std::vector<std::string>& lines)
      : lines_(lines.begin(), lines.end()) {}
  void write_line(const std::string&) override {}
  bool read_line(std::string& line, int) override {
    if (lines_.empty())
      return false;
    line = lines_.front();
    lines_.pop_front();
    return true;
  }
  [[nodiscard]] std::string name() const override { return "robot"; }
  [[nodiscard]] bool drained() const { return lines_.empty(); }

 private:
  std::deque<std::string> lines_;
};

std::vector<std::string> lines_of(const std::string& input) {
  std::vector<std::string> lines;
  std::size_t start = 0u;
  while (start < input.size()) {
    std::size_t end = input.find_first_of("\r\n", start);
    if (end == std::string::npos)
      end = input.size();
    if (end > start)
      lines.push_back(input.substr(start, end - start));
    start = end + 1u;
  }
  return lines;
}

void check_reply(const std::string& line) {
  Reply reply;
  const bool parsed = odocal::host::parse_reply(line, reply);
  if (reply.line != line || (parsed && reply.ok && (!reply.code.empty() || !reply.message.empty())))
    __builtin_trap();
  if (parsed && !reply.ok &&
      (reply.code.empty() || reply.code.find_first_of(" \t") != std::string::npos))
    __builtin_trap();
  if (!parsed && (reply.ok || !reply.pairs.empty()))
    __builtin_trap();
  for (const auto& [key, value] : reply.pairs) {
    if (&reply.text(key) != &value)
      __builtin_trap();
    try {
      if (!std::isfinite(reply.number(key)))
        __builtin_trap();
    } catch (const LinkError&) {
    }
  }
  try {
    static_cast<void>(reply.text("no-such-key="));
    __builtin_trap();
  } catch (const LinkError&) {
  }
  static_cast<void>(odocal::host::hash_line_pairs(line));
}

// A reply the client returns: an `ok` or `err` line, never a `#` line.
const Reply& checked(const Reply& reply) {
  Reply again;
  if (reply.line.empty() || reply.line[0] == '#' || !odocal::host::parse_reply(reply.line, again) ||
      again.ok != reply.ok)
    __builtin_trap();
  return reply;
}

// One run as a session drives it (session_run.cpp): odom reset, the checked stream
// (read_tick_line), the run, its `# done`, `trial` into the run's record (read_trial: asked until
// two answers agree) and session.json, `get`, `params` with its listing.
void session_run(odocal::host::RobotClient& robot) {
  using namespace odocal::host;
  RunRecord r;
  robot.on_ticks([&r](const std::string& line) {
    // As a session reads them: checked (`stream ticks 50 crc`) and, from older firmware, not.
    for (const bool crc : {true, false}) {
      if (const std::optional<TickSample> sample = session::read_tick_line(line, crc))
        r.ticks.push_back(*sample);
    }
  });
  const Reply status = checked(robot.command("status"));
  if (status.ok && status.pairs.count("ticks") != 0u)
    static_cast<void>(odocal::toolkit::parse_integer(status.text("ticks")));
  robot.expect_ok("odom reset");
  robot.expect_ok("stream ticks 50 crc");
  robot.expect_ok("run line 1.000");
  const std::map<std::string, std::string> done = robot.poll_done(0);
  robot.expect_ok("stream off");
  robot.on_ticks(nullptr);
  r.label = "line";
  r.motion = odocal::host::Motion::line(1.0);
  try {
    session::read_trial(robot, done, r, 0);
  } catch (const LinkError&) {
    // A session stops there (exit 2); what follows is fuzzed on regardless.
  }
  static_cast<void>(nlohmann::json{{"runs", session::runs_json({r})}}.dump(
      2, ' ', false, nlohmann::json::error_handler_t::replace));
  static_cast<void>(robot.expect_ok("get c_l").number("value"));
  std::vector<std::string> listing;
  const Reply params = checked(robot.command("params", 10000, &listing));
  for (const std::string& line : listing) {
    if (line.empty() || line[0] != '#')
      __builtin_trap();
    static_cast<void>(hash_line_pairs(line));
  }
  static_cast<void>(params);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::vector<std::string> lines = lines_of(input);
  for (const std::string& line : lines)
    check_reply(line);

  ScriptedChannel channel(lines);
  odocal::host::RobotClient robot(channel);
  robot.watch_restarts(true);
  for (int attempt = 0; attempt < 64 && !channel.drained(); ++attempt) {
    try {
      session_run(robot);
    } catch (const odocal::host::RobotRestarted&) {
      robot.watch_restarts(true);
    } catch (const LinkError&) {
    }
  }
  robot.drain(0);
  return 0;
}
