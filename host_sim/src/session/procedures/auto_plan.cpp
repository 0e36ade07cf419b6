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

#include "auto_plan.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include <fmt/format.h>
#include <Eigen/Dense>

#include "odocal/calib/quantile.hpp"
#include "odocal/drive/motion_executor.hpp"
#include "odocal/drive/robot_model.hpp"
#include "odocal/host/fit_noise.hpp"

namespace odocal::host::session::auto_plan {
namespace {

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

/// The same geometry in the one model's terms.
drive::model::Geometry<double> model_of(const Geometry& g) {
  return {g.d_l, g.d_r, g.b, g.b_arc};
}

/// End pose (x mm, y mm, heading rad) of `moves` driven by a firmware that believes `told` on a
/// robot that is `truth`: each move one increment of the one model (advance_believing).
Eigen::Vector3d end_pose(const std::vector<Move>& moves, const Geometry& told,
                         const Geometry& truth) {
  drive::model::PoseOf<double> pose;
  const drive::model::Geometry<double> believed = model_of(told);
  const drive::model::Geometry<double> real = model_of(truth);
  for (const Move& m : moves) {
    drive::model::advance_believing(pose, believed, real, m.distance_mm, m.turn_rad);
  }
  return {pose.x, pose.y, pose.theta};
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

/// The kind of run whose measurement lowers sigma_sys the most from covariance `c`, and the
/// covariance after it (`gu`: the unseen path's end Jacobian).
std::pair<Kind, Eigen::MatrixXd> best_run(const Eigen::MatrixXd& c, const Plan& p,
                                          const Geometry& g, const Eigen::MatrixXd& gu) {
  const Kind kinds[] = {Kind::line, Kind::spin_ccw, Kind::spin_cw, Kind::arc_left, Kind::arc_right};
  double best = HUGE_VAL;
  std::pair<Kind, Eigen::MatrixXd> out{Kind::line, c};
  for (Kind k : kinds) {
    if (!p.arcs && (k == Kind::arc_left || k == Kind::arc_right)) {
      continue;
    }
    Eigen::MatrixXd next = with_run(c, k, p, g);
    const double s = sigma_sys(gu, next);
    if (s < best) {
      best = s;
      out = {k, std::move(next)};
    }
  }
  return out;
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
    const drive::model::WheelTravel<double> w =
        drive::model::travel_for(model_of(g), m.distance_mm, m.turn_rad);
    const double s_l = w.left;
    const double s_r = w.right;
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

/// The fit's covariance of the log-parameters (np x np).
constexpr double kOneSigma = 0.841344746;  ///< a normal's quantile one sigma above the mean

Eigen::MatrixXd covariance_of(const FitResult& r, int np) {
  Eigen::MatrixXd c(np, np);
  for (int i = 0; i < np; ++i) {
    for (int j = 0; j < np; ++j) {
      c(i, j) = r.relative_cov[i][j];
    }
  }
  return c;
}

}  // namespace

std::optional<Kind> kind_of_label(const std::string& label) {
  for (const Kind k :
       {Kind::line, Kind::spin_ccw, Kind::spin_cw, Kind::arc_left, Kind::arc_right}) {
    if (label == kind_label(k)) {
      return k;
    }
  }
  return std::nullopt;
}

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

/// The drive command of a run of `k`.
Motion motion_of(Kind k, const Plan& p, double& expected_s, Context& c) {
  switch (k) {
    case Kind::line:
      expected_s = c.path_seconds(p.line_m, 0.0, 1);
      return Motion::line(p.line_m);
    case Kind::spin_ccw:
    case Kind::spin_cw: {
      const double w = (k == Kind::spin_ccw ? 1.0 : -1.0) * p.spin_radps;
      const long ms = std::lround(2.0 * kPi * p.spin_turns / p.spin_radps * 1000.0);
      expected_s = static_cast<double>(ms) / 1000.0 + 2.0;
      return Motion::timed(0.0, w, static_cast<double>(ms));
    }
    case Kind::arc_left:
    case Kind::arc_right: {
      const double w = (k == Kind::arc_left ? 1.0 : -1.0) * p.arc_mps / p.arc_radius_m;
      const long ms = std::lround(p.arc_rad / std::fabs(w) * 1000.0);
      expected_s = static_cast<double>(ms) / 1000.0 + 2.0;
      return Motion::timed(p.arc_mps, w, static_cast<double>(ms));
    }
  }
  return Motion::line(p.line_m);
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
  p.cruise_mps = c.get(ParamId::v_max_mps);
  const double w_max = c.get(ParamId::w_max_radps);
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

const FitCandidate* candidate_of(const FitResult& r, FitModelKind kind) {
  for (const FitCandidate& k : r.model.candidates) {
    if (k.kind == kind) {
      return &k;
    }
  }
  return nullptr;
}

double stop_factor_for(double dof) {
  if (!(dof > 0.0)) {
    return 1.0;
  }
  // Wilson-Hilferty: chi2_p(v) ~ v (1 - 2/(9v) + z_p sqrt(2/(9v)))^3, z_0.16 = -0.994458.
  const double a = 2.0 / (9.0 * dof);
  const double cube = 1.0 - a - 0.994458 * std::sqrt(a);
  // Below about 0.45 degrees of freedom the cube's base is not positive: no bound at all.
  if (cube <= 0.0) {
    return std::numeric_limits<double>::infinity();
  }
  return std::sqrt(1.0 / (cube * cube * cube));
}

double target_in_force(std::optional<double> target, double sigma_random_mm) {
  return target.value_or(std::max(kDefaultTargetMm, kTargetDriftShare * sigma_random_mm));
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
    arc_unresolved = plan.arcs && arc_count < 4 && one != nullptr && arc != nullptr && arc->tried &&
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
  // The runs' own scatter (CR2 over runs) where it says more than the linearised figure: slip
  // that stays the same along a run bends the whole run, which the linearised covariance counts
  // as many small independent errors. With few runs that estimate is itself unsure: it is
  // widened to one sigma's coverage of Student's t at its degrees of freedom. The runs still to
  // come are planned with the linearised covariance, the precision they reach scaled by the same
  // factor (`inflation`): each new run is assumed to scatter as the runs so far did.
  double inflation = 1.0;
  double dof = 1e9;
  for (int i = 0; i < used; ++i) {
    dof = std::min(dof, r.dof[i]);
  }
  if (dof > 0.0) {
    Eigen::MatrixXd runs(used, used);
    for (int i = 0; i < used; ++i) {
      for (int j = 0; j < used; ++j) {
        runs(i, j) = r.cluster_cov[i][j];
      }
    }
    const double t = calib::student_t_quantile(kOneSigma, std::max(dof, 1.0));
    const double linearised = sigma_sys(gu, c);
    if (linearised > 0.0) {
      inflation = std::max(1.0, t * sigma_sys(gu, runs) / linearised);
    }
  }
  out.sigma_sys_mm = inflation * sigma_sys(gu, c);
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
  out.target_mm = target_in_force(target, out.sigma_random_mm);
  out.min_runs = target || out.target_mm <= kDefaultTargetMm ? 0 : kDriftTargetMinRuns;
  // The target counts as met only when the precision, widened to what its own degrees of
  // freedom allow, is within it. Each run still to come is taken to add one degree of freedom.
  out.stop_factor = stop_factor_for(dof < 1e9 ? dof : 0.0);
  // The next run: the kind whose measurement lowers sigma_sys the most; then how many such
  // greedy choices reach the target.
  Eigen::MatrixXd now = c;
  for (std::size_t n = 0; n < room; ++n) {
    const double widen = stop_factor_for(dof < 1e9 ? dof + static_cast<double>(n) : 0.0);
    if (widen * inflation * sigma_sys(gu, now) <= out.target_mm &&
        logs.size() + n >= out.min_runs && !(n == 0 && arc_unresolved)) {
      break;
    }
    auto [pick, best_c] = best_run(now, plan, g, gu);
    if (n == 0) {
      out.next = pick;
      if (arc_unresolved) {
        // The left-out runs say the arcs turn about another wheelbase than the turns in place,
        // and the arcs so far cannot pin it: the next measurement is an arc, whatever the
        // one-wheelbase model's information says.
        out.next = arc_count % 2 == 0 ? Kind::arc_left : Kind::arc_right;
      }
    }
    now = std::move(best_c);
    ++out.more;
  }
  // Where the budget's runs are expected to leave it (the target not met within them).
  out.sigma_at_room_mm = inflation * sigma_sys(gu, now);
  out.reached_in_room =
      out.more < room || (widen_at(dof, out.more) * out.sigma_at_room_mm <= out.target_mm &&
                          logs.size() + out.more >= out.min_runs);
  return out;
}

double widen_at(double dof, std::size_t more) {
  return stop_factor_for(dof < 1e9 ? dof + static_cast<double>(more) : 0.0);
}

Expectation expected_before_runs(const Plan& plan, const FitNominal& nominal, double target_mm,
                                 std::size_t first_round, std::size_t room) {
  // Before any run the robot is its nominal geometry known to a few per cent (the plausible
  // ranges' scale: 3 % on each log-parameter), and each run's measurement is a tape's.
  Geometry g;
  g.d_l = g.d_r = nominal.wheel_diameter_mm;
  g.b = nominal.wheelbase_mm;
  Eigen::MatrixXd c = Eigen::MatrixXd::Identity(3, 3) * (0.03 * 0.03);
  const Eigen::MatrixXd gu = end_jacobian(unseen_moves(), g, 3, false);
  const Kind* first = first_round_of(plan);
  Expectation e;
  for (std::size_t i = 0; i < first_round && i < kFirstRound; ++i) {
    c = with_run(c, first[i], plan, g);
  }
  e.runs = first_round;
  while (sigma_sys(gu, c) > target_mm && e.runs < room) {
    c = best_run(c, plan, g, gu).second;
    ++e.runs;
  }
  e.sigma_sys_mm = sigma_sys(gu, c);
  e.reached = e.sigma_sys_mm <= target_mm;
  return e;
}

}  // namespace odocal::host::session::auto_plan
