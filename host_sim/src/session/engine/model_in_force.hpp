#pragma once
// Internal to the session: the one model in force on the robot (drive::model), the one table of
// plausible results, and the one rule that turns each procedure's result into new factors.

#include <span>
#include <string>

#include "odocal/drive/robot_model.hpp"
#include "odocal/host/bridge_console.hpp"
#include "session_internal.hpp"

namespace odocal::host::session {

/// The firmware's parameters (the factors in force and the nominal diameter, mm) as the model's.
drive::model::Parameters<double> parameters_of(const Factors& f, double wheel_diameter_mm);
/// The geometry the factors put in force (D_L, D_R, b, b_arc; mm): what the robot's odometry
/// and drive use (drive::model::geometry_in_force).
drive::model::Geometry<double> geometry_in_force(const Factors& f, double wheel_diameter_mm);

/// The same geometry as the fit describes one (the arc-wheelbase model when it has an arc
/// wheelbase of its own).
FitGeometry fit_geometry_of(const drive::model::Geometry<double>& g);

/// diff_drive_controller's geometry parameters (metres; the multipliers as it multiplies them).
struct RosGeometry {
  double wheel_separation_m = 0.0;
  double wheel_radius_m = 0.0;
  double separation_multiplier = 1.0;
  double left_multiplier = 1.0;
  double right_multiplier = 1.0;
};
/// For a robot running ROSArduinoBridge (raw counts both ways): the nominal geometry the owner
/// gave, the factors in force `f` (on the host) as the multipliers.
RosGeometry ros_geometry_for_bridge(const Factors& f, const BridgeNominal& nominal);
/// For an odocal robot with the factors `f` in force: its `e` counts are each wheel's counts
/// times its diameter in force over the nominal one, and its `m` speeds are read about the
/// wheelbase in force; so the nominal wheel, the wheelbase in force, multipliers 1 (docs/ros.md).
RosGeometry ros_geometry_for_odocal(const Factors& f, double wheel_diameter_mm);

/// What a fit result becomes on the robot: the fitted effective geometry with F_lat = F_lon = 1
/// (a fit sees the whole geometry: it replaces c_l, c_r, the wheelbases and the Maddahi factors).
Factors factors_for_fit(const drive::model::Geometry<double>& fitted, double wheel_diameter_mm);

/// Puts a fit's factors in force in one step (`fit apply`, provenance `fit`, the session's date
/// and runs; `arc` when the fit chose an arc wheelbase), then F_lat = F_lon = 1 if they were not
/// (the fitted geometry replaces them). Says what it did on `text`; returns whether it reset F.
bool apply_fit(Context& c, const Factors& next, std::ostream& text);

/// One figure's plausible closed range (docs/calibration.md, "Plausible results").
struct PlausibleRange {
  const char* name;
  double lo;
  double hi;
};

/// The plausible ranges, one table for every procedure: a wheel factor or ratio (c_l, c_r,
/// E_d) within 5 % of 1, a wheelbase (turns in place or arcs; E_b) within 10 % of the one in force
/// at the start, a Maddahi factor within 10 % of 1.
namespace plausible {
inline constexpr double wheel_ratio[2] = {0.95, 1.05};
inline constexpr double wheelbase_share[2] = {0.90, 1.10};
inline constexpr double maddahi[2] = {0.90, 1.10};
}  // namespace plausible

/// A value checked against its range.
struct PlausibleCheck {
  PlausibleRange range;
  double value;
};

/// The checks of a set of factors about to be applied: c_l, c_r, wheelbase_mm (and
/// wheelbase_arc_mm when it is not 0) against `wheelbase_at_start_mm`, f_lat, f_lon.
std::string implausible_factors(const Factors& next, double wheelbase_at_start_mm);

/// Empty when every check holds; else "NAME = VALUE is outside the plausible range LO .. HI for
/// a real robot (docs/calibration.md)" for the first that does not.
std::string first_implausible(std::span<const PlausibleCheck> checks);

}  // namespace odocal::host::session
