// `odocal fit`: what the logs determine, from the eigen-decomposition of the column-scaled JᵀJ
// (the scaled Jacobian's SVD), and why a parameter is not determined, in the user's words.

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "fit_steps.hpp"

namespace odocal::host::fit_detail {
namespace {

/// Why the logs fix a parameter direction `dir` (eigenvector of the scaled JᵀJ) only to the
/// relative standard deviation `sd`: the parameter it moves most, and what to add to the runs.
FitError undetermined(const Params& dir, double sd, FitModelKind kind, double turned_rad) {
  FitError error;
  const double along_scale = std::fabs(dir.head(3).sum()) / std::sqrt(3.0);
  char amount[64];
  if (std::isfinite(sd) && sd < 1e6) {
    std::snprintf(amount, sizeof amount, "±%.3g %%", 100.0 * sd);
  } else {
    std::snprintf(amount, sizeof amount, "not at all");
  }
  if (along_scale >= 0.8) {
    error.parameter = "scale";
    error.message =
        std::string(
            "the logs cannot determine the overall scale (wheel_diameter_left_mm, "
            "wheel_diameter_right_mm and wheelbase_mm together): they fix it only ") +
        amount +
        " — closed loops measured only at the end look the same at any size; add straight "
        "runs of known length or ground truth along the path";
    return error;
  }
  Eigen::Index worst = 0;
  dir.cwiseAbs().maxCoeff(&worst);
  const char* name = parameter_name(kind, static_cast<int>(worst));
  error.parameter = name;
  std::string why;
  if (worst == 3) {
    why = kind == FitModelKind::arc_wheelbase
              ? " — the logs hold only one kind of turning (turns in place or arcs): "
                "drive both to tell their wheelbases apart"
              : " — the logs turn at too narrow a range of turn rates";
  } else if (turned_rad < 0.5 * pi) {
    why =
        " — the runs hardly turn (straight lines alone say nothing about the "
        "wheelbase); add turns, squares or loops";
  } else if (std::fabs(dir[2]) > 0.3 && std::fabs(dir[0] - dir[1]) > 0.3) {
    // Turning at one curvature: the heading fixes (D_R − D_L)/b, the path's length the
    // mean diameter, and nothing tells the wheel difference from the wheelbase.
    why =
        " — the runs turn, but always at one curvature (one arc or circle): that fixes "
        "the ratio of the wheels' difference to the wheelbase, not each; add turns in "
        "place, straight lines or arcs of another radius";
  } else {
    why = " — add runs that move each wheel over a known distance";
  }
  error.message =
      std::string("the logs cannot determine ") + name + ": they fix it only " + amount + why;
  return error;
}

}  // namespace

Determination determination(const Solved& s, const FitOptions& o, FitModelKind kind,
                            double turned_rad, bool use_residuals) {
  Determination d;
  const int np = static_cast<int>(s.p.size());
  const Square scale = s.p.asDiagonal();
  const Square a = scale * s.normal.jtj * scale;  // JᵀJ of ∂r/∂ln p
  const std::size_t m = s.normal.residuals;
  const auto dofs = static_cast<std::size_t>(np);
  const double rms = m > dofs ? std::sqrt(s.normal.cost / static_cast<double>(m - dofs)) : 0.0;
  const double sigma = use_residuals ? std::max(rms, o.noise_floor_mm) : o.noise_floor_mm;
  Eigen::SelfAdjointEigenSolver<Square> eig(a);
  const Params values = eig.eigenvalues();  // ascending
  const double largest = std::max(values[np - 1], 1e-300);
  for (int j = 0; j < np; ++j) {
    const double v = values[j];
    const double sd = v > largest * 1e-24 ? sigma / std::sqrt(v) : HUGE_VAL;
    if (!(sd <= o.max_relative_sd)) {  // NaN too
      d.ok = false;
      d.error = undetermined(eig.eigenvectors().col(j), sd, kind, turned_rad);
      break;
    }
  }
  const Eigen::FullPivLU<Square> lu(a);
  if (lu.isInvertible()) {
    const Square cov = lu.inverse() * sigma * sigma;
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
  return d;
}

}  // namespace odocal::host::fit_detail
