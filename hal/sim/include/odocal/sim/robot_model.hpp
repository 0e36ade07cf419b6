#pragma once
/// @file
/// Parameters of the simulated robot: the *true* geometry (which differs from what the firmware is
/// told), the DC motors, the floor and the absolute position measurement.

#include <cstdint>

namespace odocal::sim {

/// One wheel's DC motor and gearbox, referred to the wheel shaft.
///
/// Model (electrical time constant neglected, it is far below the physics step):
///   i = (V − k·ω)/R,  J·dω/dt = k·i − c·ω − τ_c·sign(ω)
/// with V = duty·supply_v·(+1 forward / −1 reverse). The defaults give a no-load speed of about
/// 30 rad/s at full duty, matching the firmware's nominal feed-forward kff = 0.033 duty per rad/s,
/// and a mechanical time constant of about 0.1 s.
struct MotorModel {
  double supply_v = 6.0;         ///< H-bridge supply, V
  double resistance_ohm = 4.0;   ///< winding resistance, Ω
  double k_v_per_radps = 0.19;   ///< back-EMF constant = torque constant (N·m/A), at the wheel
  double inertia_kgm2 = 9.0e-4;  ///< rotor (through the gearbox) + share of the robot's mass
  double viscous_nm_per_radps = 2.0e-4;  ///< viscous friction, N·m per rad/s
  double coulomb_nm = 5.0e-3;            ///< dry friction, N·m (also the breakaway torque)
};

/// Everything that makes the simulated robot what it is. Lengths in metres, angles in radians.
struct RobotModel {
  // The real robot (the firmware is told the nominal values separately).
  double left_diameter_m = 0.05994;   ///< true left wheel diameter D_L
  double right_diameter_m = 0.06006;  ///< true right wheel diameter D_R
  double wheelbase_m = 0.1515;        ///< true wheelbase (contact point to contact point)
  /// True arc wheelbase, 0 = none (one wheelbase): the wheelbase in force is then
  /// wheelbase_m + w·(wheelbase_arc_m − wheelbase_m), w = |φ_L + φ_R| / (|φ_L + φ_R| + |φ_R − φ_L|)
  /// of the wheels' rotation φ over each physics step (odocal fit's arc-wheelbase model).
  double wheelbase_arc_m = 0.0;
  std::uint32_t counts_per_rev = 1440u;  ///< encoder counts per wheel revolution after x4; %4 == 0

  MotorModel left_motor{};
  MotorModel right_motor{};

  // Non-systematic error sources.
  double slip_sigma = 5.0e-4;        ///< standard deviation of each wheel's slip ratio (unitless)
  double slip_length_m = 0.05;       ///< the slip ratio is redrawn after this much wheel travel
  double bump_height_m = 0.0;        ///< height of the floor bumps (cables), 0 = a smooth floor
  double bump_spacing_m = 0.2;       ///< mean floor distance each wheel sweeps between two cables
  double bump_spacing_jitter = 0.1;  ///< relative spread of that spacing (uniform ±)
  /// Zero-mean random skid of the heading at each cable a wheel meets, per 10 mm of height (on
  /// top of the yaw that follows from that wheel's lost ground travel).
  double bump_yaw_sigma_rad = 2.0e-3;

  // The "absolute" measurement at the end of a run (UMBmark's sonar calibrator: ±2 mm, ±0.4°).
  double measure_sigma_m = 0.002;              ///< per-axis position noise, standard deviation
  double measure_heading_sigma_rad = 0.00698;  ///< heading noise (0.4°), standard deviation

  // Integration.
  std::uint32_t physics_step_ns = 500000u;  ///< physics step (independent of the control rate)
};

/// What is wrong with a model, if anything (the first problem found).
enum class ModelError : std::uint8_t {
  none,
  left_diameter,  ///< not finite or not > 0
  right_diameter,
  wheelbase,       ///< not finite, or not larger than the larger wheel diameter
  wheelbase_arc,   ///< neither 0 nor finite and larger than the larger wheel diameter
  counts_per_rev,  ///< zero or not a multiple of 4
  slip,            ///< slip sigma negative or >= 0.5, or slip length not > 0
  bump,            ///< negative height, height >= the smaller wheel radius, or spacing not > 0
  measure,         ///< negative noise
  motor,           ///< a motor constant not finite or not > 0 (friction may be 0)
  physics_step,    ///< zero or longer than 10 ms
};

/// Checks a model; `ModelError::none` when it can be simulated.
[[nodiscard]] ModelError check(const RobotModel& model);

/// A short lower-case description of an error ("left diameter", ...).
[[nodiscard]] const char* to_string(ModelError error);

}  // namespace odocal::sim
