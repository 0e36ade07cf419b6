#pragma once
/// @file
/// UMBmark (Borenstein & Feng, UM-MEAM-94-22, section 6): from the return position errors of the
/// bidirectional square, the wheel-diameter ratio E_d, the wheelbase error E_b and the factors.
/// Hardware-free, no heap: runs on the MCU console as well as in the host program. Generic in the
/// scalar: the host programs solve in double (the aliases below), the robot's console in float
/// (`*Of<float>`), so the robot image links no double arithmetic.

#include <cstddef>
#include <cstdint>

namespace odocal::calib {

/// Return position error of one run, mm: measured (absolute) minus odometry (perceived), in the
/// start frame (x along the initial heading, y to the left).
template <typename Real>
struct ReturnErrorOf {
  Real x_mm = 0;
  Real y_mm = 0;
};
using ReturnError = ReturnErrorOf<double>;

/// Most runs per direction the solver accepts (the paper uses 5).
inline constexpr std::size_t umbmark_max_runs = 64;

/// What the solver needs.
template <typename Real>
struct UmbmarkInputOf {
  const ReturnErrorOf<Real>* cw = nullptr;  ///< clockwise runs
  std::size_t cw_count = 0;
  const ReturnErrorOf<Real>* ccw = nullptr;  ///< counter-clockwise runs
  std::size_t ccw_count = 0;
  Real side_mm = 4000;    ///< side L of the square
  Real wheelbase_mm = 0;  ///< wheelbase b the robot used during the runs
  bool exact = false;     ///< solve the square geometry without small angles
};
using UmbmarkInput = UmbmarkInputOf<double>;

/// Everything `odocal umbmark --json` prints (same names).
template <typename Real>
struct UmbmarkResultOf {
  Real x_cg_cw = 0, y_cg_cw = 0, x_cg_ccw = 0, y_cg_ccw = 0;  ///< mm
  Real r_cg_cw = 0, r_cg_ccw = 0;                             ///< mm
  Real e_max_syst_mm = 0;
  Real alpha_deg = 0;  ///< > 0: each nominal 90° turn under-rotates (never −0)
  Real beta_deg = 0;   ///< > 0: a straight leg curves to the left (never −0)
  /// Curvature radius of a leg, mm (> 0: curves left). +infinity when β == 0 (straight legs);
  /// `odocal` prints it as JSON null and "inf" in text.
  Real radius_mm = 0;
  Real e_d = 1;  ///< D_R / D_L
  Real e_b = 1;  ///< b_actual / b_nominal
  Real c_l = 1, c_r = 1;
  Real wheelbase_new_mm = 0;
  Real sem_mm = 0;                       ///< standard error of the mean of the return errors
  bool second_pass_recommended = false;  ///< E_max,syst >= 3·SEM
  // Added beyond the JSON contract keys (reported under `provenance` / extra keys):
  Real sigma_mm = 0;            ///< pooled radial scatter of the runs about their own centre, mm
  bool exact = false;           ///< true when E_d, E_b, α, β come from the exact square solve
  std::uint8_t iterations = 0;  ///< Gauss-Newton iterations used by the exact solve (0: approx)
};
using UmbmarkResult = UmbmarkResultOf<double>;

/// Why a solve was refused. Nothing is written to the result unless `ok`.
enum class UmbmarkStatus : std::uint8_t {
  ok,
  too_few_runs,     ///< fewer than 2 runs in a direction, or more than umbmark_max_runs
  bad_side,         ///< side not finite or not > 0
  bad_wheelbase,    ///< wheelbase not finite or not > 0
  non_finite,       ///< a NaN or Inf in the errors
  error_too_large,  ///< an error larger than the path (4·L): not a return error
  degenerate,       ///< the geometry has no solution (e.g. |β| so large that R < b/2)
};

/// A short lower-case message for a status ("too few runs", ...).
[[nodiscard]] const char* to_string(UmbmarkStatus status);

/// Solves UMBmark. Pure function; ISR-unsafe only in that it may take ~10 µs. Instantiated for
/// float and double; the exact solve stops at the scalar's rounding level.
template <typename Real>
[[nodiscard]] UmbmarkStatus solve_umbmark(const UmbmarkInputOf<Real>& input,
                                          UmbmarkResultOf<Real>& result);

/// Calibration factors in the form the firmware stores them.
template <typename Real>
struct WheelFactorsOf {
  Real c_l = 1;
  Real c_r = 1;
  Real wheelbase_mm = 0;
};
using WheelFactors = WheelFactorsOf<double>;

/// Composes a result measured on a robot that already used `current` with those factors:
/// c_L' = c_L·c_L,result, c_R' = c_R·c_R,result, b' = b_result (already E_b times the b used),
/// then renormalises so that (c_L' + c_R')/2 = 1 keeps the average diameter. A second pass
/// refines the first; it does not reset it.
template <typename Real>
[[nodiscard]] WheelFactorsOf<Real> compose(const WheelFactorsOf<Real>& current,
                                           const UmbmarkResultOf<Real>& result);

/// Where a robot with the given real errors ends one bidirectional-square run, relative to where
/// its odometry believes it is (the start). The model: odometry drives each leg until the mean
/// wheel travel it sees is `side_mm` and each corner until it sees a 90° turn in place (4 legs,
/// 4 turns); the real wheels have D_R/D_L = `e_d` (mean diameter unchanged) and the real
/// wheelbase is `e_b`·`wheelbase_mm`. Every leg and turn is integrated as an exact arc, so this is
/// the geometry without small-angle approximations that `exact` solves. Used by the exact solve,
/// and offered to tests and simulators.
/// @param clockwise true for the cw square (first corner turns right).
/// @return the return error (measured minus perceived), mm, start frame.
template <typename Real>
[[nodiscard]] ReturnErrorOf<Real> square_return_error(Real side_mm, Real wheelbase_mm, Real e_d,
                                                      Real e_b, bool clockwise);

extern template UmbmarkStatus solve_umbmark(const UmbmarkInputOf<float>&, UmbmarkResultOf<float>&);
extern template UmbmarkStatus solve_umbmark(const UmbmarkInputOf<double>&,
                                            UmbmarkResultOf<double>&);
extern template WheelFactorsOf<float> compose(const WheelFactorsOf<float>&,
                                              const UmbmarkResultOf<float>&);
extern template WheelFactorsOf<double> compose(const WheelFactorsOf<double>&,
                                               const UmbmarkResultOf<double>&);
extern template ReturnErrorOf<float> square_return_error(float, float, float, float, bool);
extern template ReturnErrorOf<double> square_return_error(double, double, double, double, bool);

}  // namespace odocal::calib
