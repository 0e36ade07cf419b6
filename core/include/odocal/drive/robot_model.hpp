#pragma once
/// @file
/// The robot's odometry model, defined once: the geometry the parameters put in force (with the
/// composition rule of the calibration factors), the arc wheelbase's weight, and one exact-arc
/// step in its numerically stable form. The firmware's odometry and kinematics (float), the fit,
/// UMBmark's exact solve, the session's predictions and reports and the simulated procedures
/// (double) all call these; the simulated plant keeps its own physics and a test holds it to this
/// model (tests/core/drive/robot_model_test.cpp, tests/hal/sim/plant_test.cpp).
///
/// Templates on the scalar: `float` on the robot (bounded sin/cos, no libm tables), `double` on
/// the host (libm). Pure, ISR-safe, no state.

#include <cmath>

#include "odocal/math/bounded_trig.hpp"

namespace odocal::drive::model {

/// sin and cos of a bounded angle: the robot's own for float, libm's for double.
inline math::SinCos trig(float angle) {
  return math::sin_cos(angle);
}
inline math::SinCosOf<double> trig(double angle) {
  return {std::sin(angle), std::cos(angle)};
}

/// The terms of half of one arc's turn, h = Δθ/2.
template <typename T>
struct HalfTurn {
  T cos;   ///< cos h
  T sin;   ///< sin h
  T sinc;  ///< sin(h)/h (1 at h = 0)
};

/// Below this h², series replace the closed forms: sin(h)/h and its slope would lose digits to
/// cancellation, and the series' first dropped terms (h⁶/5040 in sinc, h⁶/720 in cos, h⁵/840 in
/// the slope) are below the type's rounding. Float: |h| < 0.02 (cheaper than sin_cos too).
template <typename T>
constexpr T series_limit_sq = T(1e-6);
template <>
inline constexpr float series_limit_sq<float> = 4e-4f;

/// cos h, sin h and sinc h, stable for every h a tick or a path segment turns.
template <typename T>
HalfTurn<T> half_turn(T h) {
  const T h2 = h * h;
  if (h2 < series_limit_sq<T>) {
    const T sinc = T(1) - h2 * (T(1) / T(6)) * (T(1) - h2 * (T(1) / T(20)));
    const T c = T(1) - h2 * T(0.5) * (T(1) - h2 * (T(1) / T(12)));
    return HalfTurn<T>{c, h * sinc, sinc};
  }
  const auto sc = trig(h);
  return HalfTurn<T>{sc.cos, sc.sin, sc.sin / h};
}

/// d(sin(h)/h)/dh from `half_turn(h)`'s terms (for derivatives of the step: the fit's Jacobian,
/// UMBmark's exact solve), by the same series below the same limit.
template <typename T>
T sinc_slope(T h, const HalfTurn<T>& t) {
  const T h2 = h * h;
  if (h2 < series_limit_sq<T>) {
    return -h * (T(1) / T(3)) * (T(1) - h2 * (T(1) / T(10)));
  }
  return (t.cos - t.sinc) / h;
}

/// The arc wheelbase's weight of one increment: forward over forward plus differential wheel
/// travel (any unit common to both wheels: counts, mm, rad/s): 0 turning in place, 1 straight,
/// R/(R + b/2) on an arc of radius R; 0 at rest.
template <typename T>
T arc_weight(T left, T right) {
  const T forward = std::fabs(left + right);
  const T sum = forward + std::fabs(right - left);
  return sum > T(0) ? forward / sum : T(0);
}

/// The wheelbase in force over an increment: b + w·(b_arc − b), w = arc_weight(left, right);
/// `wheelbase_arc` 0 means one wheelbase (b, no arithmetic).
template <typename T>
T wheelbase_for(T wheelbase, T wheelbase_arc, T left, T right) {
  return wheelbase_arc == T(0) ? wheelbase
                               : wheelbase + (wheelbase_arc - wheelbase) * arc_weight(left, right);
}

/// A planar pose: x along the start heading, y to the left, θ counter-clockwise (not wrapped).
template <typename T>
struct PoseOf {
  T x{};
  T y{};
  T theta{};
};

/// One exact-arc step of the centre: along a circular arc of length `ds` turning `dtheta`, whose
/// chord ds·sinc(dtheta/2) points at the arc's middle heading θ + dtheta/2. Exact for constant
/// curvature (not Euler); a straight line (dtheta = 0) and a turn in place (ds = 0) included.
template <typename T>
void advance_arc(PoseOf<T>& pose, T ds, T dtheta) {
  const HalfTurn<T> half = half_turn(T(0.5) * dtheta);
  const T chord = ds * half.sinc;
  const auto mid = trig(pose.theta + T(0.5) * dtheta);
  pose.x += chord * mid.cos;
  pose.y += chord * mid.sin;
  pose.theta += dtheta;
}

/// One exact-arc step from the wheels: their contact points moved `left` and `right` with the
/// wheelbase `wheelbase` in force (one length unit): Δs = (left + right)/2, Δθ = (right − left)/b.
template <typename T>
void advance(PoseOf<T>& pose, T left, T right, T wheelbase) {
  advance_arc(pose, T(0.5) * (left + right), (right - left) / wheelbase);
}

/// The geometry the odometry and the drive use (one length unit throughout).
template <typename T>
struct Geometry {
  T left_diameter{};   ///< D_L
  T right_diameter{};  ///< D_R
  T wheelbase{};       ///< b: turning in place (the one wheelbase when wheelbase_arc is 0)
  T wheelbase_arc{};   ///< b_arc: driving straight (0: one wheelbase)
};

/// The two wheels' travel over one increment (one length unit).
template <typename T>
struct WheelTravel {
  T left{};
  T right{};
};

/// The inverse of the step: the wheel travel that drives the centre `distance` along one arc
/// while turning `turn` (rad), for the geometry `g`. The turn's wheelbase is the one the arc
/// weight of those wheels' rotations picks (wheelbase_for of travel / diameter, as the firmware's
/// counts weigh it): a fixed point, exact at once for a line, a turn in place or one wheelbase.
/// On an arc each step shrinks the wheelbase's error by a factor of at most |b_arc − b|/(4·b)
/// (the weight's slope w·(1 − w)/b ≤ 1/(4·b)): 0.05 within the firmware's 20 % bound, so six
/// steps leave less than 2e-8 of the wheelbase.
template <typename T>
WheelTravel<T> travel_for(const Geometry<T>& g, T distance, T turn) {
  T b = g.wheelbase;
  for (int i = 0; i < 6 && g.wheelbase_arc != T(0); ++i) {
    b = wheelbase_for(g.wheelbase, g.wheelbase_arc,
                      (distance - T(0.5) * turn * b) / g.left_diameter,
                      (distance + T(0.5) * turn * b) / g.right_diameter);
  }
  return {distance - T(0.5) * turn * b, distance + T(0.5) * turn * b};
}

/// One increment driven by a firmware that believes the geometry `told` on a robot that is
/// `truth`: the wheels turn what `told` computes for `distance` and `turn` (travel_for), and roll
/// what `truth`'s diameters make of those rotations, one exact arc with `truth`'s wheelbase for
/// them. With told = truth it is advance_arc(pose, distance, turn).
template <typename T>
void advance_believing(PoseOf<T>& pose, const Geometry<T>& told, const Geometry<T>& truth,
                       T distance, T turn) {
  const WheelTravel<T> w = travel_for(told, distance, turn);
  const T turns_l = w.left / told.left_diameter;  // rotations, per unit of diameter
  const T turns_r = w.right / told.right_diameter;
  advance(pose, turns_l * truth.left_diameter, turns_r * truth.right_diameter,
          wheelbase_for(truth.wheelbase, truth.wheelbase_arc, turns_l, turns_r));
}

/// The calibration factors and the nominal geometry, as the firmware's parameters hold them.
template <typename T>
struct Parameters {
  T wheel_diameter{};  ///< D_a, the average diameter the firmware is told
  T wheelbase{};       ///< wheelbase_mm (UMBmark's b_new, a fit's turn-in-place wheelbase)
  T wheelbase_arc{};   ///< wheelbase_arc_mm, 0: one wheelbase
  T c_l{1};
  T c_r{1};
  T f_lat{1};
  T f_lon{1};
};

/// The geometry in force, and the one rule that composes the calibration factors:
///   D_L = D_a·c_L/(F_lat·F_lon),  D_R = D_a·c_R/F_lon  (UMBmark eq. 6.35; Maddahi eq. 7);
///   b, b_arc scaled by s = (c_L/(F_lat·F_lon) + c_R/F_lon)/(c_L + c_R).
/// F_lat and F_lon correct what straight runs show (the wheel ratio, the distance); they change
/// the mean diameter, and a turn in place turns (D_L + D_R)/b per wheel rotation: scaling the
/// wheelbases by the same s keeps every turn's angle, so a Maddahi step never undoes what UMBmark
/// or a fit got right about turning. With F_lat = F_lon = 1, s is exactly 1.
template <typename T>
Geometry<T> geometry_in_force(const Parameters<T>& p) {
  const T left_factor = p.c_l / (p.f_lat * p.f_lon);
  const T right_factor = p.c_r / p.f_lon;
  const T scale = (left_factor + right_factor) / (p.c_l + p.c_r);
  return Geometry<T>{p.wheel_diameter * left_factor, p.wheel_diameter * right_factor,
                     p.wheelbase * scale, p.wheelbase_arc * scale};
}

/// The parameters that put `g` in force with F_lat = F_lon = 1 (c = D/D_a; what a fit applies).
template <typename T>
Parameters<T> parameters_for(const Geometry<T>& g, T wheel_diameter) {
  return Parameters<T>{wheel_diameter,
                       g.wheelbase,
                       g.wheelbase_arc,
                       g.left_diameter / wheel_diameter,
                       g.right_diameter / wheel_diameter,
                       T(1),
                       T(1)};
}

}  // namespace odocal::drive::model
