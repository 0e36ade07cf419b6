#include "odocal/calib/umbmark.hpp"

#include <cmath>
#include <initializer_list>
#include <limits>
#include <numbers>

#include "norm.hpp"
#include "odocal/drive/robot_model.hpp"
#include "odocal/math/bounded_trig.hpp"
#include "odocal/name_list.hpp"

namespace odocal::calib {
namespace {

// The solver's angles stay within a few turns. Float (the robot's console) uses the bounded
// sin/cos of the tick: newlib's full-range reduction is ~3.6 KB (float) / ~4.5 KB (double) of
// flash. The host's double solve keeps libm, so `odocal umbmark` output is unchanged.
float sin_of(float a) {
  return math::sin_cos(a).sin;
}
float cos_of(float a) {
  return math::sin_cos(a).cos;
}
double sin_of(double a) {
  return std::sin(a);
}
double cos_of(double a) {
  return std::cos(a);
}

template <typename Real>
constexpr Real pi = std::numbers::pi_v<Real>;
template <typename Real>
constexpr Real quarter_turn_rad = pi<Real> / 2;
template <typename Real>
constexpr Real rad_to_deg = 180 / pi<Real>;

/// A value with its derivatives with respect to (E_d, E_b): forward-mode differentiation, so the
/// Gauss-Newton Jacobian of the square geometry is exact and costs one model evaluation.
template <typename Real>
struct Dual {
  Real v = 0;
  Real d0 = 0;  ///< ∂/∂E_d
  Real d1 = 0;  ///< ∂/∂E_b
};

template <typename Real>
Dual<Real> operator+(Dual<Real> a, Dual<Real> b) {
  return {a.v + b.v, a.d0 + b.d0, a.d1 + b.d1};
}
template <typename Real>
Dual<Real> operator-(Dual<Real> a, Dual<Real> b) {
  return {a.v - b.v, a.d0 - b.d0, a.d1 - b.d1};
}
template <typename Real>
Dual<Real> operator*(Dual<Real> a, Dual<Real> b) {
  return {a.v * b.v, a.d0 * b.v + a.v * b.d0, a.d1 * b.v + a.v * b.d1};
}
template <typename Real>
Dual<Real> operator*(Real k, Dual<Real> a) {
  return {k * a.v, k * a.d0, k * a.d1};
}
template <typename Real>
Dual<Real> operator/(Dual<Real> a, Dual<Real> b) {
  const Real inv = 1 / b.v;
  const Real q = a.v * inv;
  return {q, (a.d0 - q * b.d0) * inv, (a.d1 - q * b.d1) * inv};
}
// g(a) with g' known: chain rule.
template <typename Real>
Dual<Real> chain(Dual<Real> a, Real value, Real slope) {
  return {value, slope * a.d0, slope * a.d1};
}
template <typename Real>
Dual<Real> sin_of(Dual<Real> a) {
  return chain(a, sin_of(a.v), cos_of(a.v));
}
template <typename Real>
Dual<Real> cos_of(Dual<Real> a) {
  return chain(a, cos_of(a.v), -sin_of(a.v));
}

// sin(u)/u and its slope, from the one model's stable form (robot_model.hpp).
template <typename Real>
Real scalar_sinc(Real u, Real& slope) {
  const drive::model::HalfTurn<Real> half = drive::model::half_turn(u);
  slope = drive::model::sinc_slope(u, half);
  return half.sinc;
}
template <typename Real>
Real sinc(Real u) {
  Real slope = 0;
  return scalar_sinc(u, slope);
}
template <typename Real>
Dual<Real> sinc(Dual<Real> a) {
  Real slope = 0;
  const Real value = scalar_sinc(a.v, slope);
  return chain(a, value, slope);
}

/// Planar pose integrated by exact arcs: model::advance (robot_model.hpp) in dual numbers.
template <typename T, typename Real>
struct ArcPose {
  T x{};
  T y{};
  T theta{};

