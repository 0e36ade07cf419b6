#include "odocal/calib/umbmark.hpp"

#include <cmath>
#include <limits>

#include <Eigen/Core>
#include <Eigen/LU>

#include "odocal/drive/bounded_trig.hpp"

namespace odocal::calib {
namespace {

// The solver's angles stay within a few turns. On the bare-metal image the bounded sin/cos
// replaces newlib's full-range double sin/cos (~4.5 KB of flash; a few roundings of difference,
// far inside every tolerance); the host keeps libm, so `odocal umbmark` output is unchanged.
#if defined(__arm__) && !defined(__linux__)
double sin_of(double a) {
  return drive::sin_cos(a).sin;
}
double cos_of(double a) {
  return drive::sin_cos(a).cos;
}
#else
double sin_of(double a) {
  return std::sin(a);
}
double cos_of(double a) {
  return std::cos(a);
}
#endif

constexpr double pi = 3.14159265358979323846;
constexpr double quarter_turn_rad = pi / 2.0;
constexpr double rad_to_deg = 180.0 / pi;

/// A value with its derivatives with respect to (E_d, E_b): forward-mode differentiation, so the
/// Gauss-Newton Jacobian of the square geometry is exact and costs one model evaluation.
struct Dual {
  double v = 0.0;
  double d0 = 0.0;  ///< ∂/∂E_d
  double d1 = 0.0;  ///< ∂/∂E_b
};

Dual operator+(Dual a, Dual b) {
  return {a.v + b.v, a.d0 + b.d0, a.d1 + b.d1};
}
Dual operator-(Dual a, Dual b) {
  return {a.v - b.v, a.d0 - b.d0, a.d1 - b.d1};
}
Dual operator*(Dual a, Dual b) {
  return {a.v * b.v, a.d0 * b.v + a.v * b.d0, a.d1 * b.v + a.v * b.d1};
}
Dual operator*(double k, Dual a) {
  return {k * a.v, k * a.d0, k * a.d1};
}
Dual operator/(Dual a, Dual b) {
  const double inv = 1.0 / b.v;
  const double q = a.v * inv;
  return {q, (a.d0 - q * b.d0) * inv, (a.d1 - q * b.d1) * inv};
}
// g(a) with g' known: chain rule.
Dual chain(Dual a, double value, double slope) {
  return {value, slope * a.d0, slope * a.d1};
}
Dual sin_of(Dual a) {
  return chain(a, sin_of(a.v), cos_of(a.v));
}
Dual cos_of(Dual a) {
  return chain(a, cos_of(a.v), -sin_of(a.v));
}

double scalar_sinc(double u, double& slope) {
  if (std::fabs(u) < 1e-4) {  // series: the closed form loses digits near 0
    const double u2 = u * u;
    slope = u * (-1.0 / 3.0 + u2 / 30.0);
    return 1.0 - u2 / 6.0 + u2 * u2 / 120.0;
  }
  const double s = sin_of(u);
  slope = (u * cos_of(u) - s) / (u * u);
  return s / u;
}
double sinc(double u) {
  double slope = 0.0;
  return scalar_sinc(u, slope);
}
Dual sinc(Dual a) {
  double slope = 0.0;
  const double value = scalar_sinc(a.v, slope);
  return chain(a, value, slope);
}

/// Planar pose integrated by exact arcs.
template <typename T>
struct ArcPose {
  T x{};
  T y{};
  T theta{};

