#pragma once
// Internal to host_sim/src/fit: the odometry model of a run and its normal equations.

// Eigen's matrices of dynamic size with a fixed maximum (no allocation) leave their unused
// storage unset: GCC 12 cannot see that no code reads it and warns.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <Eigen/Dense>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <vector>

#include "odocal/drive/robot_model.hpp"
#include "odocal/host/fit.hpp"

namespace odocal::host::fit_detail {

using std::numbers::pi;

/// A stretch of one log: rows [begin, end). Its odometry starts at rows[begin]'s ground-truth
/// pose when that row has one (averaged with the rows right after it that have the same counts),
/// else at (0, 0, 0); residuals are taken at the rows after it.
struct Unit {
  const TickLog* log = nullptr;
  std::size_t begin = 0;
  std::size_t end = 0;
};

/// Parameters, mm: (D_L, D_R, b) for the one-wheelbase model, (D_L, D_R, b_turn, b_arc) for the
/// arc-wheelbase model, (D_L, D_R, b_still, b_1radps) for the turn-rate model (FitModelKind).
/// At most four: fixed maximum size, no allocation in the inner loops.
using Params = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 4, 1>;
using Square = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 4, 4>;

/// Number of parameters of a model.
inline int parameter_count(FitModelKind kind) {
  return kind == FitModelKind::one_wheelbase ? 3 : 4;
}

/// What the model needs besides the parameters.
struct ModelSpec {
  FitModelKind kind = FitModelKind::one_wheelbase;
  double k = 0.0;  ///< π / counts_per_rev: mm per count per mm of diameter
  /// Turn-rate model: rad/s of turn per (count difference per second), from the nominal geometry.
  double rate_per_count_s = 0.0;
};

/// The blend weight of a row of the arc-wheelbase model, counted in encoder counts (as the
/// firmware counts them): the one model's (robot_model.hpp).
inline double arc_weight(double count_l, double count_r) {
  return drive::model::arc_weight(count_l, count_r);
}

/// Pose (mm, rad) and its derivatives with respect to the parameters.
struct ModelState {
  double x = 0.0, y = 0.0, theta = 0.0;
  Params dx, dy, dtheta;
  explicit ModelState(int n) : dx(Params::Zero(n)), dy(Params::Zero(n)), dtheta(Params::Zero(n)) {}
};

/// Integrates the unit's odometry with parameters `p` (mm) and calls
/// `visit(row, state)` at every row after the start that has ground truth. With `jacobian`, the
/// derivatives are carried too. A wheel of diameter D moves D·k mm per count.
template <typename Visit>
void integrate(const Unit& unit, const Params& p, const ModelSpec& spec, bool jacobian,
               Visit&& visit) {
  const std::vector<TickRow>& rows = unit.log->rows;
  const int n = static_cast<int>(p.size());
  const double k = spec.k;
  ModelState s(n);
  const TickRow& start = rows[unit.begin];
  if (start.has_xy && start.has_theta) {
    // The start pose: the first row's truth, averaged over the rows after it at which the wheels
    // have not turned yet (motion capture of a robot at rest: its jitter averages out).
    double sx = 0.0, sy = 0.0, st = 0.0;
    std::size_t count = 0;
    for (std::size_t i = unit.begin; i < unit.end; ++i) {
      const TickRow& row = rows[i];
      if (row.count_l != start.count_l || row.count_r != start.count_r) {
        break;
      }
      if (row.has_xy && row.has_theta) {
        sx += row.x_mm;
        sy += row.y_mm;
        st += std::remainder((row.theta_deg - start.theta_deg) * pi / 180.0, 2.0 * pi);
        ++count;
      }
    }
    s.x = sx / static_cast<double>(count);
    s.y = sy / static_cast<double>(count);
    s.theta = start.theta_deg * pi / 180.0 + st / static_cast<double>(count);
  }
  Params ds_d = Params::Zero(n);
  Params dtheta_d = Params::Zero(n);
  Params chord_d = Params::Zero(n);
  Params mid_d = Params::Zero(n);
  for (std::size_t i = unit.begin + 1; i < unit.end; ++i) {
    const double count_l = rows[i].count_l - rows[i - 1].count_l;
    const double count_r = rows[i].count_r - rows[i - 1].count_r;
    const double a = k * count_l;
    const double c = k * count_r;
    const double dl = a * p[0];
    const double dr = c * p[1];
    const double ds = 0.5 * (dl + dr);
    // The wheelbase in force over this row, and its derivatives along p[2] and p[3].
    double b = p[2];
    double b_d2 = 1.0, b_d3 = 0.0;
    if (spec.kind == FitModelKind::arc_wheelbase) {
      // The one model's wheelbase in force, b + w·(b_arc − b) (drive::model::wheelbase_for).
      const double w = arc_weight(count_l, count_r);
      b = drive::model::wheelbase_for(p[2], p[3], count_l, count_r);
      b_d2 = 1.0 - w;
      b_d3 = w;
    } else if (spec.kind == FitModelKind::turn_rate_wheelbase) {
      const double dt = rows[i].t_s - rows[i - 1].t_s;
      const double rate =
          dt > 0.0 ? spec.rate_per_count_s * std::fabs(count_r - count_l) / dt : 0.0;
      b = p[2] + rate * (p[3] - p[2]);
      b_d2 = 1.0 - rate;
      b_d3 = rate;
    }
    // The one model's exact-arc step (drive::model::advance), carried with its derivatives.
    const double dtheta = (dr - dl) / b;
    const double h = 0.5 * dtheta;
    const drive::model::HalfTurn<double> half = drive::model::half_turn(h);
    const double sinc = half.sinc;
    const double sinc_dh = drive::model::sinc_slope(h, half);
    const double mid = s.theta + h;
    const double cm = std::cos(mid);
    const double sm = std::sin(mid);
    const double chord = ds * sinc;  // chord of an arc of length ds turning dtheta
    if (jacobian) {
      ds_d[0] = 0.5 * a;
      ds_d[1] = 0.5 * c;
      dtheta_d[0] = -a / b;
      dtheta_d[1] = c / b;
      dtheta_d[2] = -dtheta / b * b_d2;
      if (n > 3) {
        dtheta_d[3] = -dtheta / b * b_d3;
      }
      chord_d = ds_d * sinc + (ds * sinc_dh * 0.5) * dtheta_d;
      mid_d = s.dtheta + 0.5 * dtheta_d;
      s.dx += chord_d * cm - (chord * sm) * mid_d;
      s.dy += chord_d * sm + (chord * cm) * mid_d;
      s.dtheta += dtheta_d;
    }
    s.x += chord * cm;
    s.y += chord * sm;
    s.theta += dtheta;
    if (rows[i].has_xy || rows[i].has_theta) {
      visit(rows[i], s);
    }
  }
}

/// Sum of squared residuals, normal equations JᵀJ and Jᵀr, over a set of units.
struct Normal {
  double cost = 0.0;
  std::size_t residuals = 0;
  Square jtj;
  Params jtr;
  /// The heading part on its own, unweighted (rad): what other weightings are made from
  /// (jtj = position part + heading_length_mm² · jtj_theta).
  Square jtj_theta;
  double cost_theta = 0.0;  ///< rad²
  std::size_t theta_residuals = 0;
};

/// Heading difference wrapped to (−π, π]: unwrapped ground truth compares correctly.
inline double heading_error(double model_rad, const TickRow& row) {
  return std::remainder(model_rad - row.theta_deg * pi / 180.0, 2.0 * pi);
}

inline Normal normal_equations(const std::vector<Unit>& units, const std::vector<std::size_t>& pick,
                               const Params& p, const ModelSpec& spec, double heading_length_mm,
                               bool jacobian) {
  Normal n;
  n.jtj = Square::Zero(p.size(), p.size());
  n.jtr = Params::Zero(p.size());
  n.jtj_theta = Square::Zero(p.size(), p.size());
  const auto add = [&](double r, const Params& j) {
    n.cost += r * r;
    ++n.residuals;
    if (jacobian) {
      n.jtj.noalias() += j * j.transpose();
      n.jtr += j * r;
    }
  };
  for (const std::size_t u : pick) {
    integrate(units[u], p, spec, jacobian, [&](const TickRow& row, const ModelState& s) {
      if (row.has_xy) {
        add(s.x - row.x_mm, s.dx);
        add(s.y - row.y_mm, s.dy);
      }
      if (row.has_theta) {
        const double e = heading_error(s.theta, row);
        add(heading_length_mm * e, heading_length_mm * s.dtheta);
        n.cost_theta += e * e;
        ++n.theta_residuals;
        if (jacobian) {
          n.jtj_theta.noalias() += s.dtheta * s.dtheta.transpose();
        }
      }
    });
  }
  return n;
}

}  // namespace odocal::host::fit_detail
