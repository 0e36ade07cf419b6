#include "model_in_force.hpp"

#include <ostream>

#include <fmt/format.h>

namespace odocal::host::session {

drive::model::Parameters<double> parameters_of(const Factors& f, double wheel_diameter_mm) {
  return drive::model::Parameters<double>{
      wheel_diameter_mm, f.wheelbase_mm, f.wheelbase_arc_mm, f.c_l, f.c_r, f.f_lat, f.f_lon};
}

drive::model::Geometry<double> geometry_in_force(const Factors& f, double wheel_diameter_mm) {
  return drive::model::geometry_in_force(parameters_of(f, wheel_diameter_mm));
}

FitGeometry fit_geometry_of(const drive::model::Geometry<double>& g) {
  FitGeometry f;
  f.wheel_diameter_left_mm = g.left_diameter;
  f.wheel_diameter_right_mm = g.right_diameter;
  f.wheelbase_mm = g.wheelbase;
  if (g.wheelbase_arc > 0.0 && g.wheelbase_arc != g.wheelbase) {
    f.model = FitModelKind::arc_wheelbase;
    f.second_wheelbase_mm = g.wheelbase_arc;
  }
  return f;
}

Factors factors_for_fit(const drive::model::Geometry<double>& fitted, double wheel_diameter_mm) {
  const drive::model::Parameters<double> p =
      drive::model::parameters_for(fitted, wheel_diameter_mm);
  Factors f;
  f.c_l = p.c_l;
  f.c_r = p.c_r;
  f.wheelbase_mm = p.wheelbase;
  f.wheelbase_arc_mm = p.wheelbase_arc;
  f.f_lat = p.f_lat;
  f.f_lon = p.f_lon;
  return f;
}

bool apply_fit(Context& c, const Factors& next, std::ostream& text) {
  const Factors before = c.factors();
  std::string line = fmt::format("fit apply {:.6f} {:.6f} {:.4f} {} {}", next.c_l, next.c_r,
                                 next.wheelbase_mm, c.date(), c.runs.size());
  if (next.wheelbase_arc_mm != 0.0) {
    line += fmt::format(" arc {:.4f}", next.wheelbase_arc_mm);  // the arc-wheelbase model
  }
  static_cast<void>(c.robot.expect_ok(line));
  if (before.f_lat == next.f_lat && before.f_lon == next.f_lon) {
    return false;
  }
  c.set(ParamId::f_lat, next.f_lat);
  c.set(ParamId::f_lon, next.f_lon);
  text << fmt::format(
      "f_lat, f_lon reset to 1 (were {:.6f}, {:.6f}): the fitted geometry replaces them.\n",
      before.f_lat, before.f_lon);
  return true;
}

std::string first_implausible(std::span<const PlausibleCheck> checks) {
  for (const PlausibleCheck& check : checks) {
    if (!(check.value >= check.range.lo && check.value <= check.range.hi)) {
      return fmt::format(
          "{} = {:.6g} is outside the plausible range {:.6g} .. {:.6g} for a real robot "
          "(docs/calibration.md)",
          check.range.name, check.value, check.range.lo, check.range.hi);
    }
  }
  return std::string();
}

std::string implausible_factors(const Factors& next, double wheelbase_at_start_mm) {
  using namespace plausible;
  const double b_lo = wheelbase_share[0] * wheelbase_at_start_mm;
  const double b_hi = wheelbase_share[1] * wheelbase_at_start_mm;
  const PlausibleCheck checks[] = {
      {{"c_l", wheel_ratio[0], wheel_ratio[1]}, next.c_l},
      {{"c_r", wheel_ratio[0], wheel_ratio[1]}, next.c_r},
      {{"wheelbase_mm", b_lo, b_hi}, next.wheelbase_mm},
      // 0: one wheelbase, nothing to check.
      {{"wheelbase_arc_mm", b_lo, b_hi},
       next.wheelbase_arc_mm == 0.0 ? next.wheelbase_mm : next.wheelbase_arc_mm},
      {{"f_lat", maddahi[0], maddahi[1]}, next.f_lat},
      {{"f_lon", maddahi[0], maddahi[1]}, next.f_lon},
  };
  return first_implausible(checks);
}

}  // namespace odocal::host::session