  /// One segment with real wheel travels s_l, s_r (mm) and real wheelbase b (mm).
  void move(T s_l, T s_r, T b) {
    const T dtheta = (s_r - s_l) / b;
    const T ds = Real(0.5) * (s_l + s_r);
    const T half = Real(0.5) * dtheta;
    const T chord = ds * sinc(half);  // chord length of the arc
    const T mid = theta + half;
    x = x + chord * cos_of(mid);
    y = y + chord * sin_of(mid);
    theta = theta + dtheta;
  }
};

/// The bidirectional-square model of `square_return_error`, generic in the scalar (Real or
/// Dual<Real>) so that the exact solve gets its Jacobian from the same code.
template <typename T, typename Real>
void square_end(Real side_mm, Real wheelbase_mm, T e_d, T e_b, bool clockwise, T& x, T& y) {
  const T one{1};
  const T two{2};
  // Real wheel travel per perceived wheel travel; the mean diameter stays D_a (UMBmark eq. 6.30).
  const T k_l = two / (e_d + one);
  const T k_r = (two * e_d) / (e_d + one);
  const T b_real = wheelbase_mm * e_b;
  const T leg{side_mm};
  // Odometry sees a turn of 90° when each wheel has moved a quarter of the b-circle.
  const Real turn_travel = quarter_turn_rad<Real> * wheelbase_mm / 2;
  const T turn_l{clockwise ? turn_travel : -turn_travel};
  const T turn_r{clockwise ? -turn_travel : turn_travel};
  ArcPose<T, Real> pose;
  for (int corner = 0; corner < 4; ++corner) {
    pose.move(k_l * leg, k_r * leg, b_real);
    pose.move(k_l * turn_l, k_r * turn_r, b_real);
  }
  x = pose.x;
  y = pose.y;
}

template <typename Real>
bool finite(Real v) {
  return std::isfinite(v);
}

/// −0 as +0, so that no figure reads "-0.0" (e.g. β of error-free runs is 0/(−4L) = −0).
// Out of line: six figures pass through it.
template <typename Real>
[[gnu::noinline]] Real unsigned_zero(Real v) {
  return v == 0 ? Real(0) : v;
}

template <typename Real>
struct Centroid {
  Real x = 0;
  Real y = 0;
  Real scatter_sq = 0;  ///< Σ |e − c|²
};

template <typename Real>
Centroid<Real> centroid(const ReturnErrorOf<Real>* runs, std::size_t count) {
  Centroid<Real> c;
  for (std::size_t i = 0; i < count; ++i) {
    c.x += runs[i].x_mm;
    c.y += runs[i].y_mm;
  }
  const Real n = static_cast<Real>(count);
  c.x /= n;
  c.y /= n;
  for (std::size_t i = 0; i < count; ++i) {
    const Real dx = runs[i].x_mm - c.x;
    const Real dy = runs[i].y_mm - c.y;
    c.scatter_sq += dx * dx + dy * dy;
  }
  return c;
}

template <typename Real>
UmbmarkStatus check_runs(const ReturnErrorOf<Real>* runs, std::size_t count, Real limit_mm) {
  if (runs == nullptr || count < 2 || count > umbmark_max_runs) {
    return UmbmarkStatus::too_few_runs;
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (!finite(runs[i].x_mm) || !finite(runs[i].y_mm)) {
      return UmbmarkStatus::non_finite;
    }
    if (norm_of(runs[i].x_mm, runs[i].y_mm) > limit_mm) {
      return UmbmarkStatus::error_too_large;
    }
  }
  return UmbmarkStatus::ok;
}

/// The four modelled return-error coordinates: cw x, y, then ccw x, y.
template <typename T, typename Real>
void model_ends(const UmbmarkInputOf<Real>& input, T e_d, T e_b, T (&out)[4]) {
  square_end(input.side_mm, input.wheelbase_mm, e_d, e_b, true, out[0], out[1]);
  square_end(input.side_mm, input.wheelbase_mm, e_d, e_b, false, out[2], out[3]);
}

/// The model at (E_d, E_b) and its Jacobian columns ∂/∂E_d, ∂/∂E_b. Double (host): dual numbers,
/// exact. Float (the robot's console): central differences of the plain model, which keeps a
/// second, dual-number copy of the square model out of the robot's flash (~0.6 KB). With steps of
/// 2^-9 relative the derivative's error is ~1e-4 relative (float rounding of the ~mm-sized
/// differences; the truncation error is far below it): that only slows Gauss-Newton slightly, and
/// the point it converges to moves by (Jacobian error) x (residual), a few 1e-8 of E_d for
/// millimetre residuals — below float's own resolution of E_d.
template <typename Real>
void model_and_jacobian(const UmbmarkInputOf<Real>& input, Real e_d, Real e_b, Real (&value)[4],
                        Real (&d0)[4], Real (&d1)[4]) {
  if constexpr (sizeof(Real) == sizeof(float)) {
    model_ends(input, e_d, e_b, value);
    constexpr Real relative_step = Real(1) / 512;
    Real up[4];
    Real down[4];
    const Real d_hi = e_d + relative_step * e_d;
    const Real d_lo = e_d - relative_step * e_d;
    model_ends(input, d_hi, e_b, up);
    model_ends(input, d_lo, e_b, down);
    for (int i = 0; i < 4; ++i) {
      d0[i] = (up[i] - down[i]) / (d_hi - d_lo);  // the steps as represented, not as intended
    }
    const Real b_hi = e_b + relative_step * e_b;
    const Real b_lo = e_b - relative_step * e_b;
    model_ends(input, e_d, b_hi, up);
    model_ends(input, e_d, b_lo, down);
    for (int i = 0; i < 4; ++i) {
      d1[i] = (up[i] - down[i]) / (b_hi - b_lo);
    }
  } else {
    Dual<Real> model[4];
    model_ends(input, Dual<Real>{e_d, 1, 0}, Dual<Real>{e_b, 0, 1}, model);
    for (int i = 0; i < 4; ++i) {
      value[i] = model[i].v;
      d0[i] = model[i].d0;
      d1[i] = model[i].d1;
    }
  }
}

/// Gauss-Newton on the exact square geometry: (E_d, E_b) such that the modelled cw and ccw
/// return errors match the two centres of gravity in the least-squares sense. The 2x2 normal
/// equations are solved by Cramer's rule.
template <typename Real>
bool solve_exact(const UmbmarkInputOf<Real>& input, const Real (&observed)[4], Real& e_d, Real& e_b,
                 std::uint8_t& iterations) {
  constexpr int max_iterations = 30;
  // Relative step that ends the iteration: a few roundings of the scalar.
  constexpr bool single = sizeof(Real) == sizeof(float);
  const Real tolerance = single ? Real(5e-7) : Real(1e-13);
  // Normal matrix this close to singular (relative to its size) cannot give a meaningful step;
  // float's cancellation in det is ~1e-7 of the size.
  const Real singular = single ? Real(1e-5) : Real(1e-30);
  for (int it = 1; it <= max_iterations; ++it) {
    Real value[4];
    Real d0[4];
    Real d1[4];
    model_and_jacobian(input, e_d, e_b, value, d0, d1);
    Real n00 = 0, n01 = 0, n11 = 0, g0 = 0, g1 = 0;  // JᵀJ and Jᵀr
    for (int i = 0; i < 4; ++i) {
      const Real r = value[i] - observed[i];
      n00 += d0[i] * d0[i];
      n01 += d0[i] * d1[i];
      n11 += d1[i] * d1[i];
      g0 += d0[i] * r;
      g1 += d1[i] * r;
    }
    const Real det = n00 * n11 - n01 * n01;
    const Real size = n00 * n00 + 2 * n01 * n01 + n11 * n11;
    if (!finite(det) || std::fabs(det) <= singular * size) {
      return false;
    }
    const Real step0 = -(n11 * g0 - n01 * g1) / det;
    const Real step1 = -(n00 * g1 - n01 * g0) / det;
    e_d += step0;
    e_b += step1;
    if (!finite(e_d) || !finite(e_b) || e_d <= 0 || e_b <= 0) {
      return false;
    }
    if (std::fabs(step0) < tolerance * e_d && std::fabs(step1) < tolerance * e_b) {
      iterations = static_cast<std::uint8_t>(it);
      return true;
    }
  }
  // Noisy centres need not be reproducible exactly; GN still reaches the least-squares point,
  // where the steps stall at rounding level rather than below the tolerance.
  iterations = static_cast<std::uint8_t>(max_iterations);
  return true;
}

}  // namespace

const char* to_string(UmbmarkStatus status) {
  // In UmbmarkStatus' order (name_list.hpp: one string instead of a table of pointers).
  static constexpr char messages[] =
      "ok\0need 2 to 64 runs per direction\0side must be > 0\0wheelbase must be > 0\0"
      "a return error is not finite\0a return error exceeds the path\0degenerate: no square fits";
  static_assert(nul_count(messages) == static_cast<std::size_t>(UmbmarkStatus::degenerate) + 1u,
                "one message per UmbmarkStatus, in its order");
  const auto n = static_cast<unsigned>(status);
  return n <= static_cast<unsigned>(UmbmarkStatus::degenerate) ? name_at(messages, n)
                                                               : "unknown status";
}

template <typename Real>
ReturnErrorOf<Real> square_return_error(Real side_mm, Real wheelbase_mm, Real e_d, Real e_b,
                                        bool clockwise) {
  Real x = 0;
  Real y = 0;
  square_end(side_mm, wheelbase_mm, e_d, e_b, clockwise, x, y);
  return ReturnErrorOf<Real>{x, y};
}

template <typename Real>
UmbmarkStatus solve_umbmark(const UmbmarkInputOf<Real>& input, UmbmarkResultOf<Real>& result) {
  constexpr Real quarter = quarter_turn_rad<Real>;
  const Real side = input.side_mm;
  const Real b = input.wheelbase_mm;
  if (!finite(side) || side <= 0) {
    return UmbmarkStatus::bad_side;
  }
  if (!finite(b) || b <= 0) {
    return UmbmarkStatus::bad_wheelbase;
  }
  const Real path_mm = 4 * side;
  for (const auto status : {check_runs(input.cw, input.cw_count, path_mm),
                            check_runs(input.ccw, input.ccw_count, path_mm)}) {
    if (status != UmbmarkStatus::ok) {
      return status;
    }
  }

  UmbmarkResultOf<Real> out;
  const Centroid<Real> cw = centroid(input.cw, input.cw_count);
  const Centroid<Real> ccw = centroid(input.ccw, input.ccw_count);
  out.x_cg_cw = cw.x;
  out.y_cg_cw = cw.y;
  out.x_cg_ccw = ccw.x;
  out.y_cg_ccw = ccw.y;
  out.r_cg_cw = norm_of(cw.x, cw.y);  // UMBmark eq. 3.3
  out.r_cg_ccw = norm_of(ccw.x, ccw.y);
  out.e_max_syst_mm = out.r_cg_cw > out.r_cg_ccw ? out.r_cg_cw : out.r_cg_ccw;

  // Approximate solution. UMBmark eq. 6.22a/b and 6.26a/b, averaged (footnote 2), in rad.
  const Real beta_x = (cw.x - ccw.x) / (-4 * side);
  const Real beta_y = (cw.y + ccw.y) / (-4 * side);
  const Real alpha_x = (cw.x + ccw.x) / (-4 * side);
  const Real alpha_y = (cw.y - ccw.y) / (-4 * side);
  Real beta = Real(0.5) * (beta_x + beta_y);
  Real alpha = Real(0.5) * (alpha_x + alpha_y);
  // UMBmark eq. 6.23 and 6.24, written with b/(2R) = b·sin(β/2)/L so that β = 0 is regular.
  const Real half_b_over_r = b * sin_of(beta / 2) / side;
  if (std::fabs(half_b_over_r) >= 1 || alpha >= quarter) {
    return UmbmarkStatus::degenerate;
  }
  Real e_d = (1 + half_b_over_r) / (1 - half_b_over_r);
  Real e_b = quarter / (quarter - alpha);  // UMBmark eq. 6.29
  // UMBmark eq. 6.22: a straight leg (β = 0) has an infinite radius.
  const Real straight = std::numeric_limits<Real>::infinity();
  Real radius = beta == 0 ? straight : (side / 2) / sin_of(beta / 2);

  if (input.exact) {
    const Real observed[4] = {cw.x, cw.y, ccw.x, ccw.y};
    if (!solve_exact(input, observed, e_d, e_b, out.iterations)) {
      return UmbmarkStatus::degenerate;
    }
    // The same figures, read off the exact model: a real corner turns 90°/E_b, a leg turns
    // (k_R − k_L)·L/(E_b·b) along an arc of length L.
    alpha = quarter - quarter / e_b;
    beta = 2 * (e_d - 1) / (e_d + 1) * side / (e_b * b);
    radius = beta == 0 ? straight : side / beta;
    out.exact = true;
  }
  if (!finite(e_d) || !finite(e_b) || e_d <= 0 || e_b <= 0) {
    return UmbmarkStatus::degenerate;
  }
  out.x_cg_cw = unsigned_zero(out.x_cg_cw);
  out.y_cg_cw = unsigned_zero(out.y_cg_cw);
  out.x_cg_ccw = unsigned_zero(out.x_cg_ccw);
  out.y_cg_ccw = unsigned_zero(out.y_cg_ccw);
  out.alpha_deg = unsigned_zero(alpha * rad_to_deg<Real>);
  out.beta_deg = unsigned_zero(beta * rad_to_deg<Real>);
  out.radius_mm = radius;
  out.e_d = e_d;
  out.e_b = e_b;
  out.c_l = 2 / (e_d + 1);         // UMBmark eq. 6.33
  out.c_r = 2 / (1 / e_d + 1);     // UMBmark eq. 6.34
  out.wheelbase_new_mm = e_b * b;  // UMBmark eq. 6.28

  // Scatter: radial deviation of each run from its own direction's centre, pooled over both
  // directions (two centres estimated). SEM of a centre = σ/√n, with the smaller n (section 6.3).
  const std::size_t runs = input.cw_count + input.ccw_count;
  out.sigma_mm = std::sqrt((cw.scatter_sq + ccw.scatter_sq) / static_cast<Real>(runs - 2));
  const std::size_t n = input.cw_count < input.ccw_count ? input.cw_count : input.ccw_count;
  out.sem_mm = out.sigma_mm / std::sqrt(static_cast<Real>(n));
  // 3·SEM rule; no error at all needs no pass even when the runs have no scatter.
  out.second_pass_recommended = out.e_max_syst_mm > 0 && out.e_max_syst_mm >= 3 * out.sem_mm;
  result = out;
  return UmbmarkStatus::ok;
}

template <typename Real>
WheelFactorsOf<Real> compose(const WheelFactorsOf<Real>& current,
                             const UmbmarkResultOf<Real>& result) {
  Real c_l = current.c_l * result.c_l;
  Real c_r = current.c_r * result.c_r;
  const Real mean = Real(0.5) * (c_l + c_r);
  if (finite(mean) && mean > 0) {
    c_l /= mean;
    c_r /= mean;
  }
  return WheelFactorsOf<Real>{c_l, c_r, result.wheelbase_new_mm};
}

template UmbmarkStatus solve_umbmark(const UmbmarkInputOf<float>&, UmbmarkResultOf<float>&);
template UmbmarkStatus solve_umbmark(const UmbmarkInputOf<double>&, UmbmarkResultOf<double>&);
template WheelFactorsOf<float> compose(const WheelFactorsOf<float>&, const UmbmarkResultOf<float>&);
template WheelFactorsOf<double> compose(const WheelFactorsOf<double>&,
                                        const UmbmarkResultOf<double>&);
template ReturnErrorOf<float> square_return_error(float, float, float, float, bool);
template ReturnErrorOf<double> square_return_error(double, double, double, double, bool);

}  // namespace odocal::calib
