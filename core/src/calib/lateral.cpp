#include "odocal/calib/lateral.hpp"

#include <cmath>

#include "norm.hpp"
#include "odocal/math/bounded_trig.hpp"
#include "odocal/name_list.hpp"

namespace odocal::calib {
namespace {

template <typename Real>
bool positive(Real v) {
  return std::isfinite(v) && v > 0;
}

// The chord angle: the robot's float solve without newlib's atanf (math::arctan, within 3e-7
// rad); the host's double solve as before.
float chord_angle(float slope) {
  return math::arctan(slope);
}
double chord_angle(double slope) {
  return std::atan(slope);
}

}  // namespace

const char* to_string(LateralStatus status) {
  // In LateralStatus' order (name_list.hpp: one string instead of a table of pointers).
  static constexpr char messages[] =
      "ok\0need 2 to 1024 trials\0sizes and theta_L must be > 0\0a value is not finite\0"
      "a stop point lies off the line\0no positive factor fits";
  static_assert(nul_count(messages) == static_cast<std::size_t>(LateralStatus::degenerate) + 1u,
                "one message per LateralStatus, in its order");
  const auto n = static_cast<unsigned>(status);
  return n <= static_cast<unsigned>(LateralStatus::degenerate) ? name_at(messages, n)
                                                               : "unknown status";
}

template <typename Real>
LateralStatus solve_lateral(const LateralInputOf<Real>& input, LateralResultOf<Real>& result) {
  if (input.trials == nullptr || input.trial_count < 2 || input.trial_count > lateral_max_trials) {
    return LateralStatus::too_few_trials;
  }
  const Real length = input.length_mm;
  const Real l = input.wheelbase_mm;
  const Real d_l = input.left_diameter_mm;
  const Real d_r = input.right_diameter_mm;
  if (!positive(length) || !positive(l) || !positive(d_l) || !positive(d_r) ||
      !std::isfinite(input.theta_l_rad) || input.theta_l_rad < 0) {
    return LateralStatus::bad_geometry;
  }
  // θ_L: left-wheel rotation over the trial; nominally the wheel rolls L with radius D_L/2.
  const Real theta_l = input.theta_l_rad > 0 ? input.theta_l_rad : 2 * length / d_l;

  Real chord_angle_sum = 0;
  Real x_sum = 0;
  Real y_sum = 0;
  for (std::size_t i = 0; i < input.trial_count; ++i) {
    const StopPointOf<Real>& p = input.trials[i];
    if (!std::isfinite(p.x_mm) || !std::isfinite(p.y_mm)) {
      return LateralStatus::non_finite;
    }
    if (p.x_mm <= 0 || norm_of(length - p.x_mm, p.y_mm) > length) {
      return LateralStatus::error_too_large;
    }
    chord_angle_sum += chord_angle(p.y_mm / p.x_mm);  // chord angle of trial i (eq. 4)
    x_sum += p.x_mm;
    y_sum += p.y_mm;
  }
  const Real n = static_cast<Real>(input.trial_count);
  // Maddahi eq. 4: a chord leaning by φ means the heading turned 2φ; 4lφ/(D·θ_L) is the share of
  // extra left-wheel rotation that cancels it.
  const Real f_lat = d_l / d_r + 4 * l / (n * d_r * theta_l) * chord_angle_sum;
  // Maddahi eq. 5 with x_e = L − x: the denominator is the distance to the mean stop point.
  const Real reach = norm_of(x_sum / n, y_sum / n);
  if (!(reach > 0)) {
    return LateralStatus::degenerate;
  }
  const Real f_lon = length / reach;
  if (!positive(f_lat) || !positive(f_lon)) {
    return LateralStatus::degenerate;
  }
  result = LateralResultOf<Real>{f_lat, f_lon, theta_l};
  return LateralStatus::ok;
}

template LateralStatus solve_lateral(const LateralInputOf<float>&, LateralResultOf<float>&);
template LateralStatus solve_lateral(const LateralInputOf<double>&, LateralResultOf<double>&);

LateralStatus factors_from_wheel_rates(const WheelRateSample& sample, const WheelGeometry& geometry,
                                       LateralResult& result) {
  if (!std::isfinite(sample.xdot_mps) || !std::isfinite(sample.ydot_mps) ||
      !std::isfinite(sample.thetadot_radps) || !std::isfinite(sample.omega_l_radps) ||
      !std::isfinite(sample.omega_r_radps)) {
    return LateralStatus::non_finite;
  }
  if (!positive(geometry.wheelbase_mm) || !positive(geometry.left_diameter_mm) ||
      !positive(geometry.right_diameter_mm)) {
    return LateralStatus::bad_geometry;
  }
  const double l = geometry.wheelbase_mm * 1e-3;  // m, like the velocities
  const double d_l = geometry.left_diameter_mm * 1e-3;
  const double d_r = geometry.right_diameter_mm * 1e-3;
  // Maddahi eq. 3 (no side slip): the heading is the direction of travel, so
  // v = cos θ ẋ + sin θ ẏ = |(ẋ, ẏ)| taken with the sign of ẋ.
  const double speed = std::hypot(sample.xdot_mps, sample.ydot_mps);
  const double v = sample.xdot_mps < 0.0 ? -speed : speed;
  const double w = sample.thetadot_radps;
  // Maddahi eq. 7 (left row read with −F_lat·l/D_L) with the one model's wheelbase in force
  // (drive::model::geometry_in_force: the wheelbase scales with the mean effective diameter,
  // b_eff = s·l, F_lon·s = q = (D_L/F_lat + D_R)/Σ, Σ = D_L + D_R):
  //   θ̇_R·D_R = 2·F_lon·v + q·l·ω,   θ̇_L·D_L = F_lat·(2·F_lon·v − q·l·ω).
  // Eliminating F_lon (F_lat·q = (D_L + F_lat·D_R)/Σ), with k = 2lω/Σ:
  //   F_lat = D_L·(θ̇_L + k) / (D_R·(θ̇_R − k)),   F_lon = (θ̇_R·D_R − q·l·ω) / (2v).
  // F_lon needs forward motion: a turn in place keeps its angle whatever F_lon is.
  const double k = 2.0 * l * w / (d_l + d_r);
  const double scale = std::fabs(2.0 * v) + std::fabs(l * w);
  const double right = sample.omega_r_radps - k;
  if (!(scale > 0.0) || std::fabs(2.0 * v) <= 1e-9 * scale ||
      std::fabs(right) * d_r <= 1e-9 * scale) {
    return LateralStatus::degenerate;
  }
  const double f_lat = d_l * (sample.omega_l_radps + k) / (d_r * right);
  if (!positive(f_lat)) {
    return LateralStatus::degenerate;
  }
  const double q = (d_l / f_lat + d_r) / (d_l + d_r);
  const double f_lon = (sample.omega_r_radps * d_r - q * l * w) / (2.0 * v);
  if (!positive(f_lon)) {
    return LateralStatus::degenerate;
  }
  result = LateralResult{f_lat, f_lon, 0.0};
  return LateralStatus::ok;
}

}  // namespace odocal::calib
