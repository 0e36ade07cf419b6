#include "odocal/sim/robot_model.hpp"

#include <cmath>

namespace odocal::sim {
namespace {

bool positive(double x) {
  return std::isfinite(x) && x > 0.0;
}
bool non_negative(double x) {
  return std::isfinite(x) && x >= 0.0;
}

bool motor_ok(const MotorModel& m) {
  return positive(m.supply_v) && positive(m.resistance_ohm) && positive(m.k_v_per_radps) &&
         positive(m.inertia_kgm2) && non_negative(m.viscous_nm_per_radps) &&
         non_negative(m.coulomb_nm);
}

}  // namespace

ModelError check(const RobotModel& model) {
  if (!positive(model.left_diameter_m)) {
    return ModelError::left_diameter;
  }
  if (!positive(model.right_diameter_m)) {
    return ModelError::right_diameter;
  }
  const double larger = std::fmax(model.left_diameter_m, model.right_diameter_m);
  if (!positive(model.wheelbase_m) || model.wheelbase_m <= larger) {
    return ModelError::wheelbase;
  }
  if (model.wheelbase_arc_m != 0.0 &&
      (!positive(model.wheelbase_arc_m) || model.wheelbase_arc_m <= larger)) {
    return ModelError::wheelbase_arc;
  }
  if (model.counts_per_rev == 0u || model.counts_per_rev % 4u != 0u) {
    return ModelError::counts_per_rev;
  }
  if (!non_negative(model.slip_sigma) || model.slip_sigma >= 0.5 ||
      !positive(model.slip_length_m)) {
    return ModelError::slip;
  }
  const double smaller_radius = 0.5 * std::fmin(model.left_diameter_m, model.right_diameter_m);
  if (!non_negative(model.bump_height_m) || model.bump_height_m >= smaller_radius ||
      !positive(model.bump_spacing_m) || !non_negative(model.bump_spacing_jitter) ||
      model.bump_spacing_jitter >= 1.0 || !non_negative(model.bump_yaw_sigma_rad)) {
    return ModelError::bump;
  }
  if (!non_negative(model.measure_sigma_m) || !non_negative(model.measure_heading_sigma_rad)) {
    return ModelError::measure;
  }
  if (!motor_ok(model.left_motor) || !motor_ok(model.right_motor)) {
    return ModelError::motor;
  }
  if (model.physics_step_ns == 0u || model.physics_step_ns > 10000000u) {
    return ModelError::physics_step;
  }
  return ModelError::none;
}

const char* to_string(ModelError error) {
  switch (error) {
    case ModelError::none:
      return "none";
    case ModelError::left_diameter:
      return "left diameter";
    case ModelError::right_diameter:
      return "right diameter";
    case ModelError::wheelbase:
      return "wheelbase";
    case ModelError::wheelbase_arc:
      return "arc wheelbase";
    case ModelError::counts_per_rev:
      return "counts per revolution";
    case ModelError::slip:
      return "slip";
    case ModelError::bump:
      return "bump";
    case ModelError::measure:
      return "measurement noise";
    case ModelError::motor:
      return "motor";
    case ModelError::physics_step:
      return "physics step";
  }
  return "unknown";
}

}  // namespace odocal::sim
