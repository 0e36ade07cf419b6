#pragma once
/// @file
/// Multivariate linear calibration θ̇ = ΨẊ + ε and the nonparametric residual bootstrap of
/// Maddahi & Zareinia (IEEE Access 8, 2020, eq. 9-17, read as DESIGN says): least-squares fit of
/// each wheel on the training trials, residuals pooled and rescaled by sqrt(m/(m−p)), B refits on
/// resampled responses, and for each unknown Ẋ a prediction Ψ*Ẋ + ε* per replicate (eq. 16).
/// Hardware-free and heap-free: the caller lends the storage for the B predictions.

#include <cstddef>
#include <cstdint>

#include <Eigen/Core>

namespace odocal::calib {

/// One training trial: mean body velocity and the wheel velocities measured by the encoders.
struct TrainingRow {
  double xdot_mps = 0.0;
  double ydot_mps = 0.0;
  double thetadot_radps = 0.0;
  double omega_l_radps = 0.0;
  double omega_r_radps = 0.0;
};

/// One unknown: only the body velocity is observed.
struct UnknownRow {
  double xdot_mps = 0.0;
  double ydot_mps = 0.0;
  double thetadot_radps = 0.0;
};

/// Number of model parameters per wheel (p in eq. 10: α, β, γ).
inline constexpr std::size_t bootstrap_parameters = 3;
/// Fewest training rows accepted (m − p must leave residual degrees of freedom).
inline constexpr std::size_t bootstrap_min_training = 5;
/// Most training rows accepted.
inline constexpr std::size_t bootstrap_max_training = 100000;
/// Replicate count limits.
inline constexpr std::uint32_t bootstrap_min_replicates = 100;
inline constexpr std::uint32_t bootstrap_max_replicates = 1000000;

/// How the interval is taken from the B predictions.
enum class IntervalMethod : std::uint8_t {
  /// The paper's plain percentile interval at the requested level (DESIGN; the default). With
  /// m = 20 trials it covers a little less than the level (the resampled residuals are
  /// thinner-tailed than the t-distributed prediction error).
  percentile,
  /// Percentile interval at a widened level 2Φ(t_ν,q) − 1, where q = (1 + level)/2 and
  /// ν = 2(m − p) is the residual degrees of freedom of the pooled fit: the normal-theory
  /// small-sample correction, so the interval covers close to the requested level.
  calibrated_percentile,
};

/// Everything the bootstrap needs.
struct BootstrapInput {
  const TrainingRow* training = nullptr;
  std::size_t training_count = 0;  ///< m >= bootstrap_min_training
  const UnknownRow* unknowns = nullptr;
  std::size_t unknown_count = 0;    ///< >= 1
  std::uint32_t replicates = 1000;  ///< B
  std::uint64_t seed = 1;
  double level = 0.95;  ///< interval level, in (0, 1)
  IntervalMethod method = IntervalMethod::percentile;
  /// Storage for the predictions: at least bootstrap_scratch_count(replicates, unknown_count).
  double* scratch = nullptr;
  std::size_t scratch_count = 0;
};

/// Doubles of scratch the bootstrap needs: 2·B·(number of unknowns).
[[nodiscard]] constexpr std::size_t bootstrap_scratch_count(std::uint32_t replicates,
                                                            std::size_t unknown_count) {
  return std::size_t{2} * replicates * unknown_count;
}

/// Estimates for one unknown (Table 1 columns), rad/s unless noted.
struct BootstrapEstimate {
  double lr_l = 0.0, lr_r = 0.0;      ///< linear-regression baseline Ψ̂Ẋ
  double boot_l = 0.0, boot_r = 0.0;  ///< mean of the B bootstrap predictions
  double ci_l_lo = 0.0, ci_l_hi = 0.0;
  double ci_r_lo = 0.0, ci_r_hi = 0.0;
  /// boot / lr per wheel (dimensionless); meaningful only when the matching `*_defined` is true.
  double r_l = 1.0, r_r = 1.0;
  /// False when that wheel's LR estimate is 0 (e.g. an unknown standing still, Ẋ = 0) or the
  /// quotient is not finite: the ratio is undefined and r is left at 0.
  bool r_l_defined = true, r_r_defined = true;
};

/// The fitted model and what the intervals used.
struct BootstrapFit {
  Eigen::Matrix<double, 2, 3> psi = Eigen::Matrix<double, 2, 3>::Zero();  ///< rows: left, right
  double residual_scale = 1.0;                                            ///< sqrt(m/(m−p))
  double residual_rms = 0.0;     ///< RMS of the pooled rescaled residuals, rad/s
  double effective_level = 0.0;  ///< percentile level actually taken (>= level if calibrated)
};

/// Why a fit or bootstrap was refused. Nothing is written to the outputs unless `ok`.
enum class BootstrapStatus : std::uint8_t {
  ok,
  too_few_rows,       ///< training rows outside [min, max]_training, or no unknowns
  non_finite,         ///< a NaN or Inf in a row
  degenerate,         ///< the training design Ẋ is rank deficient (or nearly so)
  bad_replicates,     ///< B outside [bootstrap_min_replicates, bootstrap_max_replicates]
  bad_level,          ///< level not in (0, 1)
  scratch_too_small,  ///< scratch missing or shorter than bootstrap_scratch_count
};

/// A short lower-case message for a status.
[[nodiscard]] const char* to_string(BootstrapStatus status);

/// Least-squares fit of eq. 10 (one row of Ψ per wheel) on the training rows; also fills the
/// residual scale and RMS. Needs m >= bootstrap_min_training and a well-conditioned design.
[[nodiscard]] BootstrapStatus fit_wheel_model(const TrainingRow* training, std::size_t count,
                                              BootstrapFit& fit);

/// Runs the bootstrap and writes one estimate per unknown into `estimates`
/// (`estimates_count` >= `input.unknown_count`). Deterministic for a seed. The predictions of
/// unknown u, wheel w, replicate b are left in scratch[(2u + w)·B + b] (partially reordered).
[[nodiscard]] BootstrapStatus run_bootstrap(const BootstrapInput& input,
                                            BootstrapEstimate* estimates,
                                            std::size_t estimates_count, BootstrapFit& fit);

/// The level whose normal quantile equals the Student-t quantile with `dof` degrees of freedom
/// at `level` (two-sided): 2Φ(t_dof,(1+level)/2) − 1. Returns `level` unchanged when dof <= 0.
[[nodiscard]] double t_calibrated_level(double level, double dof);

}  // namespace odocal::calib
