// `odocal fit`: how a heading residual weighs against a position residual. Where enough runs are
// measured at their end in x, y and heading (and nowhere along the path), the noise of each is
// estimated from the end residuals, each with its own degrees of freedom (residuals less their
// share of the leverage), and the fit is redone with their ratio until it settles; elsewhere the
// fixed weight (2 mm per 0.4°) stays (docs/calibration.md "Weights").

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "fit_steps.hpp"

namespace odocal::host::fit_detail {
namespace {

std::string format(const char* fmt, double a, double b = 0.0) {
  char text[320];
  std::snprintf(text, sizeof text, fmt, a, b);
  return text;
}

/// Position (per axis, mm) and heading (rad) noise from the residuals of `s`, each sum of squares
/// over its residuals less their share of the leverage: tr(A⁻¹·P) for the position rows and
/// tr(A⁻¹·hl²Θ) for the heading rows, A = P + hl²Θ the weighted information.
struct EndNoise {
  double position_sd_mm = 0.0;
  double heading_sd_rad = 0.0;
  double position_dof = 0.0;
  double heading_dof = 0.0;
};

EndNoise end_noise(const Solved& s) {
  const Normal& n = s.normal;
  const double hl2 = s.heading_length_mm * s.heading_length_mm;
  const Square scale = s.p.asDiagonal();
  const Square heading = scale * n.jtj_theta * scale * hl2;
  const Square position = scale * n.jtj * scale - heading;
  const Eigen::FullPivLU<Square> lu(position + heading);
  EndNoise e;
  if (!lu.isInvertible()) {
    return e;
  }
  const double leverage_position = (lu.inverse() * position).trace();
  const double leverage_heading = static_cast<double>(s.p.size()) - leverage_position;
  e.position_dof = static_cast<double>(n.residuals - n.theta_residuals) - leverage_position;
  e.heading_dof = static_cast<double>(n.theta_residuals) - leverage_heading;
  const double position_squares = std::max(n.cost - hl2 * n.cost_theta, 0.0);
  if (e.position_dof > 0.0 && e.heading_dof > 0.0) {
    e.position_sd_mm = std::sqrt(position_squares / e.position_dof);
    e.heading_sd_rad = std::sqrt(n.cost_theta / e.heading_dof);
  }
  return e;
}

}  // namespace

FitWeighting choose_weighting(const std::vector<Unit>& units, const ModelSpec& spec,
                              const FitOptions& o, const Design& design, Solved& fit) {
  FitWeighting w;
  w.heading_length_mm = o.heading_length_mm;
  w.runs = design.end_pose_runs;
  const std::string fixed = format("fixed weight %.1f mm per rad (%.3g mm per degree)",
                                   o.heading_length_mm, o.heading_length_mm * pi / 180.0);
  if (!o.estimate_weighting) {
    w.reason = fixed + ": asked for";
    return w;
  }
  if (design.path_truth > 0) {
    w.reason = fixed + format(
                           ": %.0f run(s) have ground truth along the path, whose rows are not "
                           "independent measurements (a run's odometry error carries on along it)",
                           static_cast<double>(design.path_truth));
    return w;
  }
  if (design.end_pose_runs < o.min_weighting_runs) {
    w.reason = fixed + format(
                           ": %.0f run(s) measured at their end in x, y and heading; estimating "
                           "the position and heading noise apart needs %.0f",
                           static_cast<double>(design.end_pose_runs),
                           static_cast<double>(o.min_weighting_runs));
    return w;
  }
  const double floor_rad = o.noise_floor_deg * pi / 180.0;
  Solved s = fit;
  EndNoise e;
  for (int round = 0; round < 6; ++round) {
    e = end_noise(s);
    if (!(e.position_dof >= 2.0 && e.heading_dof >= 2.0)) {
      w.reason = fixed + ": too few residuals left beside the parameters to estimate the noise";
      return w;
    }
    const double weight =
        std::max(e.position_sd_mm, o.noise_floor_mm) / std::max(e.heading_sd_rad, floor_rad);
    const bool settled = std::fabs(weight / s.heading_length_mm - 1.0) < 0.01;
    const std::vector<std::size_t> all = every_unit(units.size());
    const Solved next = solve(units, all, s.p, spec, weight);
    if (!next.ok) {
      w.reason = fixed + ": the fit with the estimated weight did not converge";
      return w;
    }
    s = next;
    if (settled) {
      break;
    }
  }
  e = end_noise(s);
  w.estimated = true;
  w.heading_length_mm = s.heading_length_mm;
  w.position_sd_mm = std::max(e.position_sd_mm, o.noise_floor_mm);
  w.heading_sd_deg = std::max(e.heading_sd_rad, floor_rad) * 180.0 / pi;
  w.position_dof = e.position_dof;
  w.heading_dof = e.heading_dof;
  w.reason =
      format("estimated from the end residuals of %.0f runs (%.0f or more needed)",
             static_cast<double>(design.end_pose_runs), static_cast<double>(o.min_weighting_runs));
  fit = s;
  return w;
}

Noise noise_in_force(const FitWeighting& w, const Solved& s, const FitOptions& o) {
  if (w.estimated) {
    return Noise{w.position_sd_mm, w.heading_sd_deg * pi / 180.0};
  }
  const std::size_t m = s.normal.residuals;
  const auto dofs = static_cast<std::size_t>(s.p.size());
  const double rms = m > dofs ? std::sqrt(s.normal.cost / static_cast<double>(m - dofs)) : 0.0;
  const double sigma = std::max(rms, o.noise_floor_mm);
  return Noise{sigma, sigma / s.heading_length_mm};
}

}  // namespace odocal::host::fit_detail
