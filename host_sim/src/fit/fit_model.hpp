#pragma once
// Internal to host_sim/src/fit: the odometry model of a run and its normal equations.

#include <Eigen/Dense>
#include <cmath>
#include <cstddef>
#include <vector>

#include "odocal/host/fit.hpp"

namespace odocal::host::fit_detail {

constexpr double pi = 3.14159265358979323846;

/// A stretch of one log: rows [begin, end). Its odometry starts at rows[begin]'s ground-truth
/// pose when that row has one (averaged with the rows right after it that have the same counts),
/// else at (0, 0, 0); residuals are taken at the rows after it.
struct Unit {
  const TickLog* log = nullptr;
  std::size_t begin = 0;
  std::size_t end = 0;
};

/// Parameters (D_L, D_R, b), mm.
using Params = Eigen::Vector3d;

/// Pose (mm, rad) and its derivatives with respect to the three parameters.
struct ModelState {
  double x = 0.0, y = 0.0, theta = 0.0;
  Eigen::Vector3d dx = Eigen::Vector3d::Zero();
  Eigen::Vector3d dy = Eigen::Vector3d::Zero();
  Eigen::Vector3d dtheta = Eigen::Vector3d::Zero();
};

/// Integrates the unit's odometry with parameters `p` (mm) and calls
/// `visit(row, state)` at every row after the start that has ground truth. With `jacobian`, the
/// derivatives are carried too. `mm_per_count_per_mm` = π / counts_per_rev: a wheel of diameter D
/// moves D·π/N mm per count.
template <typename Visit>
void integrate(const Unit& unit, const Params& p, double mm_per_count_per_mm, bool jacobian,
               Visit&& visit) {
  const std::vector<TickRow>& rows = unit.log->rows;
  ModelState s;
  const TickRow& start = rows[unit.begin];
  if (start.has_xy && start.has_theta) {
    // The start pose: the first row's truth, averaged over the rows after it at which the wheels
    // have not turned yet (motion capture of a robot at rest: its jitter averages out).
    double sx = 0.0, sy = 0.0, st = 0.0;
    std::size_t n = 0;
    for (std::size_t i = unit.begin; i < unit.end; ++i) {
      const TickRow& row = rows[i];
      if (row.count_l != start.count_l || row.count_r != start.count_r) {
        break;
      }
      if (row.has_xy && row.has_theta) {
        sx += row.x_mm;
        sy += row.y_mm;
        st += std::remainder((row.theta_deg - start.theta_deg) * pi / 180.0, 2.0 * pi);
        ++n;
      }
    }
    s.x = sx / static_cast<double>(n);
    s.y = sy / static_cast<double>(n);
    s.theta = start.theta_deg * pi / 180.0 + st / static_cast<double>(n);
  }
  for (std::size_t i = unit.begin + 1; i < unit.end; ++i) {
    const double a = mm_per_count_per_mm * (rows[i].count_l - rows[i - 1].count_l);
    const double c = mm_per_count_per_mm * (rows[i].count_r - rows[i - 1].count_r);
    const double dl = a * p[0];
    const double dr = c * p[1];
    const double ds = 0.5 * (dl + dr);
    const double dtheta = (dr - dl) / p[2];
    const double h = 0.5 * dtheta;
    // sinc(h) = sin(h)/h and its derivative; series where cancellation would cost digits.
    double sinc = 0.0;
    double sinc_dh = 0.0;
    const double h2 = h * h;
    if (h2 < 1e-6) {
      sinc = 1.0 - h2 / 6.0 * (1.0 - h2 / 20.0);
      sinc_dh = -h / 3.0 * (1.0 - h2 / 10.0);
    } else {
      sinc = std::sin(h) / h;
      sinc_dh = (std::cos(h) - sinc) / h;
    }
    const double mid = s.theta + h;
    const double cm = std::cos(mid);
    const double sm = std::sin(mid);
    const double chord = ds * sinc;  // chord of an arc of length ds turning dtheta
    if (jacobian) {
      const Eigen::Vector3d ds_d(0.5 * a, 0.5 * c, 0.0);
      const Eigen::Vector3d dtheta_d(-a / p[2], c / p[2], -dtheta / p[2]);
      const Eigen::Vector3d chord_d = ds_d * sinc + (ds * sinc_dh * 0.5) * dtheta_d;
      const Eigen::Vector3d mid_d = s.dtheta + 0.5 * dtheta_d;
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
  Eigen::Matrix3d jtj = Eigen::Matrix3d::Zero();
  Eigen::Vector3d jtr = Eigen::Vector3d::Zero();
};

/// Heading difference wrapped to (−π, π]: unwrapped ground truth compares correctly.
inline double heading_error(double model_rad, const TickRow& row) {
  return std::remainder(model_rad - row.theta_deg * pi / 180.0, 2.0 * pi);
}

inline Normal normal_equations(const std::vector<Unit>& units, const std::vector<std::size_t>& pick,
                               const Params& p, double k, double heading_length_mm, bool jacobian) {
  Normal n;
  const auto add = [&](double r, const Eigen::Vector3d& j) {
    n.cost += r * r;
    ++n.residuals;
    if (jacobian) {
      n.jtj.noalias() += j * j.transpose();
      n.jtr += j * r;
    }
  };
  for (const std::size_t u : pick) {
    integrate(units[u], p, k, jacobian, [&](const TickRow& row, const ModelState& s) {
      if (row.has_xy) {
        add(s.x - row.x_mm, s.dx);
        add(s.y - row.y_mm, s.dy);
      }
      if (row.has_theta) {
        add(heading_length_mm * heading_error(s.theta, row), heading_length_mm * s.dtheta);
      }
    });
  }
  return n;
}

}  // namespace odocal::host::fit_detail
