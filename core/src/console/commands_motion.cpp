// Console commands that move the robot or watch it move: odom, drive, stop, run, stream, trial,
// trials.

#include <cmath>

#include "odocal/console/console.hpp"
#include "odocal/drive/diff_drive_kinematics.hpp"
#include "odocal/drive/motion_executor.hpp"

namespace odocal::console {
namespace {

constexpr int kPoseDecimals = 3;
constexpr float kRadToDeg = 180.0f / 3.14159265358979323846f;

Reply& pose_pairs(Reply& reply, const drive::Pose& pose) {
  return reply.pair("x_mm", pose.x_m * 1000.0f, kPoseDecimals)
      .pair("y_mm", pose.y_m * 1000.0f, kPoseDecimals)
      .pair("theta_deg", pose.theta_rad * kRadToDeg, kPoseDecimals);
}

}  // namespace

void Console::cmd_odom(std::size_t count) {
  if (count == 2u) {  // odom reset
    // The path's segments end on odometry: zeroing it mid-path would stretch the segment.
    if (refuse_busy(true)) {
      return;
    }
    loop_.reset_pose();
  }
  OkLine reply(out_);
  pose_pairs(reply, loop_.pose());
  send(reply);
}

void Console::cmd_drive(const Token* words, std::size_t count) {
  float v = 0.0f;
  float w = 0.0f;
  if (!number_arg(words[1], -5.0f, 5.0f, v) || !number_arg(words[2], -50.0f, 50.0f, w)) {
    return;
  }
  std::uint32_t ms = 0u;
  if (count == 4u) {
    float parsed = 0.0f;
    if (!number_arg(words[3], 0.0f, 600000.0f, parsed, "ms must be a whole number")) {
      return;
    }
    ms = static_cast<std::uint32_t>(parsed);
  }
  drive::Twist twist;
  twist.v_mps = v;
  twist.w_radps = w;
  if (!loop_.drive(twist, ms)) {
    send_error(ErrorCode::fault, "drive faulted; stop acknowledges");
    return;
  }
  note_pending(Pending::drive);
  OkLine reply(out_);
  reply.pair("v_mps", v, kPoseDecimals).pair("w_radps", w, kPoseDecimals).pair_u("ms", ms);
  // The loop scales both wheel set-points down to max_wheel_radps, keeping the curvature: say so,
  // with the twist that will really be driven.
  const drive::DriveConfig config = params::to_drive_config(settings_.values());
  const drive::DiffDriveKinematics kinematics(config);
  const drive::WheelRates rates = kinematics.inverse(twist);
  const float peak = std::fmax(std::fabs(rates.left_radps), std::fabs(rates.right_radps));
  if (peak > config.max_wheel_radps) {
    const float scale = config.max_wheel_radps / peak;
    reply.pair_u("clipped", 1u)
        .pair("v_clipped_mps", v * scale, kPoseDecimals)
        .pair("w_clipped_radps", w * scale, kPoseDecimals);
  }
  send(reply);
}

void Console::cmd_stop() {
  loop_.stop();
  note_pending(Pending::stop);
  OkLine reply(out_);
  reply.pair_s("mode", "idle");
  send(reply);
}

void Console::cmd_run(const Token* words) {
  // The table matched the path's name and the word count.
  const Token& name = words[1];
  const bool line = name.is("line");
  const bool unseen = name.is("unseen");
  const bool square = !line && !unseen;
  float length_m = 0.0f;
  if (!unseen && !number_arg(words[2], 0.01f, 20.0f, length_m)) {
    return;
  }
  if (refuse_busy(true)) {
    return;
  }
  drive::Path path;
  if (square) {
    path = drive::make_umbmark_square(name.is("umbmark-cw"), length_m);
  } else if (line) {
    path = drive::make_line(length_m);
  } else {
    path = drive::make_unseen_path();
  }
  if (!loop_.run(path)) {
    send_error(ErrorCode::fault, "drive faulted; stop acknowledges");
    return;
  }
  note_pending(Pending::run);
  if (square) {
    umbmark_.note_driven_side_mm(length_m * 1000.0f);
  }
  OkLine reply(out_);
  reply.pair_s("path", drive::path_name(path.id)).pair_u("segments", path.count);
  if (!unseen) {
    reply.pair("length_m", length_m, kPoseDecimals);
  }
  send(reply);
}

void Console::cmd_stream(const Token* words) {
  // The table matched odom, ticks or off and the word count.
  const bool odom = words[1].is("odom");
  const bool ticks = words[1].is("ticks");
  if (!odom && !ticks) {
    stream_odom_ = false;
    stream_ticks_ = false;
    OkLine reply(out_);
    reply.pair_s("stream", "off");
    send(reply);
    return;
  }
  // Tick logs want the control rate's detail; odometry is for watching.
  float hz = 0.0f;
  if (!number_arg(words[2], 0.1f, ticks ? 1000.0f : 100.0f, hz)) {
    return;
  }
  ReplyLine reply(out_);
  const auto period_us = static_cast<std::uint32_t>(1.0e6f / hz + 0.5f);
  if (odom) {
    stream_odom_ = true;
    odom_period_us_ = period_us;
    odom_next_us_ = last_now_us_ + period_us;
  } else {
    stream_ticks_ = true;
    ticks_period_us_ = period_us;
    ticks_next_us_ = last_now_us_ + period_us;
  }
  reply.text("ok").pair_s("stream", odom ? "odom" : "ticks").pair("hz", hz, kPoseDecimals);
  send(reply);
}

void Console::cmd_trial(const Token* words, std::size_t count) {
  const KeptTrial* trial = nullptr;
  if (count == 2u) {
    std::uint32_t number = 0u;
    if (!parse_unsigned(words[1], number)) {
      send_error(ErrorCode::bad_number, "trial number is a whole number");
      return;
    }
    trial = trials_.find(number);
    if (trial == nullptr) {
      send_error(ErrorCode::no_trial, "no such trial kept (see trials)");
      return;
    }
  } else {
    trial = trials_.latest();
    if (trial == nullptr) {
      send_error(ErrorCode::no_trial, "no trial yet (run a path or drive)");
      return;
    }
  }
  OkLine reply(out_);
  reply.pair_u("trial", trial->number);
  trial_pairs(reply, *trial);
  send(reply);
}

void Console::trial_pairs(Reply& reply, const KeptTrial& trial) {
  reply.pair_s("path", drive::path_name(trial.path))
      .pair_u("duration_ms", trial.duration_ms)
      .pair_i("count_l", trial.count_l)
      .pair_i("count_r", trial.count_r);
  pose_pairs(reply, trial.end);
}

void Console::cmd_trials(std::size_t count) {
  if (count == 2u) {  // trials clear
    trials_.clear();
    OkLine reply(out_);
    reply.pair_u("trials", 0u);
    send(reply);
    return;
  }
  start_listing(Listing::trials);
}

}  // namespace odocal::console
