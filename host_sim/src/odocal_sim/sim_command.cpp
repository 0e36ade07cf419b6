// odocal-sim: the simulator's own console command (`measure`) and the robot file's firmware
// defaults.

#include <numbers>

#include "odocal/console/text.hpp"
#include "sim_app.hpp"

namespace odocal::sim_app {

bool robot_defaults(const host::RobotSpec& spec, params::ParamSet& set, std::string& error) {
  set = params::default_params();
  drive::DriveConfig told = params::to_drive_config(set);
  told.wheel_diameter_mm = spec.nominal.wheel_diameter_mm;
  told.wheelbase_mm = spec.nominal.wheelbase_mm;
  told.counts_per_rev = spec.nominal.counts_per_rev;
  params::from_drive_config(told, set);
  if (!params::all_in_range(set) || !drive::valid(told)) {
    error = "wheel_diameter_mm, wheelbase_mm or counts_per_rev outside the firmware's ranges";
    return false;
  }
  return true;
}

void SimCommand::handle(void* context, const console::Token* words, std::size_t count,
                        console::Reply& reply) {
  auto& self = *static_cast<SimCommand*>(context);
  if (count == 1u) {
    ++self.questions_;
    self.measure(reply);
  } else if (words[1].is("cables")) {
    self.cables(words, count, reply);
  } else {
    reply.text("err wrong_arity usage: ").text(usage);
  }
}

void SimCommand::follow_resets() {
  if (!laid_) {
    return;
  }
  const std::uint32_t resets = robot_.loop().status().pose_resets;
  if (resets != resets_seen_) {
    resets_seen_ = resets;
    lay();
  }
}

/// `measure` (DESIGN "Trials, logs and the simulated tape measure"): the true pose of the robot
/// in the odometry frame, plus the robot file's measurement noise.
void SimCommand::measure(console::Reply& reply) {
  // One reading per stop: asked again where the robot has not moved (in the same frame), the tape
  // reads the same, as a note taken once (a host that asks twice to guard against line noise
  // gets two equal answers).
  const sim::WorldPose truth = robot_.plant().pose();
  const std::uint32_t resets = robot_.loop().status().pose_resets;
  if (!measured_ || truth.x_m != measured_truth_.x_m || truth.y_m != measured_truth_.y_m ||
      truth.theta_rad != measured_truth_.theta_rad || resets != measured_resets_) {
    measured_pose_ = robot_.measure_in_odometry_frame();
    measured_truth_ = truth;
    measured_resets_ = resets;
    measured_ = true;
  }
  const sim::WorldPose pose = measured_pose_;
  reply.text("ok")
      .pair("x_mm", pose.x_m * 1000.0, 3)
      .pair("y_mm", pose.y_m * 1000.0, 3)
      .pair("theta_deg", pose.theta_rad * 180.0 / std::numbers::pi, 3);
}

/// `measure cables off`: a smooth floor. `measure cables FIRST SPACING COUNT WHEEL [HEIGHT]`:
/// COUNT cables of HEIGHT mm (default: the robot file's bump_height_mm, else 10 mm) under one
/// wheel only, the first FIRST mm of floor from the start of each run, then every SPACING mm
/// (sim::Plant::lay_cables). A refused line changes nothing.
void SimCommand::cables(const console::Token* words, std::size_t count, console::Reply& reply) {
  if (count == 3u && words[2].is("off")) {
    laid_ = false;
    robot_.plant().set_bumps(0.0, 0.0);
    reply.text("ok cables=0");
    return;
  }
  if (count != 6u && count != 7u) {
    reply.text("err wrong_arity usage: ").text(usage);
    return;
  }
  float first_mm = 0.0f;
  float spacing_mm = 0.0f;
  float height_mm = static_cast<float>(default_cable_height_m_ * 1000.0);
  std::uint32_t cables = 0u;
  const bool right = words[5].is("right");
  if (!console::parse_number(words[2], first_mm) || !(first_mm >= 0.0f) || first_mm > 100000.0f ||
      !console::parse_number(words[3], spacing_mm) || !(spacing_mm > 0.0f) ||
      spacing_mm > 100000.0f || !console::parse_unsigned(words[4], cables) || cables == 0u ||
      cables > 1000u || (!right && !words[5].is("left")) ||
      (count == 7u && !console::parse_number(words[6], height_mm))) {
    reply.text("err bad_argument usage: ").text(usage);
    return;
  }
  const sim::RobotModel& truth = robot_.spec().truth;
  const double radius_mm = 500.0 * (right ? truth.right_diameter_m : truth.left_diameter_m);
  if (!(height_mm > 0.0f) || !(height_mm < radius_mm)) {
    reply.text("err bad_argument cable height must be above 0 and below the wheel radius");
    return;
  }
  laid_ = true;
  right_ = right;
  height_m_ = static_cast<double>(height_mm) * 1e-3;
  first_m_ = static_cast<double>(first_mm) * 1e-3;
  spacing_m_ = static_cast<double>(spacing_mm) * 1e-3;
  count_ = cables;
  resets_seen_ = robot_.loop().status().pose_resets;
  lay();
  reply.text("ok")
      .pair_u("cables", count_)
      .pair("height_mm", height_mm, 3)
      .pair("first_mm", first_mm, 3)
      .pair("spacing_mm", spacing_mm, 3)
      .pair_s("wheel", right_ ? "right" : "left");
}

}  // namespace odocal::sim_app
