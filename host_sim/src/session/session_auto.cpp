// `odocal session --procedure auto` (DESIGN "One command, fewest measurements"): the wiring
// self-test, then measured runs chosen for what each adds to the precision of the unseen path's
// end, the fit of the robot's geometry, the verification on the unseen path, and the save.
//
// How the runs are chosen (docs/calibration.md "How auto chooses its runs"): the fit's
// linearised covariance C of the log-parameters (ln D_L, ln D_R, ln b[, ln b_arc]) says how
// unsure the geometry is; G, the unseen path's end position's derivatives with respect to them
// (a drive that believes the fitted geometry on a robot that differs from it), turns that into the
// end error the factors leave there, sigma_sys = sqrt(trace(G C G^T)). Each kind of run (a long
// line, turns in place, arcs) adds J^T J / sigma_m^2 to C's inverse (J: the run's measured end
// pose's derivatives, sigma_m: the tape's noise); the next run is the kind that lowers sigma_sys
// the most. Measuring stops when sigma_sys is at most the target, by default 2 mm: no more than
// one tape measurement's error (the robot's own random drift, estimated from the runs' residuals,
// is too unsure after a few runs to set it).

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>
#include <Eigen/Dense>

#include "odocal/drive/motion_executor.hpp"
#include "odocal/host/fit.hpp"
#include "odocal/host/fit_noise.hpp"
#include "odocal/host/path_geometry.hpp"
#include "session_internal.hpp"

