#pragma once
/// @file
/// Maddahi & Zareinia corrective factors (IEEE Access 8, 2020): the lateral factor F_lat (eq. 4)
/// and the longitudinal factor F_lon (eq. 5) from straight-line trials, and the same factors from
/// estimated wheel velocities through the inverse kinematics (eq. 7). Hardware-free, no heap.
/// eq. 4-5 are generic in the scalar: double on the host, float in the robot's console.

#include <cstddef>
#include <cstdint>

namespace odocal::calib {

/// Where one straight trial stopped, mm, in the start frame: x along the commanded line,
/// y to the left.
template <typename Real>
struct StopPointOf {
  Real x_mm = 0;
  Real y_mm = 0;
};
using StopPoint = StopPointOf<double>;

/// Most trials `solve_lateral` accepts.
inline constexpr std::size_t lateral_max_trials = 1024;

/// What eq. 4 and eq. 5 need.
template <typename Real>
struct LateralInputOf {
  const StopPointOf<Real>* trials = nullptr;
  std::size_t trial_count = 0;
  Real length_mm = 0;          ///< commanded length L of each straight trial, > 0
  Real wheelbase_mm = 0;       ///< wheelbase l, > 0
  Real left_diameter_mm = 0;   ///< nominal D_L, > 0
  Real right_diameter_mm = 0;  ///< nominal D_R, > 0
  /// Left-wheel rotation over one trial, rad; 0 means the nominal 2L/D_L.
  Real theta_l_rad = 0;
};
using LateralInput = LateralInputOf<double>;

/// The two corrective factors (dimensionless; 1 = no correction).
template <typename Real>
struct LateralResultOf {
  Real f_lat = 1;        ///< scales the left wheel (eq. 7)
  Real f_lon = 1;        ///< scales both wheels (eq. 7)
  Real theta_l_rad = 0;  ///< the θ_L used in eq. 4
};
using LateralResult = LateralResultOf<double>;

/// Composes a correction measured on a robot that already used `in_force`: each factor scales
/// what the wheels already do (eq. 7), so the factors multiply, and a second calibration refines
/// the first rather than resetting it. θ_L is the correction's. The one composition of the
/// lateral factors: the robot's `lateral apply` and the host's session call it.
template <typename Real>
[[nodiscard]] constexpr LateralResultOf<Real> compose(const LateralResultOf<Real>& in_force,
                                                      const LateralResultOf<Real>& correction) {
  return {in_force.f_lat * correction.f_lat, in_force.f_lon * correction.f_lon,
          correction.theta_l_rad};
}

/// Why a lateral solve was refused. Nothing is written to the result unless `ok`.
enum class LateralStatus : std::uint8_t {
  ok,
  too_few_trials,   ///< fewer than 2 trials, or more than lateral_max_trials
  bad_geometry,     ///< a length, wheelbase, diameter or θ_L not finite or not > 0
  non_finite,       ///< a NaN or Inf in the trials or the wheel rates
  error_too_large,  ///< a stop point farther than L from the commanded end, or x <= 0
  degenerate,       ///< no finite factor exists (mean stop point at the start, v = ±lω/2, ...)
};

/// A short lower-case message for a status.
[[nodiscard]] const char* to_string(LateralStatus status);

/// F_lat by eq. 4 (read as DESIGN says: D_L/D_R, chord angle atan(y_i/x_i)) and F_lon by eq. 5
/// (shortfall x_e = L − x, so F_lon = L / |mean stop point|). A drift to the left (y > 0) gives
/// F_lat > 1; stopping short gives F_lon > 1.
template <typename Real>
[[nodiscard]] LateralStatus solve_lateral(const LateralInputOf<Real>& input,
                                          LateralResultOf<Real>& result);
extern template LateralStatus solve_lateral(const LateralInputOf<float>&, LateralResultOf<float>&);
extern template LateralStatus solve_lateral(const LateralInputOf<double>&,
                                            LateralResultOf<double>&);

/// Body velocity and wheel velocities of one trial (Maddahi eq. 6-7 variables).
struct WheelRateSample {
  double xdot_mps = 0.0;        ///< ẋ_b, start frame
  double ydot_mps = 0.0;        ///< ẏ_b, start frame
  double thetadot_radps = 0.0;  ///< θ̇
  double omega_l_radps = 0.0;   ///< θ̇_L (estimated, e.g. by the bootstrap)
  double omega_r_radps = 0.0;   ///< θ̇_R
};

/// Nominal geometry for eq. 7, mm.
struct WheelGeometry {
  double wheelbase_mm = 0.0;
  double left_diameter_mm = 0.0;
  double right_diameter_mm = 0.0;
};

/// F_lat and F_lon that make eq. 7 (left row read with −F_lat·l/D_L, and the wheelbase in force
/// scaled with the mean effective diameter as the drive does: drive::model::geometry_in_force)
/// hold for the given wheel velocities: the heading follows from eq. 3 (tan θ = ẏ/ẋ),
/// v = cos θ ẋ + sin θ ẏ; with k = 2lω/(D_L + D_R), F_lat = D_L(θ̇_L + k)/(D_R(θ̇_R − k)) and
/// F_lon = (θ̇_R·D_R − q·l·ω)/(2v), q = (D_L/F_lat + D_R)/(D_L + D_R). On a straight motion
/// (ω = 0) these are the paper's F_lon = θ̇_R·D_R/(2v), F_lat = θ̇_L·D_L/(F_lon·2v).
/// @return `degenerate` when v is ~0 (a turn in place does not show F_lon), θ̇_R − k is ~0, or
/// a factor is not > 0.
[[nodiscard]] LateralStatus factors_from_wheel_rates(const WheelRateSample& sample,
                                                     const WheelGeometry& geometry,
                                                     LateralResult& result);

}  // namespace odocal::calib
