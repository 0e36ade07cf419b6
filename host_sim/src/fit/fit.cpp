// `odocal fit`: Levenberg-Marquardt on the tick logs, identifiability from the scaled Jacobian,
// bootstrap over runs.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <thread>

#include "fit_interval.hpp"
#include "fit_model.hpp"
#include "odocal/calib/quantile.hpp"
#include "odocal/calib/random.hpp"
#include "odocal/host/fit.hpp"

namespace odocal::host {
namespace {

using fit_detail::ModelSpec;
using fit_detail::Normal;
using fit_detail::Params;
using fit_detail::Square;
using fit_detail::Unit;

/// The JSON name of parameter i of a model.
const char* parameter_name(FitModelKind kind, int i) {
  static const char* const first[3] = {"wheel_diameter_left_mm", "wheel_diameter_right_mm",
                                       "wheelbase_mm"};
  if (i < 3) {
    return first[i];
  }
  return kind == FitModelKind::arc_wheelbase ? "wheelbase_arc_mm" : "wheelbase_at_1radps_mm";
}

struct Solved {
  bool ok = false;
  Params p;
  Normal normal;  ///< at p, with the Jacobian
  std::size_t iterations = 0;
};

/// Levenberg-Marquardt (Marquardt's diagonal scaling) from `start`.
Solved solve(const std::vector<Unit>& units, const std::vector<std::size_t>& pick,
             const Params& start, const ModelSpec& k, double heading_length_mm) {
  Solved out;
  Params p = start;
  const Eigen::Index np = p.size();
  Normal n = fit_detail::normal_equations(units, pick, p, k, heading_length_mm, true);
  double lambda = 1e-4;
  for (std::size_t it = 0; it < 200; ++it) {
    out.iterations = it + 1;
    if (!std::isfinite(n.cost)) {
      return out;
    }
    Square a = n.jtj;
    for (Eigen::Index i = 0; i < np; ++i) {
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
  double relative_sd[4] = {0, 0, 0, 0};
  double relative_cov[4][4] = {};
};

/// @param use_residuals take the residual scatter as the noise when it exceeds the floor (at the
///        fitted geometry; at the nominal one the residuals are the systematic error itself).
Determination determination(const Solved& s, const FitOptions& o, FitModelKind kind,
                            double turned_rad, bool use_residuals = true) {
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
    if (sd <= o.max_relative_sd) {
      continue;
    }
    const Params dir = eig.eigenvectors().col(j);
    const double along_scale = std::fabs(dir.head(3).sum()) / std::sqrt(3.0);
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
      const char* name = parameter_name(kind, static_cast<int>(worst));
      d.error.parameter = name;
      std::string why;
      if (worst == 3) {
        why = kind == FitModelKind::arc_wheelbase
                  ? " — the logs hold only one kind of turning (turns in place or arcs): "
                    "drive both to tell their wheelbases apart"
                  : " — the logs turn at too narrow a range of turn rates";
      } else if (turned_rad < 0.5 * fit_detail::pi) {
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
      d.error.message =
          std::string("the logs cannot determine ") + name + ": they fix it only " + amount + why;
    }
    break;
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

/// Percentile interval of the bootstrap values, each end moved away from the estimate by
/// `widen` (the small-sample correction, see fit_geometry).
FitInterval interval(std::vector<double> values, double level, double estimate, double widen) {
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
    if (s.ok && determination(s, o, k.kind, HUGE_VAL).ok) {
      p = s.p;
      return true;
    }
    ++redrawn;
  }
  return false;
}

ModelSpec spec_for(FitModelKind kind, const FitNominal& nominal) {
  ModelSpec spec;
  spec.kind = kind;
  spec.k = fit_detail::pi / nominal.counts_per_rev;
  spec.rate_per_count_s = spec.k * nominal.wheel_diameter_mm / nominal.wheelbase_mm;
  return spec;
}

Params params_of(const FitGeometry& g) {
  Params p(fit_detail::parameter_count(g.model));
  p[0] = g.wheel_diameter_left_mm;
  p[1] = g.wheel_diameter_right_mm;
  p[2] = g.wheelbase_mm;
  if (p.size() > 3) {
    p[3] = g.second_wheelbase_mm;
  }
  return p;
}

FitGeometry geometry_of(const Params& p, FitModelKind kind) {
  FitGeometry g{p[0], p[1], p[2], kind, p.size() > 3 ? p[3] : 0.0};
  return g;
}

/// Starting point of a model's fit from a one-wheelbase estimate (D_L, D_R, b).
Params start_for(FitModelKind kind, const Params& one) {
  Params p(fit_detail::parameter_count(kind));
  p.head(3) = one.head(3);
  if (p.size() > 3) {
    p[3] = one[2];
  }
  return p;
}

/// Squared radial errors of every x/y ground-truth row of the units under p.
struct PathScore {
  double sum = 0.0;
  std::size_t rows = 0;
};

PathScore path_score(const std::vector<Unit>& units, const std::vector<std::size_t>& pick,
                     const Params& p, const ModelSpec& spec) {
  PathScore score;
  for (const std::size_t u : pick) {
    fit_detail::integrate(units[u], p, spec, false,
                          [&](const TickRow& row, const fit_detail::ModelState& s) {
                            if (row.has_xy) {
                              const double e = std::hypot(s.x - row.x_mm, s.y - row.y_mm);
                              score.sum += e * e;
                              ++score.rows;
                            }
                          });
  }
  return score;
}

/// How the runs turn, by the nominal geometry: in place (arc weight below 1/3: radius under
/// b/4), on arcs (weight 1/3 to 0.95: radius up to about 10 b), in total (rad).
struct Turning {
  double total_rad = 0.0;
  double in_place_rad = 0.0;
  double arcs_rad = 0.0;
};

Turning turning_of(const std::vector<TickLog>& runs, const FitNominal& nominal) {
  Turning t;
  const double k = fit_detail::pi / nominal.counts_per_rev * nominal.wheel_diameter_mm;
  for (const TickLog& log : runs) {
    for (std::size_t i = 1; i < log.rows.size(); ++i) {
      const double nl = log.rows[i].count_l - log.rows[i - 1].count_l;
      const double nr = log.rows[i].count_r - log.rows[i - 1].count_r;
      const double turn = std::fabs(k * (nr - nl) / nominal.wheelbase_mm);
      const double w = fit_detail::arc_weight(nl, nr);
      t.total_rad += turn;
      if (w < 1.0 / 3.0) {
        t.in_place_rad += turn;
      } else if (w < 0.95) {
        t.arcs_rad += turn;
      }
    }
  }
  return t;
}

/// The data set of each run: FitOptions::sets, or the folder of the log's source.
std::vector<std::string> set_names(const std::vector<TickLog>& runs, const FitOptions& o) {
  if (o.sets.size() == runs.size()) {
    return o.sets;
  }
  std::vector<std::string> names;
  for (const TickLog& log : runs) {
    const auto slash = log.source.find_last_of('/');
    names.push_back(slash == std::string::npos ? std::string() : log.source.substr(0, slash));
  }
  return names;
}

std::string format(const char* fmt, double a, double b = 0.0, double c = 0.0) {
  char text[256];
  std::snprintf(text, sizeof text, fmt, a, b, c);
  return text;
}

/// Held-out prediction of each candidate model, and the choice (docs/calibration.md "Models").
FitModelChoice choose_model(const std::vector<TickLog>& runs, const FitNominal& nominal,
                            const FitOptions& o, const std::vector<Unit>& units,
                            const Params& one_start) {
  FitModelChoice choice;
  if (o.model) {
    choice.kind = *o.model;
    choice.reason = std::string("asked for (") + model_name(*o.model) + "): no comparison made";
    return choice;
  }
  // Folds: one data set at a time with 3 sets or more, else one run at a time.
  const std::vector<std::string> names = set_names(runs, o);
  std::vector<std::string> distinct = names;
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  std::vector<std::vector<std::size_t>> folds;
  if (distinct.size() >= 3) {
    choice.unit = "set";
    for (const std::string& name : distinct) {
      folds.emplace_back();
      for (std::size_t i = 0; i < runs.size(); ++i) {
        if (names[i] == name) {
          folds.back().push_back(i);
        }
      }
    }
  } else if (runs.size() >= 3) {
    choice.unit = "run";
    for (std::size_t i = 0; i < runs.size(); ++i) {
      folds.push_back({i});
    }
  }
  const Turning turning = turning_of(runs, nominal);
  const FitModelKind kinds[3] = {FitModelKind::one_wheelbase, FitModelKind::arc_wheelbase,
                                 FitModelKind::turn_rate_wheelbase};
  for (const FitModelKind kind : kinds) {
    FitCandidate c;
    c.kind = kind;
    if (folds.empty()) {
      c.note = "fewer than 3 runs: nothing to hold out";
    } else if (kind == FitModelKind::arc_wheelbase &&
               (turning.in_place_rad < fit_detail::pi || turning.arcs_rad < fit_detail::pi)) {
      c.note = format(
          "only one kind of turning in the logs (%.0f° in place, %.0f° on arcs; each needs 180° "
          "or more): the arc wheelbase is not determined",
          turning.in_place_rad * 180.0 / fit_detail::pi, turning.arcs_rad * 180.0 / fit_detail::pi);
    } else if (kind != FitModelKind::one_wheelbase && turning.total_rad < fit_detail::pi) {
      c.note = "the runs turn too little to tell two wheelbases apart";
    }
    if (!c.note.empty()) {
      choice.candidates.push_back(c);
      continue;
    }
    const ModelSpec spec = spec_for(kind, nominal);
    const Params start = start_for(kind, one_start);
    std::string unsupported;  // determined too loosely to be chosen; still predicted, to compare
    if (kind != FitModelKind::one_wheelbase) {
      std::vector<std::size_t> all(units.size());
      for (std::size_t i = 0; i < all.size(); ++i) {
        all[i] = i;
      }
      const Solved full = solve(units, all, start, spec, o.heading_length_mm);
      if (!full.ok) {
        c.note = "did not converge on all the logs";
      } else if (const Determination d = determination(full, o, kind, turning.total_rad); !d.ok) {
        c.note = d.error.message;
      } else {
        // Both wheelbases must be known from the scatter between runs, not only from the noise
        // floor: a second wheelbase fitted to a few incidental arcs (the drift corrections of
        // straight legs) is an extrapolation.
        const fit_detail::ClusterInterval ci = fit_detail::cluster_interval(
            fit_detail::unit_rows(units, full.p, spec, o.heading_length_mm), full.p, 0, o.seed,
            o.level);
        if (!ci.ok || ci.se[2] > o.max_wheelbase_sd || ci.se[3] > o.max_wheelbase_sd) {
          unsupported = format(
              "the logs do not tell two wheelbases apart: from run to run they vary by ±%.2f %% "
              "and ±%.2f %% (each needs ",
              100.0 * ci.se[2], 100.0 * ci.se[3]);
          unsupported +=
              format("%.2f %% or better); %.0f° of turning in place, ", 100.0 * o.max_wheelbase_sd,
                     turning.in_place_rad * 180.0 / fit_detail::pi);
          unsupported += format("%.0f° on arcs", turning.arcs_rad * 180.0 / fit_detail::pi);
          if (kind == FitModelKind::arc_wheelbase) {
            unsupported = "only one kind of turning in the logs that counts: " + unsupported;
          }
        } else if (const double apart = std::fabs(full.p[3] - full.p[2]),
                   scatter = ci.se[2] * full.p[2] + ci.se[3] * full.p[3];
                   apart <= 2.0 * scatter) {
          // The two wheelbases must differ by more than twice their run-to-run standard errors
          // together (a bound on the difference's): else the logs show one wheelbase.
          unsupported = format(
              "the two wheelbases differ by %.2f mm, within twice their run-to-run scatter "
              "(%.2f mm): the logs show one wheelbase",
              apart, 2.0 * scatter);
        }
      }
    }
    PathScore total;
    for (std::size_t f = 0; f < folds.size() && c.note.empty(); ++f) {
      std::vector<std::size_t> train;
      for (std::size_t i = 0; i < units.size(); ++i) {
        if (std::find(folds[f].begin(), folds[f].end(), i) == folds[f].end()) {
          train.push_back(i);
        }
      }
      const Solved s = solve(units, train, start, spec, o.heading_length_mm);
      if (!s.ok) {
        c.note = "a fit without one " + choice.unit + " did not converge";
        break;
      }
      const PathScore held = path_score(units, folds[f], s.p, spec);
      total.sum += held.sum;
      total.rows += held.rows;
    }
    if (c.note.empty() && total.rows > 0) {
      c.tried = true;
      c.supported = unsupported.empty();
      c.note = unsupported;
      c.folds = folds.size();
      c.heldout_path_rms_mm = std::sqrt(total.sum / static_cast<double>(total.rows));
    } else if (c.note.empty()) {
      c.note = "no ground truth along the paths to predict";
    }
    choice.candidates.push_back(c);
  }
  const FitCandidate& one = choice.candidates.front();
  const FitCandidate* best = &one;
  for (const FitCandidate& c : choice.candidates) {
    if (c.tried && c.supported && one.tried && c.kind != FitModelKind::one_wheelbase &&
        c.heldout_path_rms_mm <= (1.0 - o.min_gain) * one.heldout_path_rms_mm &&
        c.heldout_path_rms_mm < best->heldout_path_rms_mm) {
      best = &c;
    }
  }
  choice.kind = best->kind;
  if (!one.tried) {
    choice.reason = "one wheelbase kept: " + one.note;
  } else if (best == &one) {
    choice.reason = "one wheelbase kept: no richer model predicts the left-out " + choice.unit +
                    "s " +
                    format("%.0f %% better (held-out path RMS %.2f mm with one wheelbase)",
                           100.0 * o.min_gain, one.heldout_path_rms_mm);
  } else {
    choice.reason = std::string(model_name(best->kind)) +
                    format(
                        ": held-out path RMS %.2f mm against %.2f mm with one wheelbase (%.1f "
                        "%% lower; a richer model needs ",
                        best->heldout_path_rms_mm, one.heldout_path_rms_mm,
                        100.0 * (1.0 - best->heldout_path_rms_mm / one.heldout_path_rms_mm)) +
                    format("%.0f %% or more)", 100.0 * o.min_gain);
  }
  if (!choice.unit.empty()) {
    choice.reason += ", leaving out one " + choice.unit + " at a time (" +
                     std::to_string(folds.size()) + " " + choice.unit + "s)";
  }
  return choice;
}

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

/// Lag estimate: refits with the counts shifted by ±50 ms, the parabola through the three costs.
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
    std::vector<std::size_t> all(units.size());
    for (std::size_t i = 0; i < all.size(); ++i) {
      all[i] = i;
    }
    const Solved s = solve(units, all, p, spec, o.heading_length_mm);
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

}  // namespace

const char* model_name(FitModelKind kind) {
  switch (kind) {
    case FitModelKind::one_wheelbase:
      return "one-wheelbase";
    case FitModelKind::arc_wheelbase:
      return "arc-wheelbase";
    case FitModelKind::turn_rate_wheelbase:
      return "turn-rate-wheelbase";
  }
  return "?";
}

FitFigures score_runs(const std::vector<TickLog>& runs, const FitNominal& nominal,
                      const FitGeometry& g, double /*heading_length_mm*/) {
  FitFigures f;
  f.runs = runs.size();
  FitGeometry before_geometry{nominal.wheel_diameter_mm, nominal.wheel_diameter_mm,
                              nominal.wheelbase_mm, FitModelKind::one_wheelbase, 0.0};
  const std::vector<Unit> units = whole_runs(runs);
  for (int which = 0; which < 2; ++which) {
    const FitGeometry& geometry = which == 0 ? before_geometry : g;
    const ModelSpec spec = spec_for(geometry.model, nominal);
    const Params p = params_of(geometry);
    double end_sum = 0.0, path_sum = 0.0;
    std::size_t end_n = 0, path_n = 0;
    for (const Unit& u : units) {
      double last = -1.0;
      fit_detail::integrate(u, p, spec, false,
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
  const ModelSpec one_spec = spec_for(FitModelKind::one_wheelbase, nominal);
  const std::vector<Unit> units = whole_runs(runs);
  std::vector<std::size_t> all(units.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    all[i] = i;
  }
  const double turned_rad = turning_of(runs, nominal).total_rad;
  Params start(3);
  start << nominal.wheel_diameter_mm, nominal.wheel_diameter_mm, nominal.wheelbase_mm;
  // What the runs can determine, judged first at the nominal geometry: where a parameter is
  // undetermined the fit may wander along it and hide which one it was.
  Solved at_start;
  at_start.p = start;
  at_start.normal =
      fit_detail::normal_equations(units, all, start, one_spec, o.heading_length_mm, true);
  if (const Determination first =
          determination(at_start, o, FitModelKind::one_wheelbase, turned_rad, false);
      !first.ok) {
    out.error = first.error;
    return out;
  }
  const Solved one = solve(units, all, start, one_spec, o.heading_length_mm);
  if (!one.ok) {
    out.error = FitError{"",
                         "the fit did not converge to a physical geometry (check the logs' "
                         "units: counts, mm, degrees)"};
    return out;
  }
  const FitModelChoice choice = choose_model(runs, nominal, o, units, one.p);
  const FitModelKind kind = choice.kind;
  const ModelSpec k = spec_for(kind, nominal);
  const int np = fit_detail::parameter_count(kind);
  const Solved main = kind == FitModelKind::one_wheelbase
                          ? one
                          : solve(units, all, start_for(kind, one.p), k, o.heading_length_mm);
  if (!main.ok) {
    out.error = FitError{"", std::string("the ") + model_name(kind) +
                                 " fit did not converge to a physical geometry"};
    return out;
  }
  const Determination d = determination(main, o, kind, turned_rad);
  if (!d.ok) {
    out.error = d.error;
    return out;
  }
  FitResult r;
  r.nominal = nominal;
  r.model = choice;
  r.geometry = geometry_of(main.p, kind);
  r.c_l = main.p[0] / nominal.wheel_diameter_mm;
  r.c_r = main.p[1] / nominal.wheel_diameter_mm;
  r.e_d = main.p[1] / main.p[0];
  r.e_b = main.p[2] / nominal.wheelbase_mm;
  r.level = o.level;
  r.seed = o.seed;
  r.heading_length_mm = o.heading_length_mm;
  r.iterations = main.iterations;
  for (int i = 0; i < np; ++i) {
    r.relative_sd[i] = d.relative_sd[i];
    for (int j = 0; j < np; ++j) {
      r.relative_cov[i][j] = d.relative_cov[i][j];
    }
  }
  r.fit = score_runs(runs, nominal, r.geometry, o.heading_length_mm);
  if (!holdout.empty()) {
    r.holdout = score_runs(holdout, nominal, r.geometry, o.heading_length_mm);
  }

  fit_detail::ClusterInterval ci;
  if (o.replicates > 0 && o.interval != FitIntervalMethod::percentile) {
    const std::vector<Unit> boot = bootstrap_units(runs, o.min_units);
    std::vector<fit_detail::UnitRows> rows =
        fit_detail::unit_rows(boot, main.p, k, o.heading_length_mm);
    r.interval = o.interval;
    r.bootstrap_units = boot.size();
    // Runs of one data set share what changed between sets (a floor, a tyre pressure, the
    // capture's calibration): with 3 sets or more the sets are the clusters, so that the
    // intervals hold across the robot's data sets, not only across the runs of one.
    const std::vector<std::string> names = set_names(runs, o);
    std::vector<std::string> distinct = names;
    std::sort(distinct.begin(), distinct.end());
    distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
    if (distinct.size() >= 3 && boot.size() == runs.size()) {
      std::vector<fit_detail::UnitRows> merged(distinct.size());
      for (std::size_t i = 0; i < runs.size(); ++i) {
        const auto g = static_cast<std::size_t>(
            std::lower_bound(distinct.begin(), distinct.end(), names[i]) - distinct.begin());
        fit_detail::UnitRows& m = merged[g];
        const Eigen::Index old_rows = m.residual.size();
        const Eigen::Index add = rows[i].residual.size();
        Eigen::VectorXd residual(old_rows + add);
        Eigen::MatrixXd jacobian(old_rows + add, main.p.size());
        residual << m.residual, rows[i].residual;
        if (old_rows > 0) {
          jacobian.topRows(old_rows) = m.jacobian;
        }
        jacobian.bottomRows(add) = rows[i].jacobian;
        m.residual = std::move(residual);
        m.jacobian = std::move(jacobian);
      }
      rows = std::move(merged);
      r.clusters = "set";
      r.bootstrap_units = rows.size();
    }
    ci = fit_detail::cluster_interval(rows, main.p, o.replicates, o.seed, o.level);
  }
  // One unit (a single tape-measure run) shows no scatter between runs: no intervals.
  if (ci.ok) {
    r.replicates = o.replicates;
    for (int i = 0; i < np; ++i) {
      r.cluster_sd[i] = ci.se[i];
      r.dof[i] = ci.dof[i];
    }
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
    const double dn = nominal.wheel_diameter_mm;
    r.ci_left_mm = c[0];
    r.ci_right_mm = c[1];
    r.ci_wheelbase_mm = c[2];
    if (np > 3) {
      r.ci_second_wheelbase_mm = c[3];
    }
    r.ci_c_l = FitInterval{c[0].lo / dn, c[0].hi / dn};
    r.ci_c_r = FitInterval{c[1].lo / dn, c[1].hi / dn};
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
    std::vector<double> column[6];
    for (std::uint32_t b = 0; b < o.replicates; ++b) {
      if (done[b] == 0) {
        continue;
      }
      for (int i = 0; i < np; ++i) {
        column[i].push_back(estimates[b][i]);
      }
      column[4].push_back(estimates[b][0] / nominal.wheel_diameter_mm);
      column[5].push_back(estimates[b][1] / nominal.wheel_diameter_mm);
    }
    if (column[0].size() < 2) {
      out.error = FitError{"",
                           "no bootstrap resample of the runs determines the geometry: "
                           "give more runs"};
      return out;
    }
    // Resampling n units spreads a fit of p parameters by about (n − p)/n of its true
    // variance (as residuals underestimate the noise by that much): widen each end by
    // sqrt(n/(n − p)) about the estimate, as the Maddahi bootstrap scales its residuals.
    const double n = static_cast<double>(boot.size());
    const double pc = static_cast<double>(np);
    r.widen = n > pc + 1.0 ? std::sqrt(n / (n - pc)) : 2.0;
    const double dn = nominal.wheel_diameter_mm;
    r.ci_left_mm = interval(column[0], o.level, main.p[0], r.widen);
    r.ci_right_mm = interval(column[1], o.level, main.p[1], r.widen);
    r.ci_wheelbase_mm = interval(column[2], o.level, main.p[2], r.widen);
    if (np > 3) {
      r.ci_second_wheelbase_mm = interval(column[3], o.level, main.p[3], r.widen);
    }
    r.ci_c_l = interval(column[4], o.level, main.p[0] / dn, r.widen);
    r.ci_c_r = interval(column[5], o.level, main.p[1] / dn, r.widen);
  }
  if (o.estimate_lag) {
    r.lag = estimate_lag(runs, main.p, k, o, main.normal.cost);
    if (r.lag && r.ci_left_mm) {
      const std::optional<FitInterval>* cis[4] = {&r.ci_left_mm, &r.ci_right_mm, &r.ci_wheelbase_mm,
                                                  &r.ci_second_wheelbase_mm};
      for (int i = 0; i < np; ++i) {
        const double v = r.lag->geometry_at_estimate[i];
        if (*cis[i] && (v < (*cis[i])->lo || v > (*cis[i])->hi)) {
          r.lag->within_intervals = false;
        }
      }
    }
  }
  out.result = r;
  return out;
}

}  // namespace odocal::host
