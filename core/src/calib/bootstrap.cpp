#include "odocal/calib/bootstrap.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "odocal/calib/quantile.hpp"
#include "odocal/calib/random.hpp"

namespace odocal::calib {
namespace {

using Vector3 = Eigen::Vector3d;
using Matrix3 = Eigen::Matrix3d;

Vector3 design_row(const TrainingRow& row) {
  return Vector3(row.xdot_mps, row.ydot_mps, row.thetadot_radps);
}
Vector3 design_row(const UnknownRow& row) {
  return Vector3(row.xdot_mps, row.ydot_mps, row.thetadot_radps);
}
double response(const TrainingRow& row, int wheel) {
  return wheel == 0 ? row.omega_l_radps : row.omega_r_radps;
}

bool finite_row(const TrainingRow& r) {
  return std::isfinite(r.xdot_mps) && std::isfinite(r.ydot_mps) &&
         std::isfinite(r.thetadot_radps) && std::isfinite(r.omega_l_radps) &&
         std::isfinite(r.omega_r_radps);
}
bool finite_row(const UnknownRow& r) {
  return std::isfinite(r.xdot_mps) && std::isfinite(r.ydot_mps) && std::isfinite(r.thetadot_radps);
}

/// The least-squares pieces shared by the fit and the refits: (XᵀX)⁻¹ and the residual pool.
struct Model {
  Matrix3 normal_inverse = Matrix3::Zero();
  double residual_mean[2] = {0.0, 0.0};
};

/// numerator / denominator into `quotient` when it is finite; false (and 0) otherwise.
bool ratio(double numerator, double denominator, double& quotient) {
  const double q = denominator != 0.0 ? numerator / denominator : 0.0;
  const bool defined = denominator != 0.0 && std::isfinite(q);
  quotient = defined ? q : 0.0;
  return defined;
}

BootstrapStatus fit(const TrainingRow* training, std::size_t count, BootstrapFit& out,
                    Model& model) {
  if (training == nullptr || count < bootstrap_min_training || count > bootstrap_max_training) {
    return BootstrapStatus::too_few_rows;
  }
  Matrix3 normal = Matrix3::Zero();
  Eigen::Matrix<double, 3, 2> moment = Eigen::Matrix<double, 3, 2>::Zero();
  for (std::size_t i = 0; i < count; ++i) {
    if (!finite_row(training[i])) {
      return BootstrapStatus::non_finite;
    }
    const Vector3 x = design_row(training[i]);
    normal.noalias() += x * x.transpose();
    moment.col(0) += x * training[i].omega_l_radps;
    moment.col(1) += x * training[i].omega_r_radps;
  }
  // Rank check on the column-equilibrated normal matrix: the design is refused when a column is
  // zero or its columns are parallel to ~1e-6 (condition number of the scaled X above 1e6).
  const Vector3 scale = normal.diagonal().cwiseSqrt();
  if (!(scale.minCoeff() > 0.0) || !std::isfinite(scale.maxCoeff())) {
    return BootstrapStatus::degenerate;
  }
  const Vector3 inv_scale = scale.cwiseInverse();
  const Matrix3 equilibrated = inv_scale.asDiagonal() * normal * inv_scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Matrix3> eigen(equilibrated, Eigen::EigenvaluesOnly);
  const Vector3 lambda = eigen.eigenvalues();  // ascending
  if (!(lambda(0) > 1e-12 * lambda(2))) {
    return BootstrapStatus::degenerate;
  }
  const Matrix3 equilibrated_inverse = equilibrated.inverse();
  model.normal_inverse = inv_scale.asDiagonal() * equilibrated_inverse * inv_scale.asDiagonal();

  // Maddahi eq. 9-12: one least-squares row of Ψ per wheel.
  const Eigen::Matrix<double, 3, 2> psi_t = model.normal_inverse * moment;
  out.psi = psi_t.transpose();
  const double m = static_cast<double>(count);
  const double p = static_cast<double>(bootstrap_parameters);
  out.residual_scale = std::sqrt(m / (m - p));

  // Residuals e = θ̇ − Ψ̂Ẋ (eq. 13-14 up to sign; the sign that rebuilds θ̇ in eq. 15). With no
  // intercept in eq. 10 they need not average to zero, so each wheel's set is centred before
  // pooling; otherwise every replicate would be shifted by the mean residual.
  double sum_sq = 0.0;
  for (int wheel = 0; wheel < 2; ++wheel) {
    double sum = 0.0;
    for (std::size_t i = 0; i < count; ++i) {
      sum += response(training[i], wheel) - out.psi.row(wheel).dot(design_row(training[i]));
    }
    model.residual_mean[wheel] = sum / m;
    for (std::size_t i = 0; i < count; ++i) {
      const double e = response(training[i], wheel) -
                       out.psi.row(wheel).dot(design_row(training[i])) - model.residual_mean[wheel];
      sum_sq += e * e;
    }
  }
  out.residual_rms = out.residual_scale * std::sqrt(sum_sq / (2.0 * m));
  if (!out.psi.allFinite() || !std::isfinite(out.residual_rms)) {
    return BootstrapStatus::degenerate;
  }
  return BootstrapStatus::ok;
}

}  // namespace

const char* to_string(BootstrapStatus status) {
  switch (status) {
    case BootstrapStatus::ok:
      return "ok";
    case BootstrapStatus::too_few_rows:
      return "too few training rows (need at least 5) or no unknowns";
    case BootstrapStatus::non_finite:
      return "a value is not finite";
    case BootstrapStatus::degenerate:
      return "degenerate design: the training velocities do not determine the 3 parameters "
             "(a column is zero or columns are proportional)";
    case BootstrapStatus::bad_replicates:
      return "replicates must be between 100 and 1000000";
    case BootstrapStatus::bad_level:
      return "level must be strictly between 0 and 1";
    case BootstrapStatus::scratch_too_small:
      return "scratch storage too small";
  }
  return "unknown status";
}

BootstrapStatus fit_wheel_model(const TrainingRow* training, std::size_t count,
                                BootstrapFit& result) {
  BootstrapFit out;
  Model model;
  const BootstrapStatus status = fit(training, count, out, model);
  if (status == BootstrapStatus::ok) {
    out.effective_level = 0.0;
    result = out;
  }
  return status;
}

double t_calibrated_level(double level, double dof) {
  if (!(dof > 0.0) || !(level > 0.0) || !(level < 1.0)) {
    return level;
  }
  const double t = student_t_quantile(0.5 * (1.0 + level), dof);
  return 2.0 * normal_cdf(t) - 1.0;
}

BootstrapStatus run_bootstrap(const BootstrapInput& input, BootstrapEstimate* estimates,
                              std::size_t estimates_count, BootstrapFit& fit_out) {
  if (input.unknowns == nullptr || input.unknown_count == 0 || estimates == nullptr ||
      estimates_count < input.unknown_count) {
    return BootstrapStatus::too_few_rows;
  }
  if (input.replicates < bootstrap_min_replicates || input.replicates > bootstrap_max_replicates) {
    return BootstrapStatus::bad_replicates;
  }
  if (!(input.level > 0.0) || !(input.level < 1.0)) {
    return BootstrapStatus::bad_level;
  }
  const std::size_t b_count = input.replicates;
  if (input.scratch == nullptr ||
      input.scratch_count < bootstrap_scratch_count(input.replicates, input.unknown_count)) {
    return BootstrapStatus::scratch_too_small;
  }
  for (std::size_t u = 0; u < input.unknown_count; ++u) {
    if (!finite_row(input.unknowns[u])) {
      return BootstrapStatus::non_finite;
    }
  }
  BootstrapFit out;
  Model model;
  const BootstrapStatus status = fit(input.training, input.training_count, out, model);
  if (status != BootstrapStatus::ok) {
    return status;
  }
  const std::size_t m = input.training_count;
  const TrainingRow* training = input.training;
  // Pooled residual k (0 <= k < 2m): wheel k/m, row k%m, centred and rescaled by sqrt(m/(m−p)).
  const auto pooled = [&](std::uint32_t k) {
    const int wheel = k < m ? 0 : 1;
    const TrainingRow& row = training[k < m ? k : k - m];
    return out.residual_scale * (response(row, wheel) - out.psi.row(wheel).dot(design_row(row)) -
                                 model.residual_mean[wheel]);
  };
  const auto pool_size = static_cast<std::uint32_t>(2 * m);

  Random random(input.seed);
  double* scratch = input.scratch;
  for (std::size_t b = 0; b < b_count; ++b) {
    for (int wheel = 0; wheel < 2; ++wheel) {
      // Eq. 15: θ̇* = Ψ̂Ẋ + ε*; the refit is Ψ* = Ψ̂ + (XᵀX)⁻¹Xᵀε*, since X is fixed.
      Vector3 moment = Vector3::Zero();
      for (std::size_t i = 0; i < m; ++i) {
        moment += design_row(training[i]) * pooled(random.below(pool_size));
      }
      const Vector3 psi_star = out.psi.row(wheel).transpose() + model.normal_inverse * moment;
      for (std::size_t u = 0; u < input.unknown_count; ++u) {
        // Eq. 16-17: prediction for the unknown with a fresh resampled residual.
        scratch[(2 * u + static_cast<std::size_t>(wheel)) * b_count + b] =
            psi_star.dot(design_row(input.unknowns[u])) + pooled(random.below(pool_size));
      }
    }
  }

  const double level =
      input.method == IntervalMethod::calibrated_percentile
          ? t_calibrated_level(input.level, 2.0 * static_cast<double>(m - bootstrap_parameters))
          : input.level;
  out.effective_level = level;
  const double lower_p = 0.5 * (1.0 - level);
  const double upper_p = 0.5 * (1.0 + level);
  for (std::size_t u = 0; u < input.unknown_count; ++u) {
    const Vector3 x = design_row(input.unknowns[u]);
    double values[2][4] = {};  // lr, boot, lo, hi per wheel
    for (int wheel = 0; wheel < 2; ++wheel) {
      double* predictions = scratch + (2 * u + static_cast<std::size_t>(wheel)) * b_count;
      double sum = 0.0;
      for (std::size_t b = 0; b < b_count; ++b) {
        sum += predictions[b];
      }
      values[wheel][0] = out.psi.row(wheel).dot(x);  // LR baseline Ψ̂Ẋ
      values[wheel][1] = sum / static_cast<double>(b_count);
      values[wheel][2] = sample_quantile(predictions, b_count, lower_p);
      values[wheel][3] = sample_quantile(predictions, b_count, upper_p);
    }
    BootstrapEstimate& e = estimates[u];
    e.lr_l = values[0][0];
    e.lr_r = values[1][0];
    e.boot_l = values[0][1];
    e.boot_r = values[1][1];
    e.ci_l_lo = values[0][2];
    e.ci_l_hi = values[0][3];
    e.ci_r_lo = values[1][2];
    e.ci_r_hi = values[1][3];
    // Table 1, r_L and r_R; undefined (not refused) where the LR estimate is 0.
    e.r_l_defined = ratio(e.boot_l, e.lr_l, e.r_l);
    e.r_r_defined = ratio(e.boot_r, e.lr_r, e.r_r);
  }
  fit_out = out;
  return BootstrapStatus::ok;
}

}  // namespace odocal::calib
