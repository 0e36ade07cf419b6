#include "odocal/host/extended_figure.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "odocal/calib/quantile.hpp"

namespace odocal::host {
namespace {

struct Moments {
  double mean = 0.0;
  double variance = 0.0;  ///< sample variance (n − 1)
};

template <typename Value>
Moments moments(const std::vector<ExtendedRun>& runs, Value value) {
  Moments m;
  const auto n = static_cast<double>(runs.size());
  for (const ExtendedRun& r : runs) {
    m.mean += value(r);
  }
  m.mean /= n;
  for (const ExtendedRun& r : runs) {
    m.variance += (value(r) - m.mean) * (value(r) - m.mean);
  }
  m.variance /= n - 1.0;
  return m;
}

}  // namespace

bool extended_figure(const std::vector<ExtendedRun>& reference_cw,
                     const std::vector<ExtendedRun>& reference_ccw,
                     const std::vector<ExtendedRun>& bumps_cw,
                     const std::vector<ExtendedRun>& bumps_ccw, ExtendedFigure& figure) {
  for (const auto* runs : {&reference_cw, &reference_ccw, &bumps_cw, &bumps_ccw}) {
    if (runs->size() < 2) {
      return false;
    }
  }
  ExtendedFigure f;
  // Each direction: e = mean |θ_i − θ̄_ref|. Its variance from the run-to-run scatter: that of
  // the |d_i| over the bump runs, plus the reference mean's, weighted by how much e moves with
  // it (the mean sign of the d_i); the degrees of freedom by Welch-Satterthwaite.
  double variance = 0.0;
  double dof_denominator = 0.0;
  const auto theta = [](const ExtendedRun& r) { return r.theta_error_deg; };
  const std::pair<const std::vector<ExtendedRun>*, const std::vector<ExtendedRun>*> sides[2] = {
      {&reference_cw, &bumps_cw}, {&reference_ccw, &bumps_ccw}};
  for (int side = 0; side < 2; ++side) {
    const auto& [reference, bumps] = sides[side];
    const Moments ref = moments(*reference, theta);
    const Moments deviation = moments(
        *bumps, [&](const ExtendedRun& r) { return std::fabs(r.theta_error_deg - ref.mean); });
    double sign = 0.0;
    for (const ExtendedRun& r : *bumps) {
      sign += r.theta_error_deg >= ref.mean ? 1.0 : -1.0;
    }
    sign /= static_cast<double>(bumps->size());
    const double nb = static_cast<double>(bumps->size());
    const double nr = static_cast<double>(reference->size());
    const double v_bumps = deviation.variance / nb;
    const double v_reference = sign * sign * ref.variance / nr;
    variance += v_bumps + v_reference;
    dof_denominator += v_bumps * v_bumps / (nb - 1.0) + v_reference * v_reference / (nr - 1.0);
    (side == 0 ? f.reference_cw_deg : f.reference_ccw_deg) = ref.mean;
    (side == 0 ? f.e_cw_deg : f.e_ccw_deg) = deviation.mean;
  }
  f.e_nonsys_deg = f.e_cw_deg + f.e_ccw_deg;
  f.sd_deg = std::sqrt(variance);
  const double dof = dof_denominator > 0.0 ? variance * variance / dof_denominator : 1e6;
  const double t = calib::student_t_quantile(0.975, std::max(dof, 1.0));
  f.ci_lo_deg = std::max(0.0, f.e_nonsys_deg - t * f.sd_deg);
  f.ci_hi_deg = f.e_nonsys_deg + t * f.sd_deg;
  figure = f;
  return true;
}

void extended_bump_layout(double side_m, std::size_t count, double& first_m, double& spacing_m) {
  spacing_m = side_m / static_cast<double>(count);
  first_m = 0.5 * spacing_m;
}

}  // namespace odocal::host
