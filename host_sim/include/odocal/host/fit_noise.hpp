#pragma once
/// @file
/// The random part of odometry error, beside `odocal fit`'s geometry (DESIGN "Non-systematic
/// errors"): Chong & Kleeman's per-wheel model (ICRA 1997), each wheel's travel error a zero-mean
/// random walk in the distance it rolled, variance k_l·|s_l| and k_r·|s_r| (k in mm²/mm),
/// independent between wheels and along the path. Propagated along a logged path it gives the
/// covariance of the end pose; estimated by maximum likelihood from the end residuals of the
/// fit's runs; see docs/architecture.md for the derivation and its assumptions.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "odocal/host/fit.hpp"
#include "odocal/host/ros2_yaml.hpp"

namespace odocal::host {

/// Random wheel-travel error growth, mm² per mm rolled (variance of a wheel's travel error per
/// unit of distance that wheel rolled).
struct WheelNoise {
  double k_l = 0.0;
  double k_r = 0.0;
};

/// How the end pose of a stretch of a log responds to each wheel's travel errors: the end-pose
/// error covariance is k_l·left + k_r·right (x, y in mm, θ in rad; first order in the errors).
struct EndSensitivity {
  Eigen::Matrix3d left = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d right = Eigen::Matrix3d::Zero();
  Eigen::Vector3d start = Eigen::Vector3d::Zero();  ///< odometry pose at `first` (mm, mm, rad)
  Eigen::Vector3d end = Eigen::Vector3d::Zero();    ///< odometry pose at `last`
  double left_travel_mm = 0.0;  ///< |distance| each wheel rolled over the stretch
  double right_travel_mm = 0.0;
};

/// Integrates the odometry of rows [first, last] of `log` with `geometry` (the start pose: row
/// `first`'s ground truth when it has x, y and heading, else (0, 0, 0)) and sums, over every count
/// increment, the outer products of the end pose's derivatives with respect to that increment's
/// wheel travel, weighted by the travel. `first` < `last` < rows.
[[nodiscard]] EndSensitivity end_sensitivity(const TickLog& log, std::size_t first,
                                             std::size_t last, const FitNominal& nominal,
                                             const FitGeometry& geometry);

/// k_l·left + k_r·right.
[[nodiscard]] Eigen::Matrix3d end_covariance(const EndSensitivity& sensitivity,
                                             const WheelNoise& noise);

struct NoiseOptions {
  /// Runs with ground truth along the path are cut into stretches of at least this much travel
  /// (the mean of both wheels'), each restarting from its first row's ground truth.
  double stretch_mm = 2000.0;
  /// Heading residuals weigh as position residuals times this length (as FitOptions): the
  /// measurement noise is σ_m in x and y and σ_m / heading_length_mm rad in heading.
  double heading_length_mm = 286.4789;
  std::uint32_t replicates = 400;  ///< parametric bootstrap B for the intervals (0: none)
  std::uint64_t seed = 1;
  double level = 0.95;
};

/// The estimate: k_l, k_r and the measurement noise σ_m, by maximum likelihood over the stretches'
/// end residuals (measured minus the fitted geometry's odometry), Gaussian with covariance
/// k_l·A_l + k_r·A_r + σ_m²·M (M: the measurement's shape, at the end and, when a stretch starts
/// from a measured pose, propagated from its start).
struct NoiseEstimate {
  bool ok = false;
  std::string error;  ///< why not ok
  WheelNoise noise;
  double measure_sigma_mm = 0.0;
  bool has_ci = false;
  FitInterval ci_k_l, ci_k_r, ci_measure_sigma_mm;
  std::size_t stretches = 0;  ///< independent end residuals used
  std::size_t iterations = 0;
  std::uint32_t replicates = 0;
  double level = 0.95;
  double heading_length_mm = 0.0;
};

/// Estimates the random error growth from `runs` (checked tick logs) about `geometry` (the fit's).
/// Fails (ok false, error says why) with fewer than 3 stretches.
[[nodiscard]] NoiseEstimate estimate_wheel_noise(const std::vector<TickLog>& runs,
                                                 const FitNominal& nominal,
                                                 const FitGeometry& geometry,
                                                 const NoiseOptions& options);

/// `noise: {k_l, k_r, ci: {k_l: [lo, hi], k_r: [lo, hi], measure_sigma_mm: [...]},
/// measure_sigma_mm, units, stretches, model, ...}` (DESIGN "Odometry covariance").
[[nodiscard]] nlohmann::json noise_json(const NoiseEstimate& estimate);

/// diff_drive_controller's `pose_covariance_diagonal` and `twist_covariance_diagonal` (x, y, z,
/// roll, pitch, yaw; SI units) from the per-wheel model (docs/ros.md, "The covariances"): the
/// pose entries are the covariance after driving `distance_m` straight (along: (k_l+k_r)/4·d,
/// lateral: (k_l+k_r)/b²·d³/3, yaw: (k_l+k_r)/b²·d); the twist entries that of the controller's
/// own velocity estimate at `speed_mps` straight: the mean of W per-update differences is the
/// travel over W updates divided by W·T (T = 1/update rate), so each wheel's speed has variance
/// k·v/(W·T) (k·v·W·T of travel over (W·T)²): var(v) = (k_l+k_r)/4·v/(W·T), var(ω) =
/// (k_l+k_r)/b²·v/(W·T); lateral velocity as the forward one, the model having none. z, roll and
/// pitch, which odometry does not observe: `unobserved`.
struct Ros2Covariance {
  double pose[6] = {0, 0, 0, 0, 0, 0};
  double twist[6] = {0, 0, 0, 0, 0, 0};
};
[[nodiscard]] Ros2Covariance ros2_covariance(const WheelNoise& noise, double wheelbase_mm,
                                             double speed_mps, const RosVelocityEstimate& estimate,
                                             double distance_m, double unobserved = 1.0e6);
/// The YAML comment line (ending with a newline) that says what a Ros2Covariance was computed
/// from: the growths, the pose's distance, the twist's speed, and the controller's update rate
/// and rolling window.
[[nodiscard]] std::string ros2_covariance_note(const WheelNoise& noise, double distance_m,
                                               double speed_mps,
                                               const RosVelocityEstimate& estimate);
[[nodiscard]] std::string noise_text(const NoiseEstimate& estimate);

/// The noise estimate every fit reports beside its geometry (`odocal fit` and the sessions that
/// fit): `runs` about `fit`'s geometry, with the seed, level and heading length of `options` (the
/// fit's), and intervals (NoiseOptions' B) when the fit was asked for intervals (B > 0).
[[nodiscard]] NoiseEstimate noise_for_fit(const std::vector<TickLog>& runs, const FitResult& fit,
                                          const FitOptions& options);

/// The one JSON of a fit, whatever procedure made it (`odocal fit --json`, a session's `result`
/// with `--procedure fit`, its `result.fit` with `--procedure auto`): fit_result_json with
/// `noise` (noise_json). What `odocal ros2 --from` reads.
[[nodiscard]] nlohmann::json fit_json(const FitResult& fit, const NoiseEstimate& noise);

/// The same for people: fit_result_text, then noise_text.
[[nodiscard]] std::string fit_text(const FitResult& fit, const NoiseEstimate& noise);

}  // namespace odocal::host
