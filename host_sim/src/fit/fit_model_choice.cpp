// `odocal fit`: which model describes the robot. Each candidate is fitted without one data set
// (or one run) at a time and predicts it; a richer model is chosen only where it predicts the
// left-out logs better by FitOptions::min_gain and the logs determine its parameters
// (docs/calibration.md "Models"; DESIGN "Real-robot model").

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "fit_interval.hpp"
#include "fit_steps.hpp"

namespace odocal::host::fit_detail {
namespace {

/// Squared radial errors of every x/y ground-truth row of the units under p.
struct PathScore {
  double sum = 0.0;
  std::size_t rows = 0;
};

PathScore path_score(const std::vector<Unit>& units, const std::vector<std::size_t>& pick,
                     const Params& p, const ModelSpec& spec) {
  PathScore score;
  for (const std::size_t u : pick) {
    integrate(units[u], p, spec, false, [&](const TickRow& row, const ModelState& s) {
      if (row.has_xy) {
        const double e = std::hypot(s.x - row.x_mm, s.y - row.y_mm);
        score.sum += e * e;
        ++score.rows;
      }
    });
  }
  return score;
}

/// What each fold leaves out: one data set at a time with 3 sets or more, else one run at a
/// time (none with fewer than 3 runs).
struct Folds {
  std::string unit;  ///< "set", "run" or ""
  std::vector<std::vector<std::size_t>> left_out;
};

Folds folds_of(const std::vector<TickLog>& runs, const FitOptions& o) {
  Folds folds;
  const std::vector<std::string> names = set_names(runs, o);
  const std::vector<std::string> sets = distinct(names);
  if (sets.size() >= 3) {
    folds.unit = "set";
    for (const std::string& name : sets) {
      folds.left_out.emplace_back();
      for (std::size_t i = 0; i < runs.size(); ++i) {
        if (names[i] == name) {
          folds.left_out.back().push_back(i);
        }
      }
    }
  } else if (runs.size() >= 3) {
    folds.unit = "run";
    for (std::size_t i = 0; i < runs.size(); ++i) {
      folds.left_out.push_back({i});
    }
  }
  return folds;
}

/// Why a candidate is not even tried ("" when it is).
std::string not_tried(FitModelKind kind, const Folds& folds, const Turning& turning) {
  if (folds.left_out.empty()) {
    return "fewer than 3 runs: nothing to hold out";
  }
  if (kind == FitModelKind::arc_wheelbase && (turning.in_place_rad < pi || turning.arcs_rad < pi)) {
    return reason_text(
        "only one kind of turning in the logs (%.0f° in place, %.0f° on arcs; each needs 180° "
        "or more): the arc wheelbase is not determined",
        turning.in_place_rad * 180.0 / pi, turning.arcs_rad * 180.0 / pi);
  }
  if (kind != FitModelKind::one_wheelbase && turning.total_rad < pi) {
    return "the runs turn too little to tell two wheelbases apart";
  }
  return "";
}

/// A two-wheelbase candidate fitted on all the logs: `note` says why it cannot be compared at
/// all; the result says why it may not be chosen though it is compared ("" when it may).
std::string unsupported(FitModelKind kind, const std::vector<Unit>& units, const Params& start,
                        const ModelSpec& spec, const FitOptions& o, const Design& design,
                        std::string& note) {
  const Turning& turning = design.turning;
  std::string why;
  const Solved full = solve(units, every_unit(units.size()), start, spec, o.heading_length_mm);
  if (!full.ok) {
    note = "did not converge on all the logs";
  } else if (const Determination d = determination(full, o, kind, &design); !d.ok) {
    note = d.error.message;
  } else {
    // Both wheelbases must be known from the scatter between runs, not only from the noise
    // floor: a second wheelbase fitted to a few incidental arcs (the drift corrections of
    // straight legs) is an extrapolation.
    const ClusterInterval ci = cluster_interval(unit_rows(units, full.p, spec, o.heading_length_mm),
                                                full.p, 0, o.seed, o.level);
    if (!ci.ok || ci.se[2] > o.max_wheelbase_sd || ci.se[3] > o.max_wheelbase_sd) {
      why = reason_text(
          "the logs do not tell two wheelbases apart: from run to run they vary by ±%.2f %% "
          "and ±%.2f %% (each needs ",
          100.0 * ci.se[2], 100.0 * ci.se[3]);
      why += reason_text("%.2f %% or better); %.0f° of turning in place, ",
                         100.0 * o.max_wheelbase_sd, turning.in_place_rad * 180.0 / pi);
      why += reason_text("%.0f° on arcs", turning.arcs_rad * 180.0 / pi);
      if (kind == FitModelKind::arc_wheelbase) {
        why = "only one kind of turning in the logs that counts: " + why;
      }
    } else if (const double apart = std::fabs(full.p[3] - full.p[2]),
               scatter = ci.se[2] * full.p[2] + ci.se[3] * full.p[3];
               apart <= 2.0 * scatter) {
      // The two wheelbases must differ by more than twice their run-to-run standard errors
      // together (a bound on the difference's): else the logs show one wheelbase.
      why = reason_text(
          "the two wheelbases differ by %.2f mm, within twice their run-to-run scatter "
          "(%.2f mm): the logs show one wheelbase",
          apart, 2.0 * scatter);
    }
  }
  return why;
}

/// Every fold's left-out ground truth predicted by a fit of the others (`note` set when a fit
/// fails).
PathScore heldout_score(const std::vector<Unit>& units, const Folds& folds, const Params& start,
                        const ModelSpec& spec, const FitOptions& o, std::string& note) {
  PathScore total;
  for (std::size_t f = 0; f < folds.left_out.size() && note.empty(); ++f) {
    const std::vector<std::size_t>& out = folds.left_out[f];
    std::vector<std::size_t> train;
    for (std::size_t i = 0; i < units.size(); ++i) {
      if (std::find(out.begin(), out.end(), i) == out.end()) {
        train.push_back(i);
      }
    }
    const Solved s = solve(units, train, start, spec, o.heading_length_mm);
    if (!s.ok) {
      note = "a fit without one " + folds.unit + " did not converge";
      break;
    }
    const PathScore held = path_score(units, out, s.p, spec);
    total.sum += held.sum;
    total.rows += held.rows;
  }
  return total;
}

/// The best supported candidate that beats one wheelbase by min_gain, and why.
void choose_among_candidates(FitModelChoice& choice, const FitOptions& o, std::size_t folds) {
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
                    reason_text("%.0f %% better (held-out path RMS %.2f mm with one wheelbase)",
                                100.0 * o.min_gain, one.heldout_path_rms_mm);
  } else {
    choice.reason = std::string(model_name(best->kind)) +
                    reason_text(
                        ": held-out path RMS %.2f mm against %.2f mm with one wheelbase (%.1f "
                        "%% lower; a richer model needs ",
                        best->heldout_path_rms_mm, one.heldout_path_rms_mm,
                        100.0 * (1.0 - best->heldout_path_rms_mm / one.heldout_path_rms_mm)) +
                    reason_text("%.0f %% or more)", 100.0 * o.min_gain);
  }
  if (!choice.unit.empty()) {
    choice.reason += ", leaving out one " + choice.unit + " at a time (" + std::to_string(folds) +
                     " " + choice.unit + "s)";
  }
}

}  // namespace

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