  /// One segment with real wheel travels s_l, s_r (mm) and real wheelbase b (mm).
  void move(T s_l, T s_r, T b) {
    const T dtheta = (s_r - s_l) / b;
    const T ds = 0.5 * (s_l + s_r);
    const T half = 0.5 * dtheta;
    const T chord = ds * sinc(half);  // chord length of the arc
    const T mid = theta + half;
    x = x + chord * cos_of(mid);
    y = y + chord * sin_of(mid);
    theta = theta + dtheta;
  }
};

/// The bidirectional-square model of `square_return_error`, generic in the scalar so that the
/// exact solve gets its Jacobian from the same code.
template <typename T>
void square_end(double side_mm, double wheelbase_mm, T e_d, T e_b, bool clockwise, T& x, T& y) {
  const T one{1.0};
  // Real wheel travel per perceived wheel travel; the mean diameter stays D_a (UMBmark eq. 6.30).
  const T k_l = T{2.0} / (e_d + one);
  const T k_r = (T{2.0} * e_d) / (e_d + one);
  const T b_real = wheelbase_mm * e_b;
  const T leg{side_mm};
  // Odometry sees a turn of 90° when each wheel has moved a quarter of the b-circle.
  const double turn_travel = quarter_turn_rad * wheelbase_mm / 2.0;
  const T turn_l{clockwise ? turn_travel : -turn_travel};
  const T turn_r{clockwise ? -turn_travel : turn_travel};
  ArcPose<T> pose;
  for (int corner = 0; corner < 4; ++corner) {
    pose.move(k_l * leg, k_r * leg, b_real);
    pose.move(k_l * turn_l, k_r * turn_r, b_real);
  }
  x = pose.x;
  y = pose.y;
}

bool finite(double v) {
  return std::isfinite(v);
}

/// −0 as +0, so that no figure reads "-0.0" (e.g. β of error-free runs is 0/(−4L) = −0).
double unsigned_zero(double v) {
  return v == 0.0 ? 0.0 : v;
}

struct Centroid {
  double x = 0.0;
  double y = 0.0;
  double scatter_sq = 0.0;  ///< Σ |e − c|²
};

Centroid centroid(const ReturnError* runs, std::size_t count) {
  Centroid c;
  for (std::size_t i = 0; i < count; ++i) {
    c.x += runs[i].x_mm;
    c.y += runs[i].y_mm;
  }
  const double n = static_cast<double>(count);
  c.x /= n;
  c.y /= n;
  for (std::size_t i = 0; i < count; ++i) {
    const double dx = runs[i].x_mm - c.x;
    const double dy = runs[i].y_mm - c.y;
    c.scatter_sq += dx * dx + dy * dy;
  }
  return c;
}

UmbmarkStatus check_runs(const ReturnError* runs, std::size_t count, double limit_mm) {
  if (runs == nullptr || count < 2 || count > umbmark_max_runs) {
    return UmbmarkStatus::too_few_runs;
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (!finite(runs[i].x_mm) || !finite(runs[i].y_mm)) {
      return UmbmarkStatus::non_finite;
    }
    if (std::hypot(runs[i].x_mm, runs[i].y_mm) > limit_mm) {
      return UmbmarkStatus::error_too_large;
    }
  }
  return UmbmarkStatus::ok;
}

/// Gauss-Newton on the exact square geometry: (E_d, E_b) such that the modelled cw and ccw
/// return errors match the two centres of gravity in the least-squares sense.
bool solve_exact(const UmbmarkInput& input, const Eigen::Vector4d& observed, double& e_d,
                 double& e_b, std::uint8_t& iterations) {
  constexpr int max_iterations = 30;
  for (int it = 1; it <= max_iterations; ++it) {
    Dual ed{e_d, 1.0, 0.0};
    Dual eb{e_b, 0.0, 1.0};
    Dual model[4];
    square_end(input.side_mm, input.wheelbase_mm, ed, eb, true, model[0], model[1]);
    square_end(input.side_mm, input.wheelbase_mm, ed, eb, false, model[2], model[3]);
    Eigen::Vector4d residual;
    Eigen::Matrix<double, 4, 2> jacobian;
    for (int i = 0; i < 4; ++i) {
      residual(i) = model[i].v - observed(i);
      jacobian(i, 0) = model[i].d0;
      jacobian(i, 1) = model[i].d1;
    }
    const Eigen::Matrix2d normal = jacobian.transpose() * jacobian;
    const double det = normal.determinant();
    if (!finite(det) || std::fabs(det) <= 1e-30 * normal.squaredNorm()) {
      return false;
    }
    const Eigen::Vector2d step = -normal.inverse() * (jacobian.transpose() * residual);
    e_d += step(0);
    e_b += step(1);
    if (!finite(e_d) || !finite(e_b) || e_d <= 0.0 || e_b <= 0.0) {
      return false;
    }
    if (std::fabs(step(0)) < 1e-13 * e_d && std::fabs(step(1)) < 1e-13 * e_b) {
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
  switch (status) {
    case UmbmarkStatus::ok:
      return "ok";
    case UmbmarkStatus::too_few_runs:
      return "too few runs (need 2 to 64 per direction)";
    case UmbmarkStatus::bad_side:
      return "side length must be finite and > 0";
    case UmbmarkStatus::bad_wheelbase:
      return "wheelbase must be finite and > 0";
    case UmbmarkStatus::non_finite:
      return "a return error is NaN or infinite";
    case UmbmarkStatus::error_too_large:
      return "a return error is larger than the path (4 sides)";
    case UmbmarkStatus::degenerate:
      return "degenerate: the errors fit no square geometry (curvature radius below half the "
             "wheelbase, or a turn error of 90 degrees or more)";
  }
  return "unknown status";
}

ReturnError square_return_error(double side_mm, double wheelbase_mm, double e_d, double e_b,
                                bool clockwise) {
  double x = 0.0;
  double y = 0.0;
  square_end(side_mm, wheelbase_mm, e_d, e_b, clockwise, x, y);
  return ReturnError{x, y};
}

UmbmarkStatus solve_umbmark(const UmbmarkInput& input, UmbmarkResult& result) {
  const double side = input.side_mm;
  const double b = input.wheelbase_mm;
  if (!finite(side) || side <= 0.0) {
    return UmbmarkStatus::bad_side;
  }
  if (!finite(b) || b <= 0.0) {
    return UmbmarkStatus::bad_wheelbase;
  }
  const double path_mm = 4.0 * side;
  for (const auto status : {check_runs(input.cw, input.cw_count, path_mm),
                            check_runs(input.ccw, input.ccw_count, path_mm)}) {
    if (status != UmbmarkStatus::ok) {
      return status;
    }
  }

  UmbmarkResult out;
  const Centroid cw = centroid(input.cw, input.cw_count);
  const Centroid ccw = centroid(input.ccw, input.ccw_count);
  out.x_cg_cw = cw.x;
  out.y_cg_cw = cw.y;
  out.x_cg_ccw = ccw.x;
  out.y_cg_ccw = ccw.y;
  out.r_cg_cw = std::hypot(cw.x, cw.y);  // UMBmark eq. 3.3
  out.r_cg_ccw = std::hypot(ccw.x, ccw.y);
  out.e_max_syst_mm = out.r_cg_cw > out.r_cg_ccw ? out.r_cg_cw : out.r_cg_ccw;

  // Approximate solution. UMBmark eq. 6.22a/b and 6.26a/b, averaged (footnote 2), in rad.
  const double beta_x = (cw.x - ccw.x) / (-4.0 * side);
  const double beta_y = (cw.y + ccw.y) / (-4.0 * side);
  const double alpha_x = (cw.x + ccw.x) / (-4.0 * side);
  const double alpha_y = (cw.y - ccw.y) / (-4.0 * side);
  double beta = 0.5 * (beta_x + beta_y);
  double alpha = 0.5 * (alpha_x + alpha_y);
  // UMBmark eq. 6.23 and 6.24, written with b/(2R) = b·sin(β/2)/L so that β = 0 is regular.
  const double half_b_over_r = b * sin_of(beta / 2.0) / side;
  if (std::fabs(half_b_over_r) >= 1.0 || alpha >= quarter_turn_rad) {
    return UmbmarkStatus::degenerate;
  }
  double e_d = (1.0 + half_b_over_r) / (1.0 - half_b_over_r);
  double e_b = quarter_turn_rad / (quarter_turn_rad - alpha);  // UMBmark eq. 6.29
  // UMBmark eq. 6.22: a straight leg (β = 0) has an infinite radius.
  const double straight = std::numeric_limits<double>::infinity();
  double radius = beta == 0.0 ? straight : (side / 2.0) / sin_of(beta / 2.0);

  if (input.exact) {
    Eigen::Vector4d observed(cw.x, cw.y, ccw.x, ccw.y);
    if (!solve_exact(input, observed, e_d, e_b, out.iterations)) {
      return UmbmarkStatus::degenerate;
    }
    // The same figures, read off the exact model: a real corner turns 90°/E_b, a leg turns
    // (k_R − k_L)·L/(E_b·b) along an arc of length L.
    alpha = quarter_turn_rad - quarter_turn_rad / e_b;
    beta = 2.0 * (e_d - 1.0) / (e_d + 1.0) * side / (e_b * b);
    radius = beta == 0.0 ? straight : side / beta;
    out.exact = true;
  }
  if (!finite(e_d) || !finite(e_b) || e_d <= 0.0 || e_b <= 0.0) {
    return UmbmarkStatus::degenerate;
  }
  out.x_cg_cw = unsigned_zero(out.x_cg_cw);
  out.y_cg_cw = unsigned_zero(out.y_cg_cw);
  out.x_cg_ccw = unsigned_zero(out.x_cg_ccw);
  out.y_cg_ccw = unsigned_zero(out.y_cg_ccw);
  out.alpha_deg = unsigned_zero(alpha * rad_to_deg);
  out.beta_deg = unsigned_zero(beta * rad_to_deg);
  out.radius_mm = radius;
  out.e_d = e_d;
  out.e_b = e_b;
  out.c_l = 2.0 / (e_d + 1.0);        // UMBmark eq. 6.33
  out.c_r = 2.0 / (1.0 / e_d + 1.0);  // UMBmark eq. 6.34
  out.wheelbase_new_mm = e_b * b;     // UMBmark eq. 6.28

  // Scatter: radial deviation of each run from its own direction's centre, pooled over both
  // directions (two centres estimated). SEM of a centre = σ/√n, with the smaller n (section 6.3).
  const std::size_t runs = input.cw_count + input.ccw_count;
  out.sigma_mm = std::sqrt((cw.scatter_sq + ccw.scatter_sq) / static_cast<double>(runs - 2));
  const std::size_t n = input.cw_count < input.ccw_count ? input.cw_count : input.ccw_count;
  out.sem_mm = out.sigma_mm / std::sqrt(static_cast<double>(n));
  // 3·SEM rule; no error at all needs no pass even when the runs have no scatter.
  out.second_pass_recommended = out.e_max_syst_mm > 0.0 && out.e_max_syst_mm >= 3.0 * out.sem_mm;
  result = out;
  return UmbmarkStatus::ok;
}

WheelFactors compose(const WheelFactors& current, const UmbmarkResult& result) {
  double c_l = current.c_l * result.c_l;
  double c_r = current.c_r * result.c_r;
  const double mean = 0.5 * (c_l + c_r);
  if (finite(mean) && mean > 0.0) {
    c_l /= mean;
    c_r /= mean;
  }
  return WheelFactors{c_l, c_r, result.wheelbase_new_mm};
}

}  // namespace odocal::calib
