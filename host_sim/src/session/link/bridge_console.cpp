// The odocal console of a ROSArduinoBridge robot, kept on the host (bridge_console.hpp).

#include "odocal/console/text.hpp"

#include "bridge_internal.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "odocal/console/text.hpp"
#include "odocal/console/version.hpp"
#include "odocal/toolkit/numbers.hpp"

namespace odocal::host {
namespace bridge_detail {

std::vector<std::string> words_of(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string w; in >> w;) {
    words.push_back(w);
  }
  return words;
}

const drive::ConfigField* field_named(const std::string& name) {
  for (const drive::ConfigField& f : drive::config_fields) {
    if (name == f.name) {
      return &f;
    }
  }
  return nullptr;
}

const char* group_of(const std::string& name) {
  const drive::ConfigField* field = field_named(name);
  if (field == nullptr || field->group == drive::FactorGroup::none) {
    return nullptr;
  }
  return field->group == drive::FactorGroup::wheel ? "wheel" : "lateral";
}

}  // namespace bridge_detail

using bridge_detail::field_named;
using bridge_detail::group_of;
using bridge_detail::kFrameMs;
using bridge_detail::words_of;

namespace {

/// A trial ends once both wheels have been still this long (at least; settle_ms if longer) ...
constexpr double kStillMs = 100.0;
/// ... or this long after the motion, whatever the wheels do (the firmware's bound).
constexpr double kSettleMaxMs = 3000.0;

/// "a b" of `e`: two whole numbers, nothing else.
bool parse_counts(const std::string& text, std::int32_t& left, std::int32_t& right) {
  const std::vector<std::string> words = words_of(text);
  if (words.size() != 2u) {
    return false;
  }
  const auto l = toolkit::parse_integer(words[0]);
  const auto r = toolkit::parse_integer(words[1]);
  if (!l || !r || *l < INT32_MIN || *l > INT32_MAX || *r < INT32_MIN || *r > INT32_MAX) {
    return false;
  }
  left = static_cast<std::int32_t>(*l);
  right = static_cast<std::int32_t>(*r);
  return true;
}

}  // namespace

BridgeConsole::BridgeConsole(FdChannel& link, const BridgeNominal& nominal, bool lockstep)
    : link_(link), nominal_(nominal), lockstep_(lockstep) {
  link_.set_line_end("\r");
  config_.wheel_diameter_mm = static_cast<float>(nominal.wheel_diameter_mm);
  config_.wheelbase_mm = static_cast<float>(nominal.wheelbase_mm);
  config_.counts_per_rev = static_cast<float>(nominal.counts_per_rev);
  started_ = config_;
  configure();
  for (const char* group : {"wheel", "lateral"}) {
    provenance_[std::string(group) + "_method"] = "defaults";
    provenance_[std::string(group) + "_runs"] = "0";
    provenance_[std::string(group) + "_date"] = "0";
  }
}

std::string BridgeConsole::name() const {
  return link_.name() + " (ROSArduinoBridge)";
}

void BridgeConsole::configure() {
  kinematics_.configure(config_);
}

double BridgeConsole::now_ms() const {
  if (lockstep_) {
    return static_cast<double>(frames_) * kFrameMs;
  }
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_)
      .count();
}

void BridgeConsole::connect() {
  // A board that resets when its port opens (an Arduino over USB) takes a second or two to
  // listen: `b` asked up to three times. Whatever the port held before is dropped.
  std::string stale;
  while (link_.read_line(stale, 100)) {
  }
  for (int attempt = 1;; ++attempt) {
    link_.write_line("b");
    std::string line;
    const bool got = link_.read_line(line, 2000);
    const auto value = got ? toolkit::parse_integer(line) : std::nullopt;
    if (value && *value > 0) {
      baud_ = static_cast<long>(*value);
      break;
    }
    if (attempt == 3) {
      throw LinkError(link_.name() + ": no ROSArduinoBridge answer to 'b' (the baud rate)" +
                      (got ? ", got '" + line + "'" : std::string(" within 2 s")) +
                      " (is it a ROSArduinoBridge robot at this baud rate?)");
    }
    while (link_.read_line(stale, 300)) {
    }
  }
  connected_ = true;
  start_ = std::chrono::steady_clock::now();
  next_frame_ = start_;
}

