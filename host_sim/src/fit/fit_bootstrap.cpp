// `odocal fit`: intervals over runs. By default the wild cluster bootstrap-t with the
// Bell-McCaffrey Student t as a floor (fit_interval.cpp's algebra); with 3 data sets or more the
// sets are the clusters; FitIntervalMethod::percentile refits resamples of the runs instead.

#include <algorithm>
#include <cmath>
#include <thread>

#include "fit_interval.hpp"
#include "fit_steps.hpp"
#include "odocal/calib/quantile.hpp"
#include "odocal/calib/random.hpp"

namespace odocal::host::fit_detail {
namespace {

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

/// Percentile interval of the bootstrap values, each end moved away from the estimate by
/// `widen` (the small-sample correction, see fit_geometry).
FitInterval percentile_interval(std::vector<double> values, double level, double estimate,
                                double widen) {
  const double tail = 0.5 * (1.0 - level);
  const double lo = calib::sample_quantile(values.data(), values.size(), tail);
  const double hi = calib::sample_quantile(values.data(), values.size(), 1.0 - tail);
  return FitInterval{std::min(lo, estimate - widen * (estimate - lo)),
                     std::max(hi, estimate + widen * (hi - estimate))};
}

/// One bootstrap replicate: resample units with replacement (drawing again, at most 50 times,
/// when a resample cannot determine the parameters) and refit from the full fit.
bool replicate(const std::vector<Unit>& units, const Params& start, const ModelSpec& k,
               const FitOptions& o, std::uint32_t index, Params& p, std::uint32_t& redrawn) {
  calib::Random random(o.seed ^ (0x9E3779B97F4A7C15ull * (static_cast<std::uint64_t>(index) + 1)));
  std::vector<std::size_t> pick(units.size());
  for (std::uint32_t attempt = 0; attempt < 50; ++attempt) {
    for (std::size_t& u : pick) {
      u = random.below(static_cast<std::uint32_t>(units.size()));
    }
    const Solved s = solve(units, pick, start, k, o.heading_length_mm);
    if (s.ok && determination(s, o, k.kind, nullptr).ok) {
      p = s.p;
      return true;
    }
    ++redrawn;
  }
  return false;
}

/// Runs of one data set share what changed between sets (a floor, a tyre pressure, the
/// capture's calibration): with 3 sets or more the sets are the clusters, so that the intervals
/// hold across the robot's data sets, not only across the runs of one. Merges `rows` (one per
/// run) into one per set; false (rows unchanged) with fewer sets or runs cut into pieces.
bool merge_sets(std::vector<UnitRows>& rows, const std::vector<TickLog>& runs, std::size_t units,
                const FitOptions& o) {
  const std::vector<std::string> names = set_names(runs, o);
  const std::vector<std::string> sets = distinct(names);
  if (sets.size() < 3 || units != runs.size()) {
    return false;
  }
  std::vector<UnitRows> merged(sets.size());
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const auto g = static_cast<std::size_t>(std::lower_bound(sets.begin(), sets.end(), names[i]) -
                                            sets.begin());
    UnitRows& m = merged[g];
    const Eigen::Index old_rows = m.residual.size();
    const Eigen::Index add = rows[i].residual.size();
    Eigen::VectorXd residual(old_rows + add);
    Eigen::MatrixXd jacobian(old_rows + add, rows[i].jacobian.cols());
    residual << m.residual, rows[i].residual;
    if (old_rows > 0) {
      jacobian.topRows(old_rows) = m.jacobian;
    }
    jacobian.bottomRows(add) = rows[i].jacobian;
    m.residual = std::move(residual);
    m.jacobian = std::move(jacobian);
  }
  rows = std::move(merged);
  return true;
}

/// The runs' (or sets') CR2 algebra: standard errors, degrees of freedom and covariance into `r`,
/// and the interval figures (`replicates` wild bootstrap-t draws). Not ok with one unit.
ClusterInterval cluster_figures(FitResult& r, const std::vector<TickLog>& runs, const Solved& main,
                                const ModelSpec& k, const FitOptions& o, std::uint32_t replicates) {
  const int np = static_cast<int>(main.p.size());
  const std::vector<Unit> boot = bootstrap_units(runs, o.min_units);
  std::vector<UnitRows> rows = unit_rows(boot, main.p, k, o.heading_length_mm);
  r.bootstrap_units = boot.size();
  if (merge_sets(rows, runs, boot.size(), o)) {
    r.clusters = "set";
    r.bootstrap_units = rows.size();
  }
  const ClusterInterval ci = cluster_interval(rows, main.p, replicates, o.seed, o.level);
  for (int i = 0; i < np && ci.ok; ++i) {
    r.cluster_sd[i] = ci.se[i];
    r.dof[i] = ci.dof[i];
    for (int j = 0; j < np; ++j) {
      r.cluster_cov[i][j] = ci.cov[i][j];
    }
  }
  return ci;
}

/// FitIntervalMethod::wild_t and student_t: the runs' (or sets') CR2 algebra.
void add_cluster_intervals(FitResult& r, const std::vector<TickLog>& runs, const Solved& main,
                           const ModelSpec& k, const FitOptions& o) {
  const int np = static_cast<int>(main.p.size());
  r.interval = o.interval;
  const ClusterInterval ci = cluster_figures(r, runs, main, k, o, o.replicates);
  // One unit (a single tape-measure run) shows no scatter between runs: no intervals.
  if (!ci.ok) {
    return;
  }
  r.replicates = o.replicates;
  const bool wild = o.interval == FitIntervalMethod::wild_t;
  FitInterval c[4];
  for (int i = 0; i < np; ++i) {
    // The bootstrap-t percentiles follow skewed or heavy-tailed errors; with few runs the
    // wild bootstrap (unrestricted residuals) undercuts the variance of its own standard
    // error, which the Bell-McCaffrey Student t accounts for: neither end is left narrower.
    c[i] = FitInterval{ci.t_lo[i], ci.t_hi[i]};
    if (wild) {
      c[i] = FitInterval{std::min(ci.lo[i], ci.t_lo[i]), std::max(ci.hi[i], ci.t_hi[i])};
    }
  }
  const double dn = r.nominal.wheel_diameter_mm;
  r.ci_left_mm = c[0];
  r.ci_right_mm = c[1];
  r.ci_wheelbase_mm = c[2];
  if (np > 3) {
    r.ci_second_wheelbase_mm = c[3];
  }
  r.ci_c_l = FitInterval{c[0].lo / dn, c[0].hi / dn};
  r.ci_c_r = FitInterval{c[1].lo / dn, c[1].hi / dn};
}

/// FitIntervalMethod::percentile: refits of the units resampled with replacement.
bool add_percentile_intervals(FitResult& r, const std::vector<TickLog>& runs, const Solved& main,
                              const ModelSpec& k, const FitOptions& o, FitError& error) {
  const int np = static_cast<int>(main.p.size());
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
  const double dn = r.nominal.wheel_diameter_mm;
  std::vector<double> column[6];
  for (std::uint32_t b = 0; b < o.replicates; ++b) {
    if (done[b] == 0) {
      continue;
    }
    for (int i = 0; i < np; ++i) {
      column[i].push_back(estimates[b][i]);
    }
    column[4].push_back(estimates[b][0] / dn);
    column[5].push_back(estimates[b][1] / dn);
  }
  if (column[0].size() < 2) {
    error = FitError{"",
                     "no bootstrap resample of the runs determines the geometry: "
                     "give more runs"};
    return false;
  }
  // Resampling n units spreads a fit of p parameters by about (n − p)/n of its true
  // variance (as residuals underestimate the noise by that much): widen each end by
  // sqrt(n/(n − p)) about the estimate, as the Maddahi bootstrap scales its residuals.
  const double n = static_cast<double>(boot.size());
  const double pc = static_cast<double>(np);
  r.widen = n > pc + 1.0 ? std::sqrt(n / (n - pc)) : 2.0;
  r.ci_left_mm = percentile_interval(column[0], o.level, main.p[0], r.widen);
  r.ci_right_mm = percentile_interval(column[1], o.level, main.p[1], r.widen);
  r.ci_wheelbase_mm = percentile_interval(column[2], o.level, main.p[2], r.widen);
  if (np > 3) {
    r.ci_second_wheelbase_mm = percentile_interval(column[3], o.level, main.p[3], r.widen);
  }
  r.ci_c_l = percentile_interval(column[4], o.level, main.p[0] / dn, r.widen);
  r.ci_c_r = percentile_interval(column[5], o.level, main.p[1] / dn, r.widen);
  return true;
}

}  // namespace

bool add_intervals(FitResult& r, const std::vector<TickLog>& runs, const Solved& main,
                   const ModelSpec& k, const FitOptions& o, FitError& error) {
  if (o.replicates == 0) {
    if (o.cluster_covariance) {
      static_cast<void>(cluster_figures(r, runs, main, k, o, 0));
    }
    return true;
  }
  if (o.interval == FitIntervalMethod::percentile) {
    return add_percentile_intervals(r, runs, main, k, o, error);
  }
  add_cluster_intervals(r, runs, main, k, o);
  return true;
}

}  // namespace odocal::host::fit_detail
