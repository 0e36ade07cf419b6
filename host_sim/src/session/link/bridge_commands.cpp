// The console commands of a ROSArduinoBridge robot's host-side console that change or report its
// parameters and its motions (bridge_console.hpp; the frames and the link: bridge_console.cpp).

#include <algorithm>
#include <cmath>
#include <numbers>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "bridge_internal.hpp"
#include "odocal/host/bridge_console.hpp"
#include "odocal/host/motion.hpp"
#include "odocal/toolkit/numbers.hpp"

namespace odocal::host {

using bridge_detail::field_named;
using bridge_detail::group_of;
using bridge_detail::kFrameMs;
using bridge_detail::words_of;

namespace {

/// The self-test's drive of one wheel, and the coasting after it, ms: longer than odocal's own
/// (0.3 s), as ROSArduinoBridge's PID adds only a fraction of the error to its PWM each frame.
constexpr double kSelftestDriveMs = 600.0;
constexpr double kSelftestCoastMs = 800.0;

}  // namespace

void BridgeConsole::command_set(const std::string& name, const std::string& value) {
  const drive::ConfigField* f = field_named(name);
  if (f == nullptr) {
    reply("err unknown_param " + name);
    return;
  }
  if (motion_ != Motion::idle) {
    reply("err busy the robot moves");
    return;
  }
  if (name == "wiring_fix" || name == "counts_per_rev" || name == "wheel_diameter_mm") {
    reply("err read_only " + name +
          " is the robot's own on a ROSArduinoBridge robot (wiring: its firmware's pins; the "
          "nominal geometry: odocal's command line)");
    return;
  }
  const auto parsed = toolkit::parse_real(value);
  if (!parsed || !std::isfinite(*parsed) || *parsed < f->min || *parsed > f->max) {
    reply(fmt::format("err bad_value {} {} .. {}", name, f->min, f->max));
    return;
  }
  drive::DriveConfig next = config_;
  f->set(next, static_cast<float>(*parsed));
  if (!drive::valid(next)) {
    reply("err rejected drive refused " + name);
    return;
  }
  config_ = next;
  configure();
  unsaved_ = true;
  if (const char* group = group_of(name)) {
    provenance_[std::string(group) + "_method"] = "manual";
  }
  reply("ok " + parameter_reply(*f));
}

void BridgeConsole::command_params() {
  int count = 0;
  for (const drive::ConfigField& f : drive::config_fields) {
    reply(fmt::format("# {} unit={} min={:.6f} max={:.6f} default={:.6f}", parameter_reply(f),
                      f.unit, f.min, f.max, static_cast<double>(f.get(started_))));
    ++count;
  }
  reply(fmt::format("ok params={} unsaved={}", count, unsaved_ ? 1 : 0));
}

void BridgeConsole::command_fit_apply(const std::string& line) {
  // fit apply <c_l> <c_r> <wheelbase_mm> [unix_s [runs]] [arc <mm>]
  std::vector<std::string> w = words_of(line);
  double arc = 0.0;
  if (w.size() >= 4 && w[w.size() - 2] == "arc") {
    const auto value = toolkit::parse_real(w.back());
    if (!value) {
      reply("err bad_value arc");
      return;
    }
    arc = *value;
    w.resize(w.size() - 2);
  }
  if (w.size() < 5 || w.size() > 7) {
    reply("err usage fit apply <c_l> <c_r> <wheelbase_mm> [unix_s [runs]] [arc <mm>]");
    return;
  }
  double values[5] = {0, 0, 0, 0, 0};
  for (std::size_t i = 2; i < w.size(); ++i) {
    const auto value = toolkit::parse_real(w[i]);
    if (!value) {
      reply("err bad_value " + w[i]);
      return;
    }
    values[i - 2] = *value;
  }
  drive::DriveConfig next = config_;
  next.c_l = static_cast<float>(values[0]);
  next.c_r = static_cast<float>(values[1]);
  next.wheelbase_mm = static_cast<float>(values[2]);
  next.wheelbase_arc_mm = static_cast<float>(arc);
  if (!drive::valid(next)) {
    reply(
        "err rejected drive refused (need wheelbase_arc_mm 0 or within 20% of wheelbase_mm, "
        "values in range)");
    return;
  }
  config_ = next;
  configure();
  unsaved_ = true;
  provenance_["wheel_method"] = "fit";
  provenance_["wheel_date"] = w.size() >= 6 ? w[5] : "0";
  provenance_["wheel_runs"] = w.size() >= 7 ? w[6] : "0";
  reply(fmt::format(
      "ok c_l={:.6f} c_r={:.6f} wheelbase_mm={:.6f} wheelbase_arc_mm={:.6f} method=fit{} "
      "unsaved=1",
      config_.c_l, config_.c_r, config_.wheelbase_mm, config_.wheelbase_arc_mm,
      w.size() >= 7 ? " runs=" + w[6] : std::string()));
}

void BridgeConsole::command_run(const std::string& line) {
  // Read as the robot reads it (host::Motion): the same paths, lengths and ranges.
  const std::optional<host::Motion> motion = host::Motion::of_command(line);
  if (!motion || !motion->path() || motion->kind == host::Motion::Kind::timed) {
    const std::vector<std::string> w = words_of(line);
    const bool has_length =
        w.size() == 3 && (w[1] == "line" || w[1] == "umbmark-cw" || w[1] == "umbmark-ccw");
    reply(has_length ? "err bad_value length 0.01 .. 20 m"
                     : "err usage run umbmark-cw|umbmark-ccw <side_m> | run line <m> | run unseen");
    return;
  }
  if (motion_ != Motion::idle) {
    executor_.cancel();
  }
  const drive::Path path = *motion->path();
  const float length_m = motion->length_m;
  begin_motion(Motion::path, drive::path_name(path.id));
  executor_.start(path, odometry_);
  reply(fmt::format("ok path={} segments={} length_m={:.3f}", drive::path_name(path.id), path.count,
                    static_cast<double>(length_m)));
}

void BridgeConsole::command_drive(const std::string& line) {
  const std::optional<host::Motion> motion = host::Motion::of_command(line);
  if (!motion || motion->kind != host::Motion::Kind::timed || motion->ms == 0u) {
    reply(
        "err usage drive <v_mps> <w_radps> <ms> (a timed drive: the host keeps the robot moving "
        "only while it steers)");
    return;
  }
  if (motion_ != Motion::idle) {
    executor_.cancel();
  }
  begin_motion(Motion::timed, "drive");
  timed_twist_ = drive::Twist{motion->v_mps, motion->w_radps};
  timed_ms_ = static_cast<double>(motion->ms);
  reply(fmt::format("ok v_mps={:.3f} w_radps={:.3f} ms={}", motion->v_mps, motion->w_radps,
                    motion->ms));
}

void BridgeConsole::command_selftest(const std::string& which) {
  if (!which.empty() && which != "left" && which != "right") {
    reply("err usage selftest [left|right]");
    return;
  }
  const double per_rad = static_cast<double>(config_.counts_per_rev) / (2.0 * std::numbers::pi);
  const long speed = std::max(
      2L, std::lround(0.1 * static_cast<double>(config_.max_wheel_radps) * per_rad / frame_hz));
  std::int64_t seen[2][2] = {{0, 0}, {0, 0}};  // [wheel driven][encoder]
  std::vector<std::string> faults;
  for (int side = 0; side < 2; ++side) {
    if ((side == 0 && which == "right") || (side == 1 && which == "left")) {
      continue;
    }
    const std::int64_t before[2] = {cumulative_[0], cumulative_[1]};
    const std::string command =
        side == 0 ? fmt::format("m {} 0", speed) : fmt::format("m 0 {}", speed);
    // Frames by hand: `m` for one wheel and `e` to watch, then `m 0 0` and the coasting.
    const double started = now_ms();
    bool stopped = false;
    while (now_ms() - started < kSelftestDriveMs + kSelftestCoastMs) {
      if (now_ms() - started < kSelftestDriveMs) {
        ask_ok(command);
      } else if (!stopped) {
        stop_wheels();
        stopped = true;
      }
      if (!lockstep_) {
        std::this_thread::sleep_for(std::chrono::microseconds(static_cast<long>(kFrameMs * 1e3)));
      }
      check_interrupt();
      frame();
    }
    if (!stopped) {
      stop_wheels();
    }
    queue_.clear();  // no tick lines or `# done` from the self-test's own drives
    seen[side][0] = cumulative_[0] - before[0];
    seen[side][1] = cumulative_[1] - before[1];
    const std::int64_t own = seen[side][side];
    const std::int64_t other = seen[side][1 - side];
    const char* name = side == 0 ? "left" : "right";
    if (own < 0) {
      faults.push_back(std::string(name) + "_reversed");
    } else if (own < 4) {
      faults.push_back(std::string(name) + "_still");
    }
    if (std::llabs(other) >= std::max<std::int64_t>(4, std::llabs(own) / 2)) {
      faults.push_back("crossed");
    }
  }
  std::string list;
  for (const std::string& f : faults) {
    if (list.find(f) == std::string::npos) {
      list += (list.empty() ? "" : ",") + f;
    }
  }
  reply(fmt::format("ok faults={} ll={} lr={} rl={} rr={}", list.empty() ? "none" : list,
                    seen[0][0], seen[0][1], seen[1][0], seen[1][1]));
  if (!which.empty()) {
    // One wheel alone is a trial (the session measures where it turned the robot).
    trial_.number = ++trials_;
    trial_.path = "drive";
    trial_.duration_ms = kSelftestDriveMs + kSelftestCoastMs;
    const int side = which == "left" ? 0 : 1;
    trial_.count_l = seen[side][0];
    trial_.count_r = seen[side][1];
    trial_.pose = odometry_.pose();
    have_trial_ = true;
    reply(fmt::format("# done trial={} path=drive", trial_.number));
  }
}

void BridgeConsole::command_measure(const std::string& line) {
  const std::string answer = ask(line, 5000);
  if (answer.rfind("ok", 0) == 0 || answer.rfind("err", 0) == 0) {
    reply(answer);
  } else {
    reply("err unknown_command measure (the robot answered '" + answer +
          "': only odocal-sim has a tape)");
  }
}

}  // namespace odocal::host