std::string BridgeConsole::ask(const std::string& command, int timeout_ms,
                               const std::function<bool(const std::string&)>& expected,
                               const char* what) {
  // A line still waiting is not this command's reply (the answer to the `m 0 0` a Ctrl-C sent
  // from the signal handler, a reply that came after its command timed out): dropped.
  std::string line;
  while (link_.read_line(line, 0)) {
  }
  link_.write_line(command);
  // ROSArduinoBridge answers every line with one line; one that is not what the command answers
  // (a late reply to an earlier line) is passed over, twice at most.
  for (int read = 0; read < 3; ++read) {
    if (!link_.read_line(line, timeout_ms)) {
      throw LinkError(link_.name() + ": no reply to '" + command + "' within " +
                      std::to_string(timeout_ms) + " ms (ROSArduinoBridge)");
    }
    if (!expected || expected(line)) {
      return line;
    }
  }
  throw LinkError(link_.name() + ": '" + command + "' answered '" + line + "', not " + what +
                  " (ROSArduinoBridge)");
}

void BridgeConsole::ask_ok(const std::string& command) {
  static_cast<void>(ask(
      command, 2000, [](const std::string& line) { return line == "OK"; }, "OK"));
}

void BridgeConsole::write_line(const std::string& line) {
  if (!connected_) {
    connect();
  }
  answer(line);
}

bool BridgeConsole::read_line(std::string& line, int timeout_ms) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  const double robot_deadline_ms = now_ms() + timeout_ms;
  for (;;) {
    if (!queue_.empty()) {
      line = queue_.front();
      queue_.pop_front();
      return true;
    }
    if (!active()) {
      return false;  // nothing moves and nothing streams: no line will come
    }
    if (lockstep_) {
      if (now_ms() >= robot_deadline_ms) {
        return false;
      }
    } else {
      const auto now = std::chrono::steady_clock::now();
      if (next_frame_ > now) {
        if (next_frame_ > deadline) {
          std::this_thread::sleep_until(deadline);
          check_interrupt();
          return false;
        }
        std::this_thread::sleep_until(next_frame_);
      }
      // Frames keep their 1/30 s grid; one late by more than a frame starts a new grid.
      next_frame_ += std::chrono::microseconds(static_cast<long>(kFrameMs * 1000.0));
      if (next_frame_ < std::chrono::steady_clock::now()) {
        next_frame_ = std::chrono::steady_clock::now();
      }
    }
    check_interrupt();
    frame();
  }
}

bool BridgeConsole::jumped(const std::int32_t raw[2]) const {
  // 1.5 times the wheel speed limit over the time since the last reading and a frame, and a
  // margin: no wheel turns that far. (A reset early in a run goes unseen: docs/ros.md.)
  const double elapsed_s = std::max(0.0, now_ms() - last_frame_ms_) / 1000.0 + 1.0 / frame_hz;
  const double limit = 1.5 * config_.max_wheel_radps / (2.0 * std::numbers::pi) *
                           nominal_.counts_per_rev * elapsed_s +
                       20.0;
  for (int side = 0; side < 2; ++side) {
    const auto delta = static_cast<std::int32_t>(static_cast<std::uint32_t>(raw[side]) -
                                                 static_cast<std::uint32_t>(raw_[side]));
    if (std::fabs(static_cast<double>(delta)) > limit) {
      return true;
    }
  }
  return false;
}

void BridgeConsole::read_counts(std::int32_t raw[2]) {
  static_cast<void>(ask(
      "e", 2000, [raw](const std::string& line) { return parse_counts(line, raw[0], raw[1]); },
      "two encoder counts"));
}

