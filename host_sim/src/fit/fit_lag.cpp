// `odocal fit`: the time lag between the counts and the ground truth, and how much the fitted
// geometry depends on it (refits with the counts' clock shifted).

#include <algorithm>
#include <vector>

#include "fit_steps.hpp"

namespace odocal::host::fit_detail {
namespace {

/// The log with its counts read `lag_s` later (count at t := count at t + lag, interpolated).
TickLog shifted(const TickLog& log, double lag_s) {
  TickLog out = log;
  const std::vector<TickRow>& rows = log.rows;
  std::size_t j = 0;
  for (TickRow& row : out.rows) {
    const double t = row.t_s + lag_s;
    while (j + 1 < rows.size() && rows[j + 1].t_s <= t) {
      ++j;
    }
    if (t <= rows.front().t_s) {
      row.count_l = rows.front().count_l;
      row.count_r = rows.front().count_r;
    } else if (j + 1 >= rows.size()) {
      row.count_l = rows.back().count_l;
      row.count_r = rows.back().count_r;
    } else {
      const double span = rows[j + 1].t_s - rows[j].t_s;
      const double f = span > 0.0 ? (t - rows[j].t_s) / span : 0.0;
      row.count_l = rows[j].count_l + f * (rows[j + 1].count_l - rows[j].count_l);
      row.count_r = rows[j].count_r + f * (rows[j + 1].count_r - rows[j].count_r);
    }
  }
  return out;
}

}  // namespace

std::optional<FitLag> estimate_lag(const std::vector<TickLog>& runs, const Params& p,
                                   const ModelSpec& spec, const FitOptions& o, double cost0) {
  // Only logs with ground truth along the path and a running clock can show a lag.
  std::size_t truth_rows = 0;
  for (const TickLog& log : runs) {
    if (!(log.rows.back().t_s > log.rows.front().t_s)) {
      return std::nullopt;
    }
    for (const TickRow& row : log.rows) {
      truth_rows += row.has_xy ? 1 : 0;
    }
  }
  if (truth_rows < 10 * runs.size()) {
    return std::nullopt;
  }
  const auto refit = [&](double lag, Params& out, double& cost) {
    std::vector<TickLog> moved;
    moved.reserve(runs.size());
    for (const TickLog& log : runs) {
      moved.push_back(shifted(log, lag));
    }
    const std::vector<Unit> units = whole_runs(moved);
    const Solved s = solve(units, every_unit(units.size()), p, spec, o.heading_length_mm);
    out = s.p;
    cost = s.normal.cost;
    return s.ok;
  };
  constexpr double step_s = 0.05;
  Params minus, plus, at;
  double cost_minus = 0.0, cost_plus = 0.0, cost_at = 0.0;
  if (!refit(-step_s, minus, cost_minus) || !refit(step_s, plus, cost_plus)) {
    return std::nullopt;
  }
  FitLag lag;
  const double curvature = cost_minus - 2.0 * cost0 + cost_plus;
  lag.estimate_s = curvature > 0.0 ? 0.5 * step_s * (cost_minus - cost_plus) / curvature : 0.0;
  lag.estimate_s = std::clamp(lag.estimate_s, -4.0 * step_s, 4.0 * step_s);
  for (Eigen::Index i = 0; i < p.size(); ++i) {
    lag.per_50ms[i] = 0.5 * (plus[i] - minus[i]) * (0.05 / step_s);
  }
  if (!refit(lag.estimate_s, at, cost_at)) {
    return std::nullopt;
  }
  for (Eigen::Index i = 0; i < p.size(); ++i) {
    lag.geometry_at_estimate[i] = at[i];
  }
  return lag;
}

}  // namespace odocal::host::fit_detail
