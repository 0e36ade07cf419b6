#pragma once
/// @file
/// A plain reference implementation of the residual bootstrap (Maddahi & Zareinia eq. 9-17, read
/// as DESIGN says), written the obvious way: heap vectors, a full least-squares refit of each
/// replicate with Eigen's dynamic QR, predictions kept in vectors and sorted for the percentiles.
/// It draws the same random numbers in the same order as odocal::calib::run_bootstrap, so the
/// two must agree to rounding; the benchmark times both (docs/performance.md), the test compares.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Dense>

#include "odocal/calib/bootstrap.hpp"
#include "odocal/calib/random.hpp"

namespace odocal::test {

struct ReferenceEstimate {
  double lr[2] = {0.0, 0.0};
  double boot[2] = {0.0, 0.0};
  double lo[2] = {0.0, 0.0};
  double hi[2] = {0.0, 0.0};
};

/// Type-7 sample quantile of sorted values.
inline double reference_quantile(const std::vector<double>& sorted, double p) {
  const double h = p * static_cast<double>(sorted.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(h));
  if (below + 1 >= sorted.size()) {
    return sorted[below];
  }
  return sorted[below] + (h - static_cast<double>(below)) * (sorted[below + 1] - sorted[below]);
}

/// The percentile bootstrap at `level` (plain percentile interval).
inline std::vector<ReferenceEstimate> reference_bootstrap(
    const std::vector<calib::TrainingRow>& training, const std::vector<calib::UnknownRow>& unknowns,
    std::uint32_t replicates, std::uint64_t seed, double level) {
  const auto m = static_cast<Eigen::Index>(training.size());
  Eigen::MatrixXd x(m, 3);
  Eigen::MatrixXd y(m, 2);
  for (Eigen::Index i = 0; i < m; ++i) {
    const calib::TrainingRow& r = training[static_cast<std::size_t>(i)];
    x.row(i) << r.xdot_mps, r.ydot_mps, r.thetadot_radps;
    y.row(i) << r.omega_l_radps, r.omega_r_radps;
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(x);
  const Eigen::MatrixXd psi = qr.solve(y);  // 3x2: column per wheel (eq. 9-12)
  Eigen::MatrixXd residuals = y - x * psi;  // eq. 13-14
  const double scale = std::sqrt(static_cast<double>(m) / static_cast<double>(m - 3));
  std::vector<double> pool;  // centred per wheel, rescaled, left then right
  for (int wheel = 0; wheel < 2; ++wheel) {
    const double mean = residuals.col(wheel).mean();
    for (Eigen::Index i = 0; i < m; ++i) {
      pool.push_back(scale * (residuals(i, wheel) - mean));
    }
  }
  calib::Random random(seed);
  const auto pool_size = static_cast<std::uint32_t>(pool.size());
  std::vector<std::vector<double>> predictions(unknowns.size() * 2);
  for (std::uint32_t b = 0; b < replicates; ++b) {
    for (int wheel = 0; wheel < 2; ++wheel) {
      Eigen::VectorXd y_star = x * psi.col(wheel);  // eq. 15
      for (Eigen::Index i = 0; i < m; ++i) {
        y_star(i) += pool[random.below(pool_size)];
      }
      const Eigen::VectorXd psi_star = qr.solve(y_star);  // a full refit
      for (std::size_t u = 0; u < unknowns.size(); ++u) {
        const Eigen::Vector3d xu(unknowns[u].xdot_mps, unknowns[u].ydot_mps,
                                 unknowns[u].thetadot_radps);
        predictions[2 * u + static_cast<std::size_t>(wheel)].push_back(
            psi_star.dot(xu) + pool[random.below(pool_size)]);  // eq. 16-17
      }
    }
  }
  std::vector<ReferenceEstimate> out(unknowns.size());
  for (std::size_t u = 0; u < unknowns.size(); ++u) {
    const Eigen::Vector3d xu(unknowns[u].xdot_mps, unknowns[u].ydot_mps,
                             unknowns[u].thetadot_radps);
    for (int wheel = 0; wheel < 2; ++wheel) {
      std::vector<double>& p = predictions[2 * u + static_cast<std::size_t>(wheel)];
      double sum = 0.0;
      for (double v : p) {
        sum += v;
      }
      std::sort(p.begin(), p.end());
      out[u].lr[wheel] = psi.col(wheel).dot(xu);
      out[u].boot[wheel] = sum / static_cast<double>(p.size());
      out[u].lo[wheel] = reference_quantile(p, 0.5 * (1.0 - level));
      out[u].hi[wheel] = reference_quantile(p, 0.5 * (1.0 + level));
    }
  }
  return out;
}

}  // namespace odocal::test