void BridgeConsole::frame() {
  std::int32_t raw[2] = {0, 0};
  read_counts(raw);
  if (have_raw_ && jumped(raw)) {
    // A damaged reply does not repeat itself; a robot that restarted (counts from 0) does.
    std::int32_t again[2] = {0, 0};
    read_counts(again);
    if (jumped(again)) {
      throw LinkError(fmt::format(
          "the robot's encoder counts went from {} {} to {} {} between two readings, farther than "
          "its wheels turn, and read so again: it restarted (a brown-out, a loose battery lead: "
          "its counts start again from 0) or an encoder is loose. The run under way is not counted",
          raw_[0], raw_[1], again[0], again[1]));
    }
    std::copy(again, again + 2, raw);
  }
  ++frames_;
  const double t_ms = now_ms();
  const double dt_s = std::clamp((t_ms - last_frame_ms_) / 1000.0, 0.005, 0.2);
  last_frame_ms_ = t_ms;
  for (int side = 0; side < 2; ++side) {
    // The robot's counts are 32-bit and wrap; the difference of two readings does not.
    frame_delta_[side] = have_raw_
                             ? static_cast<std::int32_t>(static_cast<std::uint32_t>(raw[side]) -
                                                         static_cast<std::uint32_t>(raw_[side]))
                             : 0;
    raw_[side] = raw[side];
    cumulative_[side] += frame_delta_[side];
  }
  have_raw_ = true;
  const auto dl = static_cast<float>(frame_delta_[0]);
  const auto dr = static_cast<float>(frame_delta_[1]);
  odometry_.update(dl * kinematics_.left_m_per_count(), dr * kinematics_.right_m_per_count(),
                   kinematics_.wheelbase_for_rates_m(dl, dr));
  if (streaming_) {
    std::string line = fmt::format("# ticks t_ms={:.0f} count_l={} count_r={}", t_ms,
                                   cumulative_[0], cumulative_[1]);
    if (streaming_crc_) {  // as odocal's console writes it (`stream ticks <hz> crc`)
      line += fmt::format(" crc={}", console::crc16(line.data(), line.size()));
    }
    reply(line);
  }
  switch (motion_) {
    case Motion::idle:
      break;
    case Motion::path: {
      const drive::Twist twist = executor_.update(odometry_, config_, static_cast<float>(dt_s));
      if (executor_.busy()) {
        send_wheels(twist);
      } else {
        begin_settling();
      }
      break;
    }
    case Motion::timed:
      if (t_ms - motion_start_ms_ >= timed_ms_) {
        begin_settling();
      } else {
        send_wheels(timed_twist_);
      }
      break;
    case Motion::settling: {
      still_ms_ = frame_delta_[0] == 0 && frame_delta_[1] == 0 ? still_ms_ + dt_s * 1000.0 : 0.0;
      const double still_needed = std::max<double>(kStillMs, config_.settle_ms);
      if (still_ms_ >= still_needed || t_ms - settle_start_ms_ >= kSettleMaxMs) {
        trial_.number = ++trials_;
        trial_.path = motion_path_;
        trial_.duration_ms = t_ms - motion_start_ms_;
        trial_.count_l = cumulative_[0] - motion_start_counts_[0];
        trial_.count_r = cumulative_[1] - motion_start_counts_[1];
        trial_.pose = odometry_.pose();
        have_trial_ = true;
        motion_ = Motion::idle;
        reply(fmt::format("# done trial={} path={}", trial_.number, trial_.path));
      }
      break;
    }
  }
}

long BridgeConsole::wheel_counts(int side, double wanted) {
  // Whole counts per frame, the fractions carried to the next frame: the mean is what was asked.
  carry_[side] += wanted;
  const double sent = std::round(carry_[side]);
  carry_[side] -= sent;
  return static_cast<long>(sent);
}

void BridgeConsole::send_wheels(const drive::Twist& twist) {
  drive::WheelRates rates = kinematics_.inverse(twist);
  float scale = 1.0f;
  static_cast<void>(drive::limit_wheel_speeds(rates, config_.max_wheel_radps, scale));
  const double per_rad = static_cast<double>(config_.counts_per_rev) / (2.0 * std::numbers::pi);
  const long left = wheel_counts(0, rates.left_radps * per_rad / frame_hz);
  const long right = wheel_counts(1, rates.right_radps * per_rad / frame_hz);
  if (left == 0 && right == 0) {
    // ROSArduinoBridge reads `m 0 0` as a stop (motors off, its PID reset): sent once.
    if (!wheels_stopped_) {
      ask_ok("m 0 0");
      wheels_stopped_ = true;
    }
    return;
  }
  ask_ok(fmt::format("m {} {}", left, right));
  wheels_stopped_ = false;
}

void BridgeConsole::stop_wheels() {
  ask_ok("m 0 0");
  wheels_stopped_ = true;
  carry_[0] = carry_[1] = 0.0;
}

void BridgeConsole::begin_motion(Motion motion, const std::string& path_name) {
  motion_ = motion;
  motion_path_ = path_name;
  motion_start_ms_ = now_ms();
  last_frame_ms_ = motion_start_ms_;
  motion_start_counts_[0] = cumulative_[0];
  motion_start_counts_[1] = cumulative_[1];
  carry_[0] = carry_[1] = 0.0;
  have_trial_ = false;
  if (!lockstep_) {
    next_frame_ = std::chrono::steady_clock::now();
  }
}

void BridgeConsole::begin_settling() {
  stop_wheels();
  motion_ = Motion::settling;
  settle_start_ms_ = now_ms();
  still_ms_ = 0.0;
}

std::string BridgeConsole::parameter_reply(const drive::ConfigField& field) const {
  return fmt::format("{}={:.6f}", field.name, static_cast<double>(field.get(config_)));
}

