// `odocal fit`: what the runs drove and what was measured (by the nominal geometry, never by the
// residuals), and why a direction the design leaves open is not determined, in the user's words.

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "fit_steps.hpp"

namespace odocal::host::fit_detail {

std::string reason_text(const char* fmt, double a, double b, double c) {
  char text[320];
  std::snprintf(text, sizeof text, fmt, a, b, c);
  return text;
}

namespace {

/// Rows after the start with ground truth, and whether they all sit at the run's end (the wheels
/// not moving between them and the last one).
struct Truthed {
  bool xy = false;
  bool end_xy = false;
  bool end_theta = false;
  bool along_path = false;
};

Truthed truthed(const TickLog& log) {
  Truthed t;
  const std::vector<TickRow>& rows = log.rows;
  std::size_t last = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    if (rows[i].has_xy || rows[i].has_theta) {
      last = i;
    }
  }
  for (std::size_t i = 1; i <= last; ++i) {
    if (!rows[i].has_xy && !rows[i].has_theta) {
      continue;
    }
    const bool at_end =
        rows[i].count_l == rows[last].count_l && rows[i].count_r == rows[last].count_r;
    t.xy = t.xy || rows[i].has_xy;
    t.along_path = t.along_path || !at_end;
    t.end_xy = t.end_xy || (at_end && rows[i].has_xy);
    t.end_theta = t.end_theta || (at_end && rows[i].has_theta);
  }
  return t;
}

/// The smaller eigenvalue of a symmetric 2×2 matrix over the larger (0 when it is zero).
double eigen_ratio(double a, double b, double c) {
  const double mean = 0.5 * (a + c);
  const double half = std::hypot(0.5 * (a - c), b);
  return mean + half > 0.0 ? std::max(mean - half, 0.0) / (mean + half) : 0.0;
}

}  // namespace

Turning turning_of(const std::vector<TickLog>& runs, const FitNominal& nominal) {
  Turning t;
  const double k = pi / nominal.counts_per_rev * nominal.wheel_diameter_mm;
  // Each kind's signed turning is summed until it reaches 0.02 rad (about 1°), then counted:
  // the counts' rounding (±1 count from row to row on a straight line) cancels instead of adding
  // up over thousands of rows.
  constexpr double step_rad = 0.02;
  for (const TickLog& log : runs) {
    double pending[3] = {0.0, 0.0, 0.0};  // in place, arcs, straight
    double counted[3] = {0.0, 0.0, 0.0};
    for (std::size_t i = 1; i < log.rows.size(); ++i) {
      const double nl = log.rows[i].count_l - log.rows[i - 1].count_l;
      const double nr = log.rows[i].count_r - log.rows[i - 1].count_r;
      const double w = arc_weight(nl, nr);
      const int kind = w < 1.0 / 3.0 ? 0 : (w < 0.95 ? 1 : 2);
      pending[kind] += k * (nr - nl) / nominal.wheelbase_mm;
      if (std::fabs(pending[kind]) >= step_rad) {
        counted[kind] += std::fabs(pending[kind]);
        pending[kind] = 0.0;
      }
    }
    for (int kind = 0; kind < 3; ++kind) {
      counted[kind] += std::fabs(pending[kind]);
    }
    t.in_place_rad += counted[0];
    t.arcs_rad += counted[1];
    t.total_rad += counted[0] + counted[1] + counted[2];
  }
  return t;
}

Design design_of(const std::vector<TickLog>& runs, const FitNominal& nominal) {
  Design d;
  d.turning = turning_of(runs, nominal);
  d.runs = runs.size();
  const double k = pi / nominal.counts_per_rev * nominal.wheel_diameter_mm;
  double sll = 0.0, slr = 0.0, srr = 0.0;
  for (const TickLog& log : runs) {
    // The nominal odometry: where the run ends relative to where it started, how far it went.
    double x = 0.0, y = 0.0, theta = 0.0, travel = 0.0, wheels = 0.0;
    for (std::size_t i = 1; i < log.rows.size(); ++i) {
      const double nl = log.rows[i].count_l - log.rows[i - 1].count_l;
      const double nr = log.rows[i].count_r - log.rows[i - 1].count_r;
      sll += nl * nl;
      slr += nl * nr;
      srr += nr * nr;
      const double ds = 0.5 * k * (nl + nr);
      const double dtheta = k * (nr - nl) / nominal.wheelbase_mm;
      x += ds * std::cos(theta + 0.5 * dtheta);
      y += ds * std::sin(theta + 0.5 * dtheta);
      theta += dtheta;
      travel += std::fabs(ds);
      wheels += 0.5 * k * (std::fabs(nl) + std::fabs(nr));
      d.left_mm += std::fabs(k * nl);
      d.right_mm += std::fabs(k * nr);
    }
    const Truthed t = truthed(log);
    d.path_truth += t.along_path ? 1 : 0;
    d.end_pose_runs += t.end_xy && t.end_theta ? 1 : 0;
    if (t.xy) {
      ++d.runs_with_xy;
      d.travel_mm += travel;
      d.wheel_travel_mm += wheels;
      const bool closed = travel > 0.0 && std::hypot(x, y) < 0.1 * travel;
      d.closed_end_only += !t.along_path && closed ? 1 : 0;
    }
  }
  d.count_spread = eigen_ratio(sll, slr, srr);
  return d;
}