std::vector<std::string> distinct(std::vector<std::string> names) {
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  return names;
}

FitModelChoice choose_model(const std::vector<TickLog>& runs, const FitNominal& nominal,
                            const FitOptions& o, const std::vector<Unit>& units,
                            const Params& one_start) {
  FitModelChoice choice;
  if (o.model) {
    choice.kind = *o.model;
    choice.reason = std::string("asked for (") + model_name(*o.model) + "): no comparison made";
    return choice;
  }
  const Folds folds = folds_of(runs, o);
  choice.unit = folds.unit;
  const Design design = design_of(runs, nominal);
  const Turning& turning = design.turning;
  const FitModelKind kinds[3] = {FitModelKind::one_wheelbase, FitModelKind::arc_wheelbase,
                                 FitModelKind::turn_rate_wheelbase};
  for (const FitModelKind kind : kinds) {
    FitCandidate c;
    c.kind = kind;
    c.note = not_tried(kind, folds, turning);
    if (!c.note.empty()) {
      choice.candidates.push_back(c);
      continue;
    }
    const ModelSpec spec = spec_for(kind, nominal);
    const Params start = start_for(kind, one_start);
    // Determined too loosely to be chosen: still predicted, to compare.
    const std::string why_not = kind != FitModelKind::one_wheelbase
                                    ? unsupported(kind, units, start, spec, o, design, c.note)
                                    : std::string();
    PathScore total;
    if (c.note.empty()) {
      total = heldout_score(units, folds, start, spec, o, c.note);
    }
    if (c.note.empty() && total.rows > 0) {
      c.tried = true;
      c.supported = why_not.empty();
      c.note = why_not;
      c.folds = folds.left_out.size();
      c.heldout_path_rms_mm = std::sqrt(total.sum / static_cast<double>(total.rows));
    } else if (c.note.empty()) {
      c.note = "no ground truth along the paths to predict";
    }
    choice.candidates.push_back(c);
  }
  choose_among_candidates(choice, o, folds.left_out.size());
  return choice;
}

}  // namespace odocal::host::fit_detail