bool BridgeConsole::answer_parameters(const std::vector<std::string>& w, const std::string& line) {
  const std::string& verb = w[0];
  const bool moving = motion_ != Motion::idle;
  if (verb == "get" && w.size() == 2) {
    const drive::ConfigField* f = field_named(w[1]);
    reply(f == nullptr ? "err unknown_param " + w[1] : "ok " + parameter_reply(*f));
  } else if (verb == "set" && w.size() == 3) {
    command_set(w[1], w[2]);
  } else if (verb == "params") {
    command_params();
  } else if (verb == "provenance") {
    std::string text = "ok";
    for (const char* key : {"wheel_method", "wheel_runs", "wheel_date", "lateral_method",
                            "lateral_runs", "lateral_date"}) {
      text += std::string(" ") + key + "=" + provenance_[key];
    }
    reply(text);
  } else if (verb == "load") {
    config_ = started_;
    configure();
    unsaved_ = false;
    reply("ok sequence=0 version=0 migrated=0");
  } else if (verb == "save") {
    reply(
        "err read_only nothing is written to a ROSArduinoBridge robot (odocal writes "
        "diff_drive_controller.yaml)");
  } else if (verb == "fit" && w.size() >= 2 && w[1] == "apply") {
    if (moving) {
      reply("err busy the robot moves");
    } else {
      command_fit_apply(line);
    }
  } else {
    return false;
  }
  return true;
}

void BridgeConsole::answer(const std::string& line) {
  const std::vector<std::string> w = words_of(line);
  if (w.empty()) {
    return;
  }
  if (answer_parameters(w, line)) {
    return;
  }
  const std::string& verb = w[0];
  const bool moving = motion_ != Motion::idle;
  if (verb == "echo") {
    reply("ok echo=" + std::string(w.size() > 1 && w[1] == "on" ? "on" : "off"));
  } else if (verb == "version") {
    reply(
        fmt::format("ok name=ROSArduinoBridge version={}-baud protocol=ros-arduino-bridge baud={} "
                    "host={}",
                    baud_, baud_, console::project_version));
  } else if (verb == "status") {
    const char* mode = motion_ == Motion::idle    ? "idle"
                       : motion_ == Motion::timed ? "drive"
                                                  : "path";
    reply(fmt::format("ok mode={} faults=none unsaved={} store=none trials={}", mode,
                      unsaved_ ? 1 : 0, trials_));
  } else if (verb == "stop") {
    executor_.cancel();
    motion_ = Motion::idle;
    stop_wheels();
    reply("ok mode=idle");
  } else if (verb == "stream" && w.size() >= 2 && w[1] == "off") {
    streaming_ = false;
    reply("ok stream=off");
  } else if (verb == "stream" && w.size() == 4 && w[1] == "ticks" && w[3] != "crc") {
    reply("err bad_argument usage: stream ticks <hz> [crc]");
  } else if (verb == "stream" && (w.size() == 3 || w.size() == 4) && w[1] == "ticks") {
    const auto hz = toolkit::parse_real(w[2]);
    if (!hz || *hz < 0.1 || *hz > 1000.0) {
      reply("err bad_value stream ticks: hz 0.1 to 1000");
      return;
    }
    streaming_ = true;  // one line per frame: 30 Hz whatever is asked
    streaming_crc_ = w.size() == 4u;
    reply(fmt::format("ok stream=ticks hz={:.3f}", static_cast<double>(frame_hz)));
  } else if (verb == "odom" && w.size() == 1) {
    const drive::Pose p = odometry_.pose();
    reply(fmt::format("ok x_mm={:.3f} y_mm={:.3f} theta_deg={:.3f}", p.x_m * 1000.0, p.y_m * 1000.0,
                      p.theta_rad * 180.0 / std::numbers::pi));
  } else if (verb == "odom" && w.size() == 2 && w[1] == "reset") {
    if (moving) {
      reply("err busy a path runs");
      return;
    }
    ask_ok("r");  // the robot's counts to zero: the next `e` counts from there
    raw_[0] = raw_[1] = 0;
    have_raw_ = true;
    odometry_.reset();
    reply("ok x_mm=0.000 y_mm=0.000 theta_deg=0.000");
  } else if (verb == "run") {
    command_run(line);
  } else if (verb == "drive") {
    command_drive(line);
  } else if (verb == "trial") {
    if (!have_trial_ || (w.size() == 2 && w[1] != std::to_string(trial_.number))) {
      reply("err no_trial");
      return;
    }
    reply(fmt::format(
        "ok trial={} path={} duration_ms={:.0f} count_l={} count_r={} x_mm={:.3f} y_mm={:.3f} "
        "theta_deg={:.3f}",
        trial_.number, trial_.path, trial_.duration_ms, trial_.count_l, trial_.count_r,
        trial_.pose.x_m * 1000.0, trial_.pose.y_m * 1000.0,
        trial_.pose.theta_rad * 180.0 / std::numbers::pi));
  } else if (verb == "selftest") {
    if (moving) {
      reply("err busy the robot moves");
      return;
    }
    command_selftest(w.size() >= 2 ? w[1] : std::string());
  } else if (verb == "measure") {
    command_measure(line);
  } else {
    reply("err unknown_command " + verb + " (not on a ROSArduinoBridge robot)");
  }
}

}  // namespace odocal::host