FitError undetermined(const Params& dir, double sd, FitModelKind kind, const Design& design) {
  FitError error;
  const std::string amount = std::isfinite(sd) && sd < 1e6
                                 ? reason_text("±%.3g %% at the noise floor", 100.0 * sd)
                                 : std::string("not at all");
  const double along_scale = std::fabs(dir.head(3).sum()) / std::sqrt(3.0);
  const Turning& turning = design.turning;
  if (along_scale >= 0.8) {
    error.parameter = "scale";
    std::string why;
    if (design.runs_with_xy == 0) {
      why =
          " — only headings are measured, and a robot of any size turns through the same "
          "angles; measure where the runs end (x_mm, y_mm)";
    } else if (design.travel_mm < 0.1 * design.wheel_travel_mm) {
      why =
          " — the runs turn in place: the robot's centre goes nowhere, so nothing measures "
          "its size; add straight runs of known length";
    } else if (design.closed_end_only == design.runs_with_xy) {
      why =
          " — the runs are closed loops measured only at the end, and closed loops look the "
          "same at any size; add straight runs of known length or ground truth along the path";
    } else {
      why = reason_text(
          " — the runs measured in x and y travel %.2f m in all, too little to show the size "
          "to within the noise floor; drive farther or add ground truth along the path",
          1e-3 * design.travel_mm);
    }
    error.message =
        "the logs cannot determine the overall scale (wheel_diameter_left_mm, "
        "wheel_diameter_right_mm and wheelbase_mm together): they fix it only " +
        amount + why;
    return error;
  }
  Eigen::Index worst = 0;
  dir.cwiseAbs().maxCoeff(&worst);
  std::string name = parameter_name(kind, static_cast<int>(worst));
  std::string why;
  const bool second = dir.size() > 3 && std::fabs(dir[3]) >= 0.1;
  if (second && kind == FitModelKind::arc_wheelbase &&
      (turning.in_place_rad < pi || turning.arcs_rad < pi)) {
    // The wheelbase of the kind of turning that was not driven is the one left open.
    name = turning.in_place_rad < pi ? "wheelbase_mm" : "wheelbase_arc_mm";
    why = reason_text(
        " — the logs hold only one kind of turning (%.0f° in place, %.0f° on arcs; each needs "
        "180° or more): the arc-wheelbase model needs both to tell the wheelbase for turns in "
        "place from the arc wheelbase; drive turns in place and arcs, or fit one wheelbase",
        turning.in_place_rad * 180.0 / pi, turning.arcs_rad * 180.0 / pi);
  } else if (second && kind == FitModelKind::turn_rate_wheelbase) {
    why = " — the logs turn at too narrow a range of turn rates; add slow and fast turns";
  } else if (turning.total_rad < 0.5 * pi) {
    name = "wheelbase_mm";
    why = reason_text(
        " — the runs hardly turn (%.0f° in all; straight lines alone say nothing about the "
        "wheelbase); add turns, squares or loops",
        turning.total_rad * 180.0 / pi);
  } else if (design.count_spread < 0.01) {
    // Every row at one curvature: the heading fixes (D_R − D_L)/b, the path's length the mean
    // diameter, and nothing tells the wheel difference from the wheelbase.
    why =
        " — the runs turn, but always at one curvature (one arc or circle): that fixes the "
        "ratio of the wheels' difference to the wheelbase, not each; add turns in place, "
        "straight lines or arcs of another radius";
  } else if (std::min(design.left_mm, design.right_mm) <
             0.01 * std::max(design.left_mm, design.right_mm)) {
    name = design.left_mm < design.right_mm ? "wheel_diameter_left_mm" : "wheel_diameter_right_mm";
    why = " — that wheel hardly moves in any run; add runs that roll it over a known distance";
  } else {
    why = " — add runs that move each wheel over a known distance";
  }
  error.parameter = name;
  error.message = "the logs cannot determine " + name + ": they fix it only " + amount + why;
  return error;
}

}  // namespace odocal::host::fit_detail
