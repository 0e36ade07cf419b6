// The console's line protocol on top of a line channel: replies, `#` lines, `# done`.

#include "odocal/host/robot_client.hpp"

#include <array>
#include <chrono>
#include <cstdio>

#include "link_internal.hpp"
#include "odocal/console/commands.hpp"
#include "odocal/drive/drive_config.hpp"
#include "odocal/toolkit/numbers.hpp"

namespace odocal::host {

using link_detail::Clock;
using link_detail::remaining_ms;

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
  if (watch_restarts_ && line.rfind("# odocal ", 0) == 0 &&
      line.find(" console ") != std::string::npos) {
    watch_restarts_ = false;
    snapshot_.clear();  // what it held in RAM is gone
    throw RobotRestarted(channel_.name() + ": the robot restarted (it printed its start-up line '" +
                         line + "')");
  }
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

void RobotClient::before_sending(const std::string& line) {
  // The robot's own reading of the line (console/commands.hpp) says what it may change.
  std::array<console::Token, 12> words{};
  const std::size_t count = console::split(line.data(), line.size(), words.data(), words.size());
  if (count == 1u && words[0].is("measure")) {
    return;  // odocal-sim's question (where the robot is), not a robot command
  }
  const console::FormLookup lookup = console::find_form(words.data(), count);
  if (lookup.result != console::FormLookup::Result::found) {
    // Refused by the robot (changes nothing), or a line this client does not know: forgotten all
    // the same, as the robot's firmware may be newer than this table.
    snapshot_.clear();
    return;
  }
  const auto forget_group = [this](drive::FactorGroup group) {
    for (const drive::ConfigField& field : drive::config_fields) {
      if (field.group == group) {
        snapshot_.erase(std::string("get ") + field.name);
      }
    }
  };
  switch (lookup.form->changes()) {
    case console::Changes::nothing:
      return;
    case console::Changes::named:
      snapshot_.erase("get " + std::string(words[1].text, words[1].length));
      return;
    case console::Changes::wheel:
      forget_group(drive::FactorGroup::wheel);
      return;
    case console::Changes::lateral:
      forget_group(drive::FactorGroup::lateral);
      return;
    case console::Changes::any:
      break;
  }
  snapshot_.clear();
}

void RobotClient::remember(const std::string& name, double value) {
  Reply reply;
  char text[96];
  std::snprintf(text, sizeof text, "ok %s=%.6f", name.c_str(), value);
  static_cast<void>(parse_reply(text, reply));
  snapshot_["get " + name] = reply;
}

void RobotClient::send(const std::string& line) {
  before_sending(line);
  ++lines_sent_;
  if (line.rfind("get ", 0) == 0) {
    ++gets_sent_;
  }
  channel_.write_line(line);
}

void RobotClient::say_chatter() {
  if (chatter_.empty() || in_chatter_) {
    return;
  }
  in_chatter_ = true;
  try {
    static_cast<void>(command(chatter_));
  } catch (...) {
    in_chatter_ = false;
    throw;
  }
  in_chatter_ = false;
}

void RobotClient::probe_restart() {
  // A robot that restarted while a command ran (its reply lost with the reset) says so only
  // before the reply to its next odocal command: its start-up line waits for one. Asked once.
  if (!watch_restarts_) {
    return;
  }
  send("status");
  std::string received;
  while (channel_.read_line(received, 2000) && !received.empty() && received[0] == '#') {
    route(received);  // the start-up line throws RobotRestarted
  }
}

namespace {

/// Whether sending `line` twice does what sending it once does: such a line is sent again when
/// its reply comes damaged. A motion, an `add`, or an `apply` that composes with what is in force
/// (umbmark, lateral) is not; its damaged reply comes back as `err garbled` for the caller to
/// judge. `set`, `fit apply`, `lateral set` put values, `save` saves what is in force: repeatable.
bool repeatable(const std::string& line) {
  for (const char* verb : {"run ", "drive ", "selftest", "umbmark add", "umbmark apply",
                           "lateral add", "lateral apply"}) {
    if (line.rfind(verb, 0) == 0) {
      return false;
    }
  }
  return true;
}

}  // namespace

Reply RobotClient::command(const std::string& line, int timeout_ms,
                           std::vector<std::string>* listing) {
  send(line);
  const Clock::time_point deadline = Clock::now() + std::chrono::milliseconds(timeout_ms);
  std::string received;
  int resent = 0;
  for (;;) {
    if (!channel_.read_line(received, remaining_ms(deadline))) {
      probe_restart();
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
      say_chatter();
      return reply;
    }
    // Anything else (an echo of typed text, line noise at start-up) is not a reply. In the
    // session it is a reply damaged on the line: asked again, or handed back as such.
    if (in_session_) {
      ++garbled_;
      if (!repeatable(line)) {
        Reply damaged;
        damaged.line = received;
        damaged.code = "garbled";
        damaged.message = "the reply came damaged on the line: '" + received + "'";
        return damaged;
      }
      if (resent < 3) {
        ++resent;
        if (listing != nullptr) {
          listing->clear();
        }
        send(line);
      }
    }
  }
}

Reply RobotClient::status() {
  for (int asked = 1;; ++asked) {
    Reply reply = command("status");
    const auto field = [&reply](const char* key) {
      const auto it = reply.pairs.find(key);
      return it == reply.pairs.end() ? std::string() : it->second;
    };
    const std::string mode = field("mode");
    const std::string unsaved = field("unsaved");
    const std::string ticks = field("ticks");
    const bool whole = reply.ok &&
                       (mode == "idle" || mode == "drive" || mode == "path" || mode == "fault") &&
                       (unsaved == "0" || unsaved == "1") &&
                       (reply.pairs.count("ticks") == 0u || toolkit::parse_integer(ticks));
    if (whole) {
      return reply;
    }
    if (asked == 5) {
      throw LinkError(channel_.name() + ": 'status' answered '" + reply.line +
                      "' five times over without a whole reply (line noise?)");
    }
  }
}

Reply RobotClient::query(const std::string& line, int timeout_ms) {
  const bool parameter = line.rfind("get ", 0) == 0;
  if (parameter) {
    const auto known = snapshot_.find(line);
    if (known != snapshot_.end()) {
      return known->second;
    }
  }
  // Two equal answers: a damaged one (a lost or flipped byte) does not repeat itself. On a line
  // that damages a quarter of the replies, twelve asks find two clean ones but once in 10^5.
  std::vector<Reply> answers;
  for (int asked = 0; asked < 12; ++asked) {
    Reply again = command(line, timeout_ms);
    for (const Reply& before : answers) {
      if (before.line == again.line) {
        if (parameter) {
          snapshot_[line] = again;
        }
        return again;
      }
    }
    answers.push_back(std::move(again));
  }
  throw LinkError(channel_.name() + ": no two answers to '" + line +
                  "' agreed in 12 asks (line noise?); last '" + answers.back().line + "'");
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
    probe_restart();
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
