// Console commands that move the robot or watch it move: odom, drive, stop, run, stream, trial,
// trials.

#include "odocal/console/console.hpp"
#include "odocal/drive/diff_drive_kinematics.hpp"
#include "odocal/drive/motion_executor.hpp"

namespace odocal::console {

void Console::cmd_odom(Handler handler) {
  if (handler == Handler::odom_reset) {
    // The path's segments end on odometry: zeroing it mid-path would stretch the segment.
    if (refuse_busy(Busy::path)) {
      return;
    }
    loop_.reset_pose();
  }
  ReplyLine reply(out_);
  reply.text("ok");
  pose_pairs(reply, loop_.pose());
  send(reply);
}

void Console::cmd_drive(const Token* words, std::size_t count) {
  float v = 0.0f;
  float w = 0.0f;
  if (!number_arg(words[1], -drive_v_limit_mps, drive_v_limit_mps, v) ||
      !number_arg(words[2], -drive_w_limit_radps, drive_w_limit_radps, w)) {
    return;
  }
  std::uint32_t ms = 0u;
  if (count == 4u) {
    float parsed = 0.0f;
    if (!number_arg(words[3], 0.0f, drive_ms_max, parsed, "ms must be whole")) {
      return;
    }
    ms = static_cast<std::uint32_t>(parsed);
  }
  drive::Twist twist;
  twist.v_mps = v;
  twist.w_radps = w;
  if (!loop_.drive(twist, ms)) {
    send_error(ErrorCode::fault, "faulted; stop acknowledges");
    return;
  }
  ReplyLine reply(out_);
  append(reply, "ok v_mps=%3 w_radps=%3 ms=%u", v, w, ms);
  // The loop scales both wheel set-points down to max_wheel_radps, keeping the curvature: say so,
  // with the twist that will really be driven.
  const drive::DriveConfig config = params::to_drive_config(settings_.values());
  const drive::DiffDriveKinematics kinematics(config);
  drive::WheelRates rates = kinematics.inverse(twist);
  float scale = 1.0f;
  if (drive::limit_wheel_speeds(rates, config.max_wheel_radps, scale)) {
    append(reply, " clipped=1 v_clipped_mps=%3 w_clipped_radps=%3", v * scale, w * scale);
  }
  send(reply);
}

void Console::cmd_stop() {
  loop_.stop();
  send_line("ok mode=idle");
}

void Console::cmd_run(Handler handler, const Token* words) {
  const bool line = handler == Handler::run_line;
  const bool unseen = handler == Handler::run_unseen;
  const bool square = !line && !unseen;
  float length_m = 0.0f;
  if (!unseen && !number_arg(words[2], run_length_min_m, run_length_max_m, length_m)) {
    return;
  }
  if (refuse_busy(Busy::path)) {
    return;
  }
  // Built in place (one expression): no default path to overwrite, no copy of one.
  const drive::Path path =
      square ? drive::make_umbmark_square(handler == Handler::run_umbmark_cw, length_m)
      : line ? drive::make_line(length_m)
             : drive::make_unseen_path();
  if (!loop_.run(path)) {
    send_error(ErrorCode::fault, "faulted; stop acknowledges");
    return;
  }
  if (square) {
    umbmark_.note_driven_side_mm(length_m * 1000.0f);
  }
  // The unseen path has no length.
  send_either(unseen ? Spec::shorter : Spec::full, "ok path=%s segments=%u length_m=%3",
              "ok path=%s segments=%u", drive::path_name(path.id), path.count, length_m);
}

void Console::cmd_stream(Handler handler, const Token* words, std::size_t count) {
  if (handler == Handler::stream_off) {
    streams_[0].period_us = 0u;
    streams_[1].period_us = 0u;
    send_line("ok stream=off");
    return;
  }
  const bool odom = handler == Handler::stream_odom;
  // Tick logs want the control rate's detail; odometry is for watching.
  float hz = 0.0f;
  if (count == 4u && !words[3].is("crc")) {
    send_usage(ErrorCode::bad_argument);
    return;
  }
  if (!number_arg(words[2], 0.1f, odom ? 100.0f : 1000.0f, hz)) {
    return;
  }
  if (!odom) {
    ticks_crc_ = count == 4u;
  }
  const auto period_us = static_cast<std::uint32_t>(1.0e6f / hz + 0.5f);
  StreamTimer& timer = streams_[odom ? 0u : 1u];
  timer.period_us = period_us;
  timer.next_us = last_now_us_ + period_us;
  send_line("ok stream=%s hz=%3", odom ? "odom" : "ticks", hz);
}

void Console::cmd_trial(const Token* words, std::size_t count) {
  const KeptTrial* trial = nullptr;
  if (count == 2u) {
    std::uint32_t number = 0u;
    if (!parse_unsigned(words[1], number)) {
      send_error(ErrorCode::bad_number, "trial number must be whole");
      return;
    }
    trial = trials_.find(number);
    if (trial == nullptr) {
      send_error(ErrorCode::no_trial, "no such trial (see trials)");
      return;
    }
  } else {
    trial = trials_.latest();
    if (trial == nullptr) {
      send_error(ErrorCode::no_trial, "no trial yet");
      return;
    }
  }
  ReplyLine reply(out_);
  append(reply, "ok trial=%u", trial->number);
  trial_pairs(reply, *trial);
  send(reply);
}

void Console::trial_pairs(Reply& reply, const KeptTrial& trial) {
  append(reply, " path=%s duration_ms=%u count_l=%i count_r=%i", drive::path_name(trial.path),
         trial.duration_ms, trial.count_l, trial.count_r);
  pose_pairs(reply, trial.end);
}

void Console::cmd_trials(Handler handler) {
  if (handler == Handler::trials_clear) {
    trials_.clear();
    send_line("ok trials=%u", 0u);  // the spec of `trials`'s last line
    return;
  }
  start_listing(Listing::trials);
}

}  // namespace odocal::console
