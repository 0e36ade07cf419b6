#pragma once
// Internal to host_sim/src/fit: intervals for the fitted geometry from the runs as independent
// clusters. See fit_interval.cpp.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "fit_model.hpp"

namespace odocal::host::fit_detail {

/// Residuals and Jacobian rows of one bootstrap unit at the fitted parameters.
struct UnitRows {
  Eigen::MatrixXd jacobian;  ///< ∂r/∂(parameters), one row per residual
  Eigen::VectorXd residual;  ///< model − ground truth (mm; heading × heading_length_mm)
};

/// Collects every unit's residuals and Jacobian rows at `p`.
[[nodiscard]] std::vector<UnitRows> unit_rows(const std::vector<Unit>& units, const Params& p,
                                              const ModelSpec& spec, double heading_length_mm);

/// What the interval computation gives per parameter.
struct ClusterInterval {
  bool ok = false;
  double se[4] = {0, 0, 0, 0};   ///< CR2 cluster-robust standard error, relative to p
  double dof[4] = {0, 0, 0, 0};  ///< Bell-McCaffrey degrees of freedom
  double lo[4] = {0, 0, 0, 0};   ///< wild bootstrap-t interval ends
  double hi[4] = {0, 0, 0, 0};
  double t_lo[4] = {0, 0, 0, 0};  ///< Student-t (Bell-McCaffrey) interval ends
  double t_hi[4] = {0, 0, 0, 0};
  double cov[4][4] = {};  ///< the CR2 covariance itself, relative to p (se is its diagonal's root)
};

/// Wild cluster bootstrap-t: the units' (CR2-adjusted) residuals are multiplied by one random
/// weight per unit (Webb's six-point distribution), the linearised fit is redone and studentized by
/// its own CR2 standard error, B times; the interval is p̂ − t*·se with the t* quantiles. Also the
/// Student-t interval with the Bell-McCaffrey degrees of freedom (fit_geometry takes the wider
/// end of the two). Not ok with fewer than 2 units.
[[nodiscard]] ClusterInterval cluster_interval(const std::vector<UnitRows>& rows, const Params& p,
                                               std::uint32_t replicates, std::uint64_t seed,
                                               double level);

}  // namespace odocal::host::fit_detail
