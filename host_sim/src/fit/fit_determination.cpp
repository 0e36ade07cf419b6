// `odocal fit`: what the logs determine, from the eigen-decomposition of the column-scaled JᵀJ
// (the scaled Jacobian's SVD). The design is judged at the noise floor (a refusal); the residual
// scatter only widens the covariance (a warning).

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "fit_steps.hpp"

namespace odocal::host::fit_detail {
namespace {

/// JᵀJ of ∂r/∂ln p with position residuals divided by `noise.position_mm` and heading residuals
/// (rad) by `noise.heading_rad`: the inverse of the relative covariance.
Square information(const Solved& s, const Noise& noise) {
  const Normal& n = s.normal;
  const Square scale = s.p.asDiagonal();
  const double hl = s.heading_length_mm;
  const Square position = n.jtj - hl * hl * n.jtj_theta;
  const Square raw = position / (noise.position_mm * noise.position_mm) +
                     n.jtj_theta / (noise.heading_rad * noise.heading_rad);
  return scale * raw * scale;
}

/// The loosest direction of `a`: its relative standard deviation and eigenvector.
struct Loosest {
  double sd = 0.0;
  Params dir;
};

Loosest loosest(const Square& a) {
  const int np = static_cast<int>(a.rows());
  Eigen::SelfAdjointEigenSolver<Square> eig(a);
  const Params values = eig.eigenvalues();  // ascending
  const double largest = std::max(values[np - 1], 1e-300);
  const double v = values[0];
  return Loosest{v > largest * 1e-24 ? 1.0 / std::sqrt(v) : HUGE_VAL, eig.eigenvectors().col(0)};
}

}  // namespace

Determination determination(const Solved& s, const FitOptions& o, FitModelKind kind,
                            const Design* design) {
  Determination d;
  const Noise floor{o.noise_floor_mm, o.noise_floor_deg * pi / 180.0};
  const Loosest worst = loosest(information(s, floor));
  if (!(worst.sd <= o.max_relative_sd)) {  // NaN too
    d.ok = false;
    if (design != nullptr) {
      d.error = undetermined(worst.dir, worst.sd, kind, *design);
    }
  }
  return d;
}

void add_scatter(Determination& d, const Solved& s, const FitOptions& o, FitModelKind kind,
                 const Noise& noise) {
  const int np = static_cast<int>(s.p.size());
  const Square a = information(s, noise);
  const Eigen::FullPivLU<Square> lu(a);
  if (lu.isInvertible()) {
    const Square cov = lu.inverse();
    for (int i = 0; i < np; ++i) {
      d.relative_sd[i] = std::sqrt(std::max(cov(i, i), 0.0));
      for (int j = 0; j < np; ++j) {
        d.relative_cov[i][j] = cov(i, j);
      }
    }
  } else {
    for (double& sd : d.relative_sd) {
      sd = HUGE_VAL;
    }
  }
  const Loosest worst = loosest(a);
  if (worst.sd <= o.max_relative_sd) {
    return;
  }
  const double along_scale = std::fabs(worst.dir.head(3).sum()) / std::sqrt(3.0);
  Eigen::Index index = 0;
  worst.dir.cwiseAbs().maxCoeff(&index);
  const std::string name = along_scale >= 0.8 ? std::string("the overall scale")
                                              : parameter_name(kind, static_cast<int>(index));
  // What the residuals are, as measured (RMS, not weighted): the scatter the warning names.
  const Normal& n = s.normal;
  const double hl2 = s.heading_length_mm * s.heading_length_mm;
  const std::size_t position_residuals = n.residuals - n.theta_residuals;
  const double position_rms = position_residuals > 0
                                  ? std::sqrt(std::max(n.cost - hl2 * n.cost_theta, 0.0) /
                                              static_cast<double>(position_residuals))
                                  : 0.0;
  const double heading_rms_deg =
      n.theta_residuals > 0
          ? std::sqrt(n.cost_theta / static_cast<double>(n.theta_residuals)) * 180.0 / pi
          : 0.0;
  char text[512];
  std::snprintf(text, sizeof text,
                "large scatter: the runs scatter about the fit by %.3g mm in x and y and %.3g° in "
                "heading (RMS; the noise floor is %.3g mm and %.3g°), which leaves %s known only "
                "to ±%.3g %% (wide intervals); the runs' design determines it, so the result is "
                "given: look for what varied between runs (slip, floor, measurement) or add runs",
                position_rms, heading_rms_deg, o.noise_floor_mm, o.noise_floor_deg, name.c_str(),
                100.0 * worst.sd);
  d.warning = text;
}

}  // namespace odocal::host::fit_detail