namespace odocal::host::session {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kMeasureSigmaMm = 2.0;        ///< a tape over a few metres (docs/calibration.md)
constexpr double kHeadingLengthMm = 286.4789;  ///< 2 mm per 0.4 degree, as odocal fit
constexpr std::size_t kTotalMeasurements = 12;
/// --target's default: the factors add no more to the unseen path's end than one tape
/// measurement's error (docs/calibration.md).
constexpr double kDefaultTargetMm = 2.0;

enum class Kind { line, spin_ccw, spin_cw, arc_left, arc_right };

const char* kind_label(Kind k) {
  switch (k) {
    case Kind::line:
      return "line";
    case Kind::spin_ccw:
      return "turns-ccw";
    case Kind::spin_cw:
      return "turns-cw";
    case Kind::arc_left:
      return "arc-left";
    case Kind::arc_right:
      return "arc-right";
  }
  return "?";
}

/// What the runs are made of, from the robot's size and speeds.
struct Plan {
  double line_m = 2.0;
  double spin_radps = 2.0;
  double spin_turns = 5.0;
  double arc_radius_m = 0.4;
  double arc_rad = 1.5 * kPi;
  double arc_mps = 0.2;
  double cruise_mps = 0.3;
};

/// A segment as wheel travel: distance along (mm) and turn (rad).
struct Move {
  double distance_mm;
  double turn_rad;
};

/// Geometry as (D_L, D_R, b, b_arc) in mm; b_arc 0: one wheelbase.
struct Geometry {
  double d_l = 0.0;
  double d_r = 0.0;
  double b = 0.0;
  double b_arc = 0.0;
};

Geometry geometry_of(const FitGeometry& g) {
  return {g.wheel_diameter_left_mm, g.wheel_diameter_right_mm, g.wheelbase_mm,
          g.model == FitModelKind::arc_wheelbase ? g.second_wheelbase_mm : 0.0};
}

/// The wheelbase in force for a stretch of wheel travel s_l, s_r (fit's arc-wheelbase model).
double wheelbase_for(const Geometry& g, double s_l, double s_r) {
  if (g.b_arc <= 0.0) {
    return g.b;
  }
  const double sum = std::fabs(s_l + s_r);
  const double diff = std::fabs(s_r - s_l);
  const double w = sum + diff > 0.0 ? sum / (sum + diff) : 0.0;
  return g.b + w * (g.b_arc - g.b);
}

/// End pose (x mm, y mm, heading rad) of `moves` driven by a firmware that believes `told` on a
/// robot that is `truth`: the wheels turn what `told` computes for each move, and roll what
/// `truth`'s diameters make of that; each move an exact arc, in steps so that the arc model's
/// wheelbase follows the curvature.
Eigen::Vector3d end_pose(const std::vector<Move>& moves, const Geometry& told,
                         const Geometry& truth) {
  double x = 0.0, y = 0.0, th = 0.0;
  for (const Move& m : moves) {
    // Wheel travel the told geometry commands (its wheelbase for this curvature: solve
    // s_r - s_l = turn * b(s_l, s_r), which is linear once the weight is known from the shape).
    const double b0 = told.b;
    double s_l = m.distance_mm - 0.5 * m.turn_rad * b0;
    double s_r = m.distance_mm + 0.5 * m.turn_rad * b0;
    const double bt = wheelbase_for(told, s_l, s_r);
    s_l = m.distance_mm - 0.5 * m.turn_rad * bt;
    s_r = m.distance_mm + 0.5 * m.turn_rad * bt;
    // Wheel angles (rad) the drive turns, and what the true wheels roll.
    const double a_l = s_l / (0.5 * told.d_l);
    const double a_r = s_r / (0.5 * told.d_r);
    const double t_l = a_l * 0.5 * truth.d_l;
    const double t_r = a_r * 0.5 * truth.d_r;
    const double b = wheelbase_for(truth, t_l, t_r);
    const double ds = 0.5 * (t_l + t_r);
    const double dth = (t_r - t_l) / b;
    if (std::fabs(dth) < 1e-12) {
      x += ds * std::cos(th);
      y += ds * std::sin(th);
    } else {
      const double r = ds / dth;
      x += r * (std::sin(th + dth) - std::sin(th));
      y -= r * (std::cos(th + dth) - std::cos(th));
    }
    th += dth;
  }
  return {x, y, th};
}

std::vector<Move> unseen_moves() {
  const drive::Path path = drive::make_unseen_path();
  std::vector<Move> moves;
  for (std::uint8_t i = 0; i < path.count; ++i) {
    moves.push_back(Move{static_cast<double>(path.segments[i].distance_m) * 1e3,
                         static_cast<double>(path.segments[i].angle_rad)});
  }
  return moves;
}

std::vector<Move> run_moves(Kind k, const Plan& p) {
  switch (k) {
    case Kind::line:
      return {Move{p.line_m * 1e3, 0.0}};
    case Kind::spin_ccw:
      return {Move{0.0, 2.0 * kPi * p.spin_turns}};
    case Kind::spin_cw:
      return {Move{0.0, -2.0 * kPi * p.spin_turns}};
    case Kind::arc_left:
      return {Move{p.arc_radius_m * p.arc_rad * 1e3, p.arc_rad}};
    case Kind::arc_right:
      return {Move{p.arc_radius_m * p.arc_rad * 1e3, -p.arc_rad}};
  }
  return {};
}

/// Derivatives of `moves`' end with respect to the truth's log-parameters (np of them), the drive
/// believing `g`: rows x, y (mm) and, with `heading`, the heading times kHeadingLengthMm.
Eigen::MatrixXd end_jacobian(const std::vector<Move>& moves, const Geometry& g, int np,
                             bool heading) {
  const Eigen::Vector3d base = end_pose(moves, g, g);
  Eigen::MatrixXd j(heading ? 3 : 2, np);
  constexpr double h = 1e-6;
  for (int k = 0; k < np; ++k) {
    Geometry t = g;
    double* const values[4] = {&t.d_l, &t.d_r, &t.b, &t.b_arc};
    *values[k] *= 1.0 + h;
    const Eigen::Vector3d e = end_pose(moves, g, t);
    j(0, k) = (e[0] - base[0]) / h;
    j(1, k) = (e[1] - base[1]) / h;
    if (heading) {
      j(2, k) = (e[2] - base[2]) * kHeadingLengthMm / h;
    }
  }
  return j;
}

/// sqrt(trace(G C G^T)): the RMS end error on the unseen path the covariance C leaves.
double sigma_sys(const Eigen::MatrixXd& g, const Eigen::MatrixXd& c) {
  return std::sqrt(std::max((g * c * g.transpose()).trace(), 0.0));
}

/// The covariance after one more run of `k` (its information added to C's inverse).
Eigen::MatrixXd with_run(const Eigen::MatrixXd& c, Kind k, const Plan& p, const Geometry& g) {
  const int np = static_cast<int>(c.rows());
  const Eigen::MatrixXd j = end_jacobian(run_moves(k, p), g, np, true);
  const Eigen::MatrixXd info =
      c.inverse() + j.transpose() * j / (kMeasureSigmaMm * kMeasureSigmaMm);
  return info.inverse();
}

/// The unseen path as a tick log of counts under geometry `g` (what end_sensitivity needs), in
/// steps of about 10 mm or 2 degrees.
TickLog unseen_tick_log(const Geometry& g, const FitNominal& nominal) {
  TickLog log;
  log.source = "unseen path (predicted)";
  double cl = 0.0, cr = 0.0;
  const double per_mm_l = nominal.counts_per_rev / (kPi * g.d_l);
  const double per_mm_r = nominal.counts_per_rev / (kPi * g.d_r);
  double t = 0.0;
  log.rows.push_back(TickRow{0, 0.0, 0.0, 0.0, true, 0.0, 0.0, true, 0.0});
  for (const Move& m : unseen_moves()) {
    const double b = m.distance_mm == 0.0 ? g.b : (g.b_arc > 0.0 ? g.b_arc : g.b);
    const double s_l = m.distance_mm - 0.5 * m.turn_rad * b;
    const double s_r = m.distance_mm + 0.5 * m.turn_rad * b;
    const int steps = std::max(
        1, static_cast<int>(std::ceil(std::max(std::fabs(m.distance_mm) / 10.0,
                                               std::fabs(m.turn_rad) / (2.0 * kPi / 180.0)))));
    for (int i = 0; i < steps; ++i) {
      cl += s_l * per_mm_l / steps;
      cr += s_r * per_mm_r / steps;
      t += 0.05;
      TickRow row;
      row.t_s = t;
      row.count_l = cl;
      row.count_r = cr;
      log.rows.push_back(row);
    }
  }
  return log;
}

/// The drive command of a run of `k`.
std::string command_of(Kind k, const Plan& p, double& expected_s, Context& c) {
  char line[96];
  switch (k) {
    case Kind::line:
      std::snprintf(line, sizeof line, "run line %.3f", p.line_m);
      expected_s = c.path_seconds(p.line_m, 0.0, 1);
      break;
    case Kind::spin_ccw:
    case Kind::spin_cw: {
      const double w = (k == Kind::spin_ccw ? 1.0 : -1.0) * p.spin_radps;
      const long ms = std::lround(2.0 * kPi * p.spin_turns / p.spin_radps * 1000.0);
      std::snprintf(line, sizeof line, "drive 0 %.4f %ld", w, ms);
      expected_s = static_cast<double>(ms) / 1000.0 + 2.0;
      break;
    }
    case Kind::arc_left:
    case Kind::arc_right: {
      const double w = (k == Kind::arc_left ? 1.0 : -1.0) * p.arc_mps / p.arc_radius_m;
      const long ms = std::lround(p.arc_rad / std::fabs(w) * 1000.0);
      std::snprintf(line, sizeof line, "drive %.4f %.4f %ld", p.arc_mps, w, ms);
      expected_s = static_cast<double>(ms) / 1000.0 + 2.0;
      break;
    }
  }
  return line;
}

std::string what_to_do(Kind k, const Plan& p) {
  switch (k) {
    case Kind::line:
      return fmt::format(
          "a straight line of {:.2f} m: measure where it stops (x ahead, y to the left) and its "
          "heading",
          p.line_m);
    case Kind::spin_ccw:
    case Kind::spin_cw:
      return fmt::format(
          "{:.0f} turns in place {}: it ends about where it started; measure its heading (the "
          "two marks) and x, y",
          p.spin_turns, k == Kind::spin_ccw ? "counter-clockwise" : "clockwise");
    case Kind::arc_left:
    case Kind::arc_right:
      return fmt::format(
          "an arc of {:.0f} degrees, radius {:.2f} m, to the {}: measure where it stops and its "
          "heading",
          p.arc_rad * 180.0 / kPi, p.arc_radius_m, k == Kind::arc_left ? "left" : "right");
  }
  return "";
}

Plan plan_for(Context& c, double wheelbase_mm) {
  Plan p;
  p.cruise_mps = c.get("v_max_mps");
  const double w_max = c.get("w_max_radps");
  // The longest straight the floor allows (--side-m, default 3 m): long lines are what pin the
  // wheel ratio (the lateral offset grows with the square of the length).
  p.line_m = c.options.side_m.value_or(3.0);
  // Turns in place at 0.7 of the turn-rate limit, as many whole turns as 40 s take, 2 to 10: the
  // heading error grows with the turns, the tape's error does not.
  p.spin_radps = 0.7 * w_max;
  p.spin_turns = std::clamp(std::floor(40.0 * p.spin_radps / (2.0 * kPi)), 2.0, 10.0);
  // Arcs of three quarters of a circle, radius 2.5 wheelbases within 0.25 .. 0.8 m (the unseen
  // path's semicircle is 0.8 m), at 0.6 of the cruise speed or what the turn-rate limit allows.
  p.arc_radius_m = std::clamp(2.5 * wheelbase_mm * 1e-3, 0.25, 0.8);
  p.arc_mps = std::min(0.6 * p.cruise_mps, 0.5 * w_max * p.arc_radius_m);
  return p;
}

/// The fit's covariance of the log-parameters (np x np).
Eigen::MatrixXd covariance_of(const FitResult& r, int np) {
  Eigen::MatrixXd c(np, np);
  for (int i = 0; i < np; ++i) {
    for (int j = 0; j < np; ++j) {
      c(i, j) = r.relative_cov[i][j];
    }
  }
  return c;
}

struct Precision {
  double sigma_sys_mm = 0.0;
  double sigma_random_mm = 0.0;  ///< 0: not estimated
  double target_mm = 0.0;
  Kind next = Kind::line;
  std::size_t more = 0;  ///< runs expected before the target is met (capped)
  /// The arcs look like another wheelbase the runs cannot pin yet: not done before more arcs.
  bool arc_unresolved = false;
  nlohmann::json noise;  ///< `odocal fit`'s `noise` object, null when not estimated
};

/// The fit's comparison of model `kind` (nullptr when it was not among the candidates).
const FitCandidate* candidate_of(const FitResult& r, FitModelKind kind) {
  for (const FitCandidate& k : r.model.candidates) {
    if (k.kind == kind) {
      return &k;
    }
  }
  return nullptr;
}

Precision precision_of(const FitResult& r, const FitNominal& nominal,
                       const std::vector<TickLog>& logs, const Plan& plan,
                       std::optional<double> target, std::size_t room, std::size_t arc_count) {
  Precision out;
  bool arc_unresolved = false;
  if (r.geometry.model == FitModelKind::one_wheelbase) {
    const FitCandidate* one = candidate_of(r, FitModelKind::one_wheelbase);
    const FitCandidate* arc = candidate_of(r, FitModelKind::arc_wheelbase);
    // At most two arcs more than the first round's: beyond that the arcs' own scatter is what
    // the held-out comparison sees.
    // Better by a fifth, and by more than a quarter of the tape's noise (perfect measurements
    // make any model's held-out error a fraction of a millimetre).
    arc_unresolved = arc_count < 4 && one != nullptr && arc != nullptr && arc->tried &&
                     !arc->supported && arc->heldout_path_rms_mm < 0.8 * one->heldout_path_rms_mm &&
                     one->heldout_path_rms_mm - arc->heldout_path_rms_mm > 0.25 * kMeasureSigmaMm;
  }
  out.arc_unresolved = arc_unresolved;
  const Geometry g = geometry_of(r.geometry);
  const int np = r.geometry.model == FitModelKind::one_wheelbase ? 3 : 4;
  // The turn-rate model's second parameter has no firmware counterpart: the sensitivity treats
  // the robot as the one-wheelbase model there.
  const int used = r.geometry.model == FitModelKind::arc_wheelbase ? 4 : 3;
  Eigen::MatrixXd c = covariance_of(r, np).topLeftCorner(used, used);
  const Eigen::MatrixXd gu = end_jacobian(unseen_moves(), g, used, false);
  out.sigma_sys_mm = sigma_sys(gu, c);
  NoiseOptions no;
  no.replicates = 0;
  const NoiseEstimate noise = estimate_wheel_noise(logs, nominal, r.geometry, no);
  if (noise.ok) {
    out.noise = noise_json(noise);
    const TickLog path = unseen_tick_log(g, nominal);
    const EndSensitivity full = end_sensitivity(path, 0, path.rows.size() - 1, nominal, r.geometry);
    const Eigen::Matrix3d cov = end_covariance(full, noise.noise);
    out.sigma_random_mm = std::sqrt(std::max(cov(0, 0) + cov(1, 1), 0.0));
  }
  out.target_mm = target.value_or(kDefaultTargetMm);
  // The next run: the kind whose measurement lowers sigma_sys the most; then how many such
  // greedy choices reach the target.
  const Kind kinds[] = {Kind::line, Kind::spin_ccw, Kind::spin_cw, Kind::arc_left, Kind::arc_right};
  Eigen::MatrixXd now = c;
  for (std::size_t n = 0; n < room; ++n) {
    if (sigma_sys(gu, now) <= out.target_mm && !(n == 0 && arc_unresolved)) {
      break;
    }
    double best = HUGE_VAL;
    Kind pick = Kind::line;
    Eigen::MatrixXd best_c = now;
    for (Kind k : kinds) {
      const Eigen::MatrixXd next = with_run(now, k, plan, g);
      const double s = sigma_sys(gu, next);
      if (s < best) {
        best = s;
        pick = k;
        best_c = next;
      }
    }
    if (n == 0) {
      out.next = pick;
      if (arc_unresolved) {
        // The left-out runs say the arcs turn about another wheelbase than the turns in place,
        // and the arcs so far cannot pin it: the next measurement is an arc, whatever the
        // one-wheelbase model's information says.
        out.next = arc_count % 2 == 0 ? Kind::arc_left : Kind::arc_right;
      }
    }
    now = best_c;
    ++out.more;
  }
  return out;
}

/// `odocal fit`'s text without what is advice for its own command line (held-out logs, the
/// console lines to type): auto applies the result itself.
std::string fit_text_for_auto(const FitResult& r) {
  std::istringstream in(fit_result_text(r));
  std::string out;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("  holdout", 0) == 0 || line.rfind("Firmware:", 0) == 0 ||
        line.rfind("  (wheelbase_mm is the turn-in-place", 0) == 0) {
      continue;
    }
    out += line + "\n";
  }
  return out;
}

}  // namespace

