// `odocal fit`: Levenberg-Marquardt on the tick logs, identifiability from the scaled Jacobian,
// bootstrap over runs.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <thread>

#include "fit_interval.hpp"
#include "fit_model.hpp"
#include "odocal/calib/random.hpp"
#include "odocal/host/fit.hpp"

namespace odocal::host {
namespace {

using fit_detail::Normal;
using fit_detail::Params;
using fit_detail::Unit;

const char* const parameter_names[3] = {"wheel_diameter_left_mm", "wheel_diameter_right_mm",
                                        "wheelbase_mm"};

struct Solved {
  bool ok = false;
  Params p = Params::Zero();
  Normal normal;  ///< at p, with the Jacobian
  std::size_t iterations = 0;
};

/// Levenberg-Marquardt (Marquardt's diagonal scaling) from `start`.
Solved solve(const std::vector<Unit>& units, const std::vector<std::size_t>& pick,
             const Params& start, double k, double heading_length_mm) {
  Solved out;
  Params p = start;
  Normal n = fit_detail::normal_equations(units, pick, p, k, heading_length_mm, true);
  double lambda = 1e-4;
  for (std::size_t it = 0; it < 200; ++it) {
    out.iterations = it + 1;
    if (!std::isfinite(n.cost)) {
      return out;
    }
    Eigen::Matrix3d a = n.jtj;
    for (int i = 0; i < 3; ++i) {
      a(i, i) += lambda * std::max(n.jtj(i, i), 1e-30);
    }
    const Params step = a.ldlt().solve(-n.jtr);
    const Params trial = p + step;
    if (!step.allFinite() || !(trial.minCoeff() > 0.0)) {
      lambda *= 10.0;
      if (lambda > 1e12) {
        break;
      }
      continue;
    }
    // Steps below 1e-10 of a parameter are far below anything a log can tell: converged.
    const double relative_step = (step.array().abs() / p.array()).maxCoeff();
    if (relative_step < 1e-10) {
      break;
    }
    const Normal m = fit_detail::normal_equations(units, pick, trial, k, heading_length_mm, true);
    if (std::isfinite(m.cost) && m.cost <= n.cost) {
      const bool flat = n.cost - m.cost <= 1e-12 * n.cost;
      p = trial;
      n = m;
      lambda = std::max(lambda * 0.1, 1e-12);
      if (flat || relative_step < 1e-9) {
        break;
      }
    } else {
      lambda *= 10.0;
      if (lambda > 1e12 || relative_step < 1e-9) {
        break;  // no step lowers the cost: at the minimum to working precision
      }
    }
  }
  out.ok = std::isfinite(n.cost) && p.allFinite() && p.minCoeff() > 0.0;
  out.p = p;
  out.normal = n;
  return out;
}

/// Relative (log-parameter) covariance directions: what the data determine, and how well.
struct Determination {
  bool ok = true;
  FitError error;
  double relative_sd[3] = {0, 0, 0};
};

/// @param use_residuals take the residual scatter as the noise when it exceeds the floor (at the
///        fitted geometry; at the nominal one the residuals are the systematic error itself).
Determination determination(const Solved& s, const FitOptions& o, bool use_residuals = true) {
  Determination d;
  const Eigen::Matrix3d scale = s.p.asDiagonal();
  const Eigen::Matrix3d a = scale * s.normal.jtj * scale;  // JᵀJ of ∂r/∂ln p
  const std::size_t m = s.normal.residuals;
  const double rms = m > 3 ? std::sqrt(s.normal.cost / static_cast<double>(m - 3)) : 0.0;
  const double sigma = use_residuals ? std::max(rms, o.noise_floor_mm) : o.noise_floor_mm;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(a);
  const Eigen::Vector3d values = eig.eigenvalues();  // ascending
  const double largest = std::max(values[2], 1e-300);
  for (int j = 0; j < 3; ++j) {
    const double v = values[j];
    const double sd = v > largest * 1e-24 ? sigma / std::sqrt(v) : HUGE_VAL;
    if (sd <= o.max_relative_sd) {
      continue;
    }
    const Eigen::Vector3d dir = eig.eigenvectors().col(j);
    const double along_scale = std::fabs(dir.sum()) / std::sqrt(3.0);
    d.ok = false;
    char amount[64];
    if (std::isfinite(sd) && sd < 1e6) {
      std::snprintf(amount, sizeof amount, "±%.3g %%", 100.0 * sd);
    } else {
      std::snprintf(amount, sizeof amount, "not at all");
    }
    if (along_scale >= 0.8) {
      d.error.parameter = "scale";
      d.error.message =
          std::string(
              "the logs cannot determine the overall scale (wheel_diameter_left_mm, "
              "wheel_diameter_right_mm and wheelbase_mm together): they fix it only ") +
          amount +
          " — closed loops measured only at the end look the same at any size; add straight "
          "runs of known length or ground truth along the path";
    } else {
      Eigen::Index worst = 0;
      dir.cwiseAbs().maxCoeff(&worst);
      d.error.parameter = parameter_names[worst];
      d.error.message =
          std::string("the logs cannot determine ") + parameter_names[worst] +
          ": they fix it only " + amount +
          (worst == 2 ? " — the runs hardly turn (straight lines alone say nothing about the "
                        "wheelbase); add turns, squares or loops"
                      : " — add runs that move each wheel over a known distance");
    }
    break;
  }
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(a);
  if (lu.isInvertible()) {
    const Eigen::Matrix3d cov = lu.inverse() * sigma * sigma;
    for (int i = 0; i < 3; ++i) {
      d.relative_sd[i] = std::sqrt(std::max(cov(i, i), 0.0));
    }
  } else {
    for (double& sd : d.relative_sd) {
      sd = HUGE_VAL;
    }
  }
  return d;
}

/// Whole runs as units.
std::vector<Unit> whole_runs(const std::vector<TickLog>& logs) {
  std::vector<Unit> units;
  for (const TickLog& log : logs) {
    units.push_back(Unit{&log, 0, log.rows.size()});
  }
  return units;
}

/// Bootstrap units: whole runs, or, with fewer runs than `min_units`, the runs with ground truth
/// along the path cut at full-pose rows into pieces of equal numbers of ground-truth rows.
std::vector<Unit> bootstrap_units(const std::vector<TickLog>& logs, std::size_t min_units) {
  if (logs.size() >= min_units) {
    return whole_runs(logs);
  }
  const std::size_t pieces = (min_units + logs.size() - 1) / logs.size();
  constexpr std::size_t min_rows_per_piece = 5;
  std::vector<Unit> units;
  for (const TickLog& log : logs) {
    std::vector<std::size_t> starts;  // rows with a full pose, after the first
    for (std::size_t i = 1; i + 1 < log.rows.size(); ++i) {
      if (log.rows[i].has_xy && log.rows[i].has_theta) {
        starts.push_back(i);
      }
    }
    if (pieces < 2 || starts.size() < pieces * min_rows_per_piece) {
      units.push_back(Unit{&log, 0, log.rows.size()});
      continue;
    }
    std::size_t begin = 0;
    for (std::size_t j = 1; j <= pieces; ++j) {
      const std::size_t end = j == pieces ? log.rows.size() : starts[j * starts.size() / pieces];
      units.push_back(Unit{&log, begin, j == pieces ? end : end + 1});
      begin = end;
    }
  }
  return units;
}

/// Type-7 quantile of sorted values.
double quantile(const std::vector<double>& sorted, double probability) {
  const double h = (static_cast<double>(sorted.size()) - 1.0) * probability;
  const auto lo = static_cast<std::size_t>(std::floor(h));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (h - static_cast<double>(lo)) * (sorted[hi] - sorted[lo]);
}

/// Percentile interval of the bootstrap values, each end moved away from the estimate by
/// `widen` (the small-sample correction, see fit_geometry).
FitInterval interval(std::vector<double> values, double level, double estimate, double widen) {
  std::sort(values.begin(), values.end());
  const double tail = 0.5 * (1.0 - level);
  const double lo = quantile(values, tail);
  const double hi = quantile(values, 1.0 - tail);
  return FitInterval{std::min(lo, estimate - widen * (estimate - lo)),
                     std::max(hi, estimate + widen * (hi - estimate))};
}

/// One bootstrap replicate: resample units with replacement (drawing again, at most 50 times,
/// when a resample cannot determine the parameters) and refit from the full fit.
bool replicate(const std::vector<Unit>& units, const Params& start, double k, const FitOptions& o,
               std::uint32_t index, Params& p, std::uint32_t& redrawn) {
  calib::Random random(o.seed ^ (0x9E3779B97F4A7C15ull * (static_cast<std::uint64_t>(index) + 1)));
  std::vector<std::size_t> pick(units.size());
  for (std::uint32_t attempt = 0; attempt < 50; ++attempt) {
    for (std::size_t& u : pick) {
      u = random.below(static_cast<std::uint32_t>(units.size()));
    }
    const Solved s = solve(units, pick, start, k, o.heading_length_mm);
    if (s.ok && determination(s, o).ok) {
      p = s.p;
      return true;
    }
    ++redrawn;
  }
  return false;
}

}  // namespace

FitFigures score_runs(const std::vector<TickLog>& runs, const FitNominal& nominal,
                      const FitGeometry& g, double /*heading_length_mm*/) {
  FitFigures f;
  f.runs = runs.size();
  const double k = fit_detail::pi / nominal.counts_per_rev;
  const Params before(nominal.wheel_diameter_mm, nominal.wheel_diameter_mm, nominal.wheelbase_mm);
  const Params after(g.wheel_diameter_left_mm, g.wheel_diameter_right_mm, g.wheelbase_mm);
  const std::vector<Unit> units = whole_runs(runs);
  for (int which = 0; which < 2; ++which) {
    double end_sum = 0.0, path_sum = 0.0;
    std::size_t end_n = 0, path_n = 0;
    for (const Unit& u : units) {
      double last = -1.0;
      fit_detail::integrate(u, which == 0 ? before : after, k, false,
                            [&](const TickRow& row, const fit_detail::ModelState& s) {
                              if (row.has_xy) {
                                last = std::hypot(s.x - row.x_mm, s.y - row.y_mm);
                                path_sum += last * last;
                                ++path_n;
                              }
                            });
      if (last >= 0.0) {
        end_sum += last * last;
        ++end_n;
      }
    }
    const double end = end_n > 0 ? std::sqrt(end_sum / static_cast<double>(end_n)) : 0.0;
    const double path = path_n > 0 ? std::sqrt(path_sum / static_cast<double>(path_n)) : 0.0;
    (which == 0 ? f.end_rms_before_mm : f.end_rms_after_mm) = end;
    (which == 0 ? f.path_rms_before_mm : f.path_rms_after_mm) = path;
  }
  return f;
}

FitOutcome fit_geometry(const std::vector<TickLog>& runs, const FitNominal& nominal,
                        const FitOptions& o, const std::vector<TickLog>& holdout) {
  FitOutcome out;
  if (runs.empty()) {
    out.error = FitError{"", "no runs to fit"};
    return out;
  }
  if (!(nominal.wheel_diameter_mm > 0.0 && nominal.wheelbase_mm > 0.0 &&
        nominal.counts_per_rev > 0.0) ||
      !(o.level > 0.0 && o.level < 1.0) || !(o.heading_length_mm >= 0.0)) {
    out.error = FitError{"", "the nominal geometry and options must be positive"};
    return out;
  }
  const double k = fit_detail::pi / nominal.counts_per_rev;
  const std::vector<Unit> units = whole_runs(runs);
  std::vector<std::size_t> all(units.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    all[i] = i;
  }
  const Params start(nominal.wheel_diameter_mm, nominal.wheel_diameter_mm, nominal.wheelbase_mm);
  // What the runs can determine, judged first at the nominal geometry: where a parameter is
  // undetermined the fit may wander along it and hide which one it was.
  Solved at_start;
  at_start.p = start;
  at_start.normal = fit_detail::normal_equations(units, all, start, k, o.heading_length_mm, true);
  if (const Determination first = determination(at_start, o, false); !first.ok) {
    out.error = first.error;
    return out;
  }
  const Solved main = solve(units, all, start, k, o.heading_length_mm);
  if (!main.ok) {
    out.error = FitError{"",
                         "the fit did not converge to a physical geometry (check the logs' "
                         "units: counts, mm, degrees)"};
    return out;
  }
  const Determination d = determination(main, o);
  if (!d.ok) {
    out.error = d.error;
    return out;
  }
  FitResult r;
  r.nominal = nominal;
  r.geometry = FitGeometry{main.p[0], main.p[1], main.p[2]};
  r.c_l = main.p[0] / nominal.wheel_diameter_mm;
  r.c_r = main.p[1] / nominal.wheel_diameter_mm;
  r.e_d = main.p[1] / main.p[0];
  r.e_b = main.p[2] / nominal.wheelbase_mm;
  r.level = o.level;
  r.seed = o.seed;
  r.heading_length_mm = o.heading_length_mm;
  r.iterations = main.iterations;
  for (int i = 0; i < 3; ++i) {
    r.relative_sd[i] = d.relative_sd[i];
  }
  r.fit = score_runs(runs, nominal, r.geometry, o.heading_length_mm);
  if (!holdout.empty()) {
    r.holdout = score_runs(holdout, nominal, r.geometry, o.heading_length_mm);
  }

  fit_detail::ClusterInterval ci;
  if (o.replicates > 0 && o.interval != FitIntervalMethod::percentile) {
    const std::vector<Unit> boot = bootstrap_units(runs, o.min_units);
    ci = fit_detail::cluster_interval(fit_detail::unit_rows(boot, main.p, k, o.heading_length_mm),
                                      main.p, o.replicates, o.seed, o.level);
    r.interval = o.interval;
    r.bootstrap_units = boot.size();
  }
  // One unit (a single tape-measure run) shows no scatter between runs: no intervals.
  if (ci.ok) {
    r.replicates = o.replicates;
    for (int i = 0; i < 3; ++i) {
      r.cluster_sd[i] = ci.se[i];
      r.dof[i] = ci.dof[i];
    }
    const bool wild = o.interval == FitIntervalMethod::wild_t;
    FitInterval c[3];
    for (int i = 0; i < 3; ++i) {
      // The bootstrap-t percentiles follow skewed or heavy-tailed errors; with few runs the
      // wild bootstrap (unrestricted residuals) undercuts the variance of its own standard
      // error, which the Bell-McCaffrey Student t accounts for: neither end is left narrower.
      c[i] = FitInterval{ci.t_lo[i], ci.t_hi[i]};
      if (wild) {
        c[i] = FitInterval{std::min(ci.lo[i], ci.t_lo[i]), std::max(ci.hi[i], ci.t_hi[i])};
      }
    }
    const double d = nominal.wheel_diameter_mm;
    r.ci_left_mm = c[0];
    r.ci_right_mm = c[1];
    r.ci_wheelbase_mm = c[2];
    r.ci_c_l = FitInterval{c[0].lo / d, c[0].hi / d};
    r.ci_c_r = FitInterval{c[1].lo / d, c[1].hi / d};
  } else if (o.replicates > 0 && o.interval == FitIntervalMethod::percentile) {
    const std::vector<Unit> boot = bootstrap_units(runs, o.min_units);
    r.interval = o.interval;
    r.bootstrap_units = boot.size();
    r.replicates = o.replicates;
    std::vector<Params> estimates(o.replicates);
    std::vector<char> done(o.replicates, 0);
    std::vector<std::uint32_t> redrawn(2, 0);
    std::vector<std::size_t> finished(2, 0);
    // Two threads, replicates interleaved; each replicate has its own random stream, so the
    // intervals do not depend on the thread count.
    const auto work = [&](unsigned t) {
      for (std::uint32_t b = t; b < o.replicates; b += 2) {
        done[b] = replicate(boot, main.p, k, o, b, estimates[b], redrawn[t]) ? 1 : 0;
        if (++finished[t] % 50 == 0 && t == 0 && o.progress) {
          o.progress("fit: bootstrap " + std::to_string(2 * finished[t]) + "/" +
                     std::to_string(o.replicates));
        }
      }
    };
    std::thread helper(work, 1u);
    work(0u);
    helper.join();
    r.redrawn = redrawn[0] + redrawn[1];
    std::vector<double> column[5];
    for (std::uint32_t b = 0; b < o.replicates; ++b) {
      if (done[b] == 0) {
        continue;
      }
      for (int i = 0; i < 3; ++i) {
        column[i].push_back(estimates[b][i]);
      }
      column[3].push_back(estimates[b][0] / nominal.wheel_diameter_mm);
      column[4].push_back(estimates[b][1] / nominal.wheel_diameter_mm);
    }
    if (column[0].size() < 2) {
      out.error = FitError{"",
                           "no bootstrap resample of the runs determines the geometry: "
                           "give more runs"};
      return out;
    }
    // Resampling n units spreads a fit of p = 3 parameters by about (n − p)/n of its true
    // variance (as residuals underestimate the noise by that much): widen each end by
    // sqrt(n/(n − p)) about the estimate, as the Maddahi bootstrap scales its residuals.
    const double n = static_cast<double>(boot.size());
    r.widen = n > 4.0 ? std::sqrt(n / (n - 3.0)) : 2.0;
    const double d = nominal.wheel_diameter_mm;
    r.ci_left_mm = interval(column[0], o.level, main.p[0], r.widen);
    r.ci_right_mm = interval(column[1], o.level, main.p[1], r.widen);
    r.ci_wheelbase_mm = interval(column[2], o.level, main.p[2], r.widen);
    r.ci_c_l = interval(column[3], o.level, main.p[0] / d, r.widen);
    r.ci_c_r = interval(column[4], o.level, main.p[1] / d, r.widen);
  }
  out.result = r;
  return out;
}

}  // namespace odocal::host