Outcome run_auto(Context& c) {
  Outcome out;
  // 1. The wiring: a miswired robot passes for a bad calibration.
  c.log << "Auto calibration: the wiring self-test first.\n";
  c.planned = auto_first_round + auto_verify_runs;
  const Outcome wiring = run_selftest(c);
  out.result["selftest"] = wiring.result;
  out.text += wiring.text;
  const std::size_t selftest_runs = c.runs.size();
  c.robot.drain(300);  // the `# done` lines of the self-test's own drives
  for (const auto& fault : wiring.result["faults"]) {
    const bool fixed_now =
        wiring.applied && wiring.result.contains("after") && wiring.result["after"].empty();
    if (!fixed_now) {
      throw std::runtime_error(
          "the self-test found " + fault.get<std::string>() +
          (wiring.applied ? " and the fix did not clear it" : " and its fix was not applied") +
          ": fix the wiring first (docs/wiring.md); nothing calibrated");
    }
  }
  if (wiring.applied) {
    out.applied = true;
  }

  FitNominal nominal;
  nominal.wheel_diameter_mm = c.get("wheel_diameter_mm");
  nominal.wheelbase_mm = c.get("wheelbase_mm");
  nominal.counts_per_rev = c.get("counts_per_rev");
  const Plan plan = plan_for(c, nominal.wheelbase_mm);
  const std::size_t budget = std::min(auto_max_runs, kTotalMeasurements - auto_verify_runs -
                                                         std::min<std::size_t>(selftest_runs, 2));
  c.planned = selftest_runs + auto_first_round + auto_verify_runs;
  c.log << fmt::format(
      "Auto: {} measured runs first (a {:.2f} m line, {:.0f} turns in place each way, arcs of "
      "{:.2f} m radius each way, a second line), more only where they buy precision (at most {} "
      "calibration runs), then {} runs of the unseen path to verify.\n"
      "How to measure: mark the start on the floor and two points on the robot, one over the "
      "middle of the axle and one ahead of it (as far as the robot allows). After each run, "
      "measure the axle mark's position from the start mark along the start line (x, ahead) "
      "and across it (y, left), and the heading: the angle of the line through the two marks "
      "(atan2 of their across and along differences), in degrees, counter-clockwise positive.\n",
      auto_first_round, plan.line_m, plan.spin_turns, plan.arc_radius_m, budget, auto_verify_runs);

  const Kind first_round[auto_first_round] = {Kind::line, Kind::spin_ccw, Kind::arc_left,
                                              Kind::line, Kind::spin_cw,  Kind::arc_right};
  std::vector<TickLog> logs;
  std::size_t arc_runs = 0;
  nlohmann::json chosen = nlohmann::json::array();
  const auto drive_one = [&](Kind k, const std::string& why) {
    double expected_s = 0.0;
    const std::string command = command_of(k, plan, expected_s, c);
    c.log << fmt::format("Next: {} ({}).\n", what_to_do(k, plan), why);
    const RunRecord r = c.run(kind_label(k), command, expected_s, true);
    if (!r.measured.theta_deg) {
      c.log << "  (no heading given: this run counts with its position only)\n";
    }
    const std::string name = fmt::format("auto_run_{:02d}.csv", logs.size() + 1);
    c.write_file(name, tick_log_csv(r));
    logs.push_back(read_tick_log(c.options.out_dir + "/" + name));
    chosen.push_back({{"kind", kind_label(k)}, {"command", command}, {"why", why}});
    if (k == Kind::arc_left || k == Kind::arc_right) {
      ++arc_runs;
    }
  };
  for (Kind k : first_round) {
    drive_one(k, "first round: every parameter seen from two sides");
  }

  FitOptions fo;
  fo.seed = c.options.seed;
  fo.replicates = 0;
  fo.estimate_lag = false;
  fo.noise_floor_mm = kMeasureSigmaMm;
  fo.heading_length_mm = kHeadingLengthMm;
  fo.max_relative_sd = 0.05;
  const auto fit_with = [&](const FitOptions& options) {
    const FitOutcome f = fit_geometry(logs, nominal, options);
    if (!f) {
      throw std::runtime_error("auto: the fit of the runs failed: " + f.error.message +
                               " (nothing applied; check the measurements and the wiring)");
    }
    return *f.result;
  };
  // The models the firmware applies: one wheelbase, or one for turns in place and one for arcs.
  // The turn-rate model is a comparison candidate of `odocal fit` with no firmware parameter:
  // when the logs prefer it, the arc model stands in for it where it predicts the left-out runs
  // better than one wheelbase by the fit's margin, else one wheelbase.
  const auto fit_now = [&]() {
    FitResult r = fit_with(fo);
    if (r.geometry.model != FitModelKind::turn_rate_wheelbase) {
      return r;
    }
    const FitCandidate* one = candidate_of(r, FitModelKind::one_wheelbase);
    const FitCandidate* arc = candidate_of(r, FitModelKind::arc_wheelbase);
    FitOptions forced = fo;
    forced.model = FitModelKind::one_wheelbase;
    if (one != nullptr && arc != nullptr && arc->tried && arc->supported &&
        arc->heldout_path_rms_mm <= (1.0 - fo.min_gain) * one->heldout_path_rms_mm &&
        one->heldout_path_rms_mm - arc->heldout_path_rms_mm > 0.25 * kMeasureSigmaMm) {
      forced.model = FitModelKind::arc_wheelbase;
    }
    const std::vector<FitCandidate> compared = r.model.candidates;
    FitResult chosen = fit_with(forced);
    chosen.model.candidates = compared;
    chosen.model.reason = fmt::format(
        "the left-out runs preferred the turn-rate model, which has no firmware parameter; "
        "auto uses the {} model, {}",
        model_name(*forced.model),
        *forced.model == FitModelKind::arc_wheelbase
            ? "which predicts them as well or nearly"
            : "the arc model not predicting them 2 % (and a quarter of the tape's noise) better "
              "than one wheelbase");
    return chosen;
  };
  FitResult fitted = fit_now();
  Precision p = precision_of(fitted, nominal, logs, plan, c.options.target_mm, budget - logs.size(),
                             arc_runs);
  nlohmann::json progress = nlohmann::json::array();
  const auto report = [&]() {
    progress.push_back({{"runs", logs.size()},
                        {"sigma_sys_mm", p.sigma_sys_mm},
                        {"sigma_random_mm", p.sigma_random_mm},
                        {"target_mm", p.target_mm},
                        {"model", model_name(fitted.geometry.model)}});
    c.partial["precision"] = progress;
    const bool done = (p.sigma_sys_mm <= p.target_mm && !p.arc_unresolved) || logs.size() >= budget;
    c.log << fmt::format(
        "Precision after {} runs: the factors leave about {:.1f} mm (1 sigma) on the unseen "
        "path, target {:.1f} mm ({}). {}\n",
        logs.size(), p.sigma_sys_mm, p.target_mm,
        p.sigma_random_mm > 0.05
            ? fmt::format(
                  "the robot's own random drift, as far as the runs show it, about {:.1f} mm",
                  p.sigma_random_mm)
            : std::string("the robot's own random drift not estimated yet"),
        done ? fmt::format(
                   "{}: {} more measurements (the verification).",
                   p.sigma_sys_mm <= p.target_mm
                       ? "Enough"
                       : fmt::format("That is the {} calibration runs there is room for", budget),
                   auto_verify_runs)
             : fmt::format("About {} more measurements expected ({} to calibrate, {} to verify).",
                           p.more + auto_verify_runs, p.more, auto_verify_runs));
    return done;
  };
  while (!report()) {
    c.planned = selftest_runs + logs.size() + std::max<std::size_t>(p.more, 1) + auto_verify_runs;
    drive_one(p.next, p.arc_unresolved
                          ? "the arcs seem to turn about another wheelbase: one more arc pins it"
                          : "lowers the unseen path's uncertainty the most");
    fitted = fit_now();
    p = precision_of(fitted, nominal, logs, plan, c.options.target_mm, budget - logs.size(),
                     arc_runs);
  }
  out.result["runs_chosen"] = chosen;
  out.result["precision"] = progress;
  out.result["target_mm"] = p.target_mm;
  out.result["target_met"] = p.sigma_sys_mm <= p.target_mm;
  if (!(p.sigma_sys_mm <= p.target_mm)) {
    c.log << fmt::format(
        "Note: {} runs leave {:.1f} mm, above the target {:.1f} mm; the factors are still the "
        "best the runs give (a longer --side-m helps the wheel ratio most).\n",
        logs.size(), p.sigma_sys_mm, p.target_mm);
  }

  // 2. The final fit with its intervals, applied.
  fo.replicates = 300;
  fo.progress = [&c](const std::string& message) { c.log << "  " << message << "\n"; };
  fitted = fit_now();
  // The JSON of `odocal fit` on these logs (noise with its intervals): what `odocal ros2` reads.
  out.result["fit"] = fit_json(fitted, noise_for_fit(logs, fitted, fo));
  c.log << fit_text_for_auto(fitted);
  const double d = nominal.wheel_diameter_mm;
  const double c_l = fitted.geometry.wheel_diameter_left_mm / d;
  const double c_r = fitted.geometry.wheel_diameter_right_mm / d;
  const double wheelbase = fitted.geometry.wheelbase_mm;
  const auto outside = [](double v, double lo, double hi) { return !(v >= lo && v <= hi); };
  const double arc = fitted.geometry.model == FitModelKind::arc_wheelbase
                         ? fitted.geometry.second_wheelbase_mm
                         : wheelbase;
  if (outside(c_l, 0.95, 1.05) || outside(c_r, 0.95, 1.05) ||
      outside(wheelbase, 0.9 * nominal.wheelbase_mm, 1.1 * nominal.wheelbase_mm) ||
      outside(arc, 0.9 * nominal.wheelbase_mm, 1.1 * nominal.wheelbase_mm)) {
    throw std::runtime_error(fmt::format(
        "auto: c_l {:.6f}, c_r {:.6f}, wheelbase {:.3f} mm, arc wheelbase {:.3f} mm: outside the "
        "plausible range (c within 0.95 .. 1.05, each wheelbase within 10 % of {:.3f} mm; "
        "docs/calibration.md). Nothing applied: check the wiring (docs/wiring.md) and the "
        "measurements (a heading typed with the wrong sign?).",
        c_l, c_r, wheelbase, arc, nominal.wheelbase_mm));
  }
  std::string line = fmt::format("fit apply {:.6f} {:.6f} {:.4f} {} {}", c_l, c_r, wheelbase,
                                 c.date(), c.runs.size());
  if (fitted.geometry.model == FitModelKind::arc_wheelbase) {
    line += fmt::format(" arc {:.4f}", fitted.geometry.second_wheelbase_mm);
  }
  static_cast<void>(c.robot.expect_ok(line));
  const Factors before_f = c.factors();
  if (before_f.f_lat != 1.0 || before_f.f_lon != 1.0) {
    c.set("f_lat", 1.0);
    c.set("f_lon", 1.0);
    c.log << "f_lat, f_lon reset to 1: the fitted geometry replaces them.\n";
  }
  out.applied = true;

  // 3. Verification on the unseen path with the factors in force.
  const drive::Path unseen = drive::make_unseen_path();
  const PathEnd goal = path_end(unseen);
  double length_m = 0.0, turn_rad = 0.0;
  for (std::uint8_t i = 0; i < unseen.count; ++i) {
    length_m += std::fabs(static_cast<double>(unseen.segments[i].distance_m));
    if (unseen.segments[i].distance_m == 0.0f) {
      turn_rad += std::fabs(static_cast<double>(unseen.segments[i].angle_rad));
    }
  }
  c.planned = c.runs.size() + auto_verify_runs;
  c.log << fmt::format(
      "Verify: the unseen path (100 cm square, 100 cm triangle, 80 cm semicircle), {} runs with "
      "the new factors; it should end {:.0f} mm ahead and {:.0f} mm to the left of the start.\n",
      auto_verify_runs, plain(goal.x_m * 1e3, 0), plain(goal.y_m * 1e3, 0));
  nlohmann::json stops = nlohmann::json::array();
  double sum2 = 0.0;
  for (std::size_t i = 0; i < auto_verify_runs; ++i) {
    const RunRecord r =
        c.run("verify", "run unseen", c.path_seconds(length_m, turn_rad, unseen.count));
    const double ex = r.measured.x_mm - goal.x_m * 1e3;
    const double ey = r.measured.y_mm - goal.y_m * 1e3;
    sum2 += ex * ex + ey * ey;
    stops.push_back({{"x_mm", r.measured.x_mm},
                     {"y_mm", r.measured.y_mm},
                     {"error_x_mm", ex},
                     {"error_y_mm", ey},
                     {"error_mm", std::hypot(ex, ey)}});
  }
  const double rms = std::sqrt(sum2 / static_cast<double>(auto_verify_runs));
  const double expected =
      std::sqrt(p.sigma_sys_mm * p.sigma_sys_mm + p.sigma_random_mm * p.sigma_random_mm);
  out.result["verify"] = {{"goal", {{"x_mm", goal.x_m * 1e3}, {"y_mm", goal.y_m * 1e3}}},
                          {"stops", stops},
                          {"rms_mm", rms},
                          {"expected_mm", expected}};
  std::ostringstream text;
  text << fmt::format(
      "Auto: {} calibration runs, {} to verify ({} measurements in all). Model {}. "
      "Unseen path end error {:.1f} mm RMS (the runs account for about {:.1f} mm of it: {:.1f} "
      "of random drift, {:.1f} from what the factors are unsure of; the path's own tracking "
      "error comes on top).\n",
      logs.size(), auto_verify_runs, c.runs.size(), model_name(fitted.geometry.model), rms,
      expected, p.sigma_random_mm, p.sigma_sys_mm);
  if (expected > 0.0 && rms > 3.0 * std::max(expected, 2.0 * kMeasureSigmaMm)) {
    text << "WARNING: the verification ends much further off than the runs predict: check the "
            "measurements (a heading typed with the wrong sign?) and the floor.\n";
  }
  c.log << text.str();
  out.text += fit_text_for_auto(fitted) + text.str();
  return out;
}

}  // namespace odocal::host::session
