// `odocal session --procedure auto` (DESIGN "One command, fewest measurements"): the wiring
// self-test, then measured runs chosen for what each adds to the precision of the unseen path's
// end (auto_plan.hpp), the fit of the robot's geometry, the one apply step, the verification on
// the unseen path (the verify procedure's step), and the save.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "auto_plan.hpp"
#include "auto_session.hpp"
#include "model_in_force.hpp"
#include "odocal/drive/motion_executor.hpp"
#include "odocal/drive/robot_model.hpp"
#include "odocal/host/fit.hpp"
#include "odocal/host/fit_noise.hpp"
#include "odocal/host/path_geometry.hpp"
#include "run_jury.hpp"
#include "session_internal.hpp"
#include "unseen_path.hpp"
#include "wall_truth.hpp"

namespace odocal::host::session {

using namespace auto_plan;

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

std::string tape_how_to() {
  return "How to measure: mark the start on the floor and two points on the robot, one over the "
         "middle of the axle and one ahead of it (as far as the robot allows). After each run, "
         "measure the axle mark's position from the start mark along the start line (x, ahead) "
         "and across it (y, left), and the heading: the angle of the line through the two marks "
         "(atan2 of their across and along differences), in degrees, counter-clockwise "
         "positive.\n";
}

void AutoSession::check_wiring(Outcome& out) {
  c_.log << "Auto calibration: the wiring self-test first.\n";
  c_.planned = auto_first_round + auto_verify_runs;
  const Outcome wiring = run_selftest(c_);
  out.result["selftest"] = wiring.result;
  out.text += wiring.text;
  selftest_runs_ = c_.runs.size();
  c_.robot.drain(300);  // the `# done` lines of the self-test's own drives
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
}

void AutoSession::drive_one(Kind k, const std::string& why) {
  // --resume: a run the interrupted session drove is taken as it was, whatever the plan would
  // choose now (a reading edited in measurements.csv changes the plan from there on).
  const std::optional<Kind> recorded = recorded_kind();
  double expected_s = 0.0;
  Motion motion;
  std::vector<Motion> then;  ///< with the walls, a route's quarter turn and second leg
  if (recorded) {
    k = *recorded;
    motion = c_.options.replay[c_.runs.size()].motion;
    then = c_.options.replay[c_.runs.size()].then;
  } else if (lines_in_the_maze() && k == Kind::line) {
    std::string what;
    double side = 0.0;
    motion = straighter_ && walls_->second_corridor(side)
                 ? walls_->route_run(plan_.cruise_mps, plan_.spin_radps, then, expected_s, what)
                 : walls_->corridor_line(walls_lines_++, plan_.cruise_mps, expected_s, what);
    c_.log << fmt::format("Next: {} ({}).\n", what, why);
  } else {
    if (plan_.floor_lines && k == Kind::line && !walls_->on_the_floor()) {
      to_the_floor();  // the first line: everything from here on is on the floor, by the tape
    }
    motion = motion_of(k, plan_, expected_s, c_);
    c_.log << fmt::format("Next: {} ({}).\n",
                          walls_ != nullptr && !walls_->on_the_floor()
                              ? fmt::format("{:.0f} turns in place {}", plan_.spin_turns,
                                            k == Kind::spin_ccw ? "counter-clockwise" : "clockwise")
                              : what_to_do(k, plan_),
                          why);
  }
  const RunRecord r = c_.run(kind_label(k), motion, expected_s, true, then);
  if (!r.measured.theta_deg) {
    c_.log << "  (no heading given: this run counts with its position only)\n";
  }
  c_.write_file(fmt::format("auto_run_{:02d}.csv", jury_->size() + 1), tick_log_csv(r));
  jury_->add(c_.runs.size() - 1);
  chosen_.push_back({{"kind", kind_label(k)}, {"command", motion.command()}, {"why", why}});
  if (k == Kind::arc_left || k == Kind::arc_right) {
    ++arc_runs_;
  }
  if (walls_ != nullptr) {
    c_.partial["walls"] = walls_->json();
  }
  for (const std::size_t again : jury_->settle()) {
    if (const std::optional<Kind> kind = kind_of_label(c_.runs[again].label)) {
      drive_one(*kind,
                fmt::format("run {} again: its reading disagreed with the other runs", again + 1));
    }
  }
}

FitResult AutoSession::fit_with(const FitOptions& options) {
  const FitOutcome f = fit_geometry(jury_->logs_in_use(), nominal_, options);
  if (!f) {
    throw std::runtime_error("auto: the fit of the runs failed: " + f.error.message +
                             " (nothing applied; check the measurements and the wiring)");
  }
  return *f.result;
}

// The models the firmware applies: one wheelbase, or one for turns in place and one for arcs.
// The turn-rate model is a comparison candidate of `odocal fit` with no firmware parameter:
// when the logs prefer it, the arc model stands in for it where it predicts the left-out runs
// better than one wheelbase by the fit's margin, else one wheelbase.
FitResult AutoSession::fit_now() {
  FitResult r = fit_with(fo_);
  if (r.geometry.model != FitModelKind::turn_rate_wheelbase) {
    return r;
  }
  const FitCandidate* one = candidate_of(r, FitModelKind::one_wheelbase);
  const FitCandidate* arc = candidate_of(r, FitModelKind::arc_wheelbase);
  FitOptions forced = fo_;
  forced.model = FitModelKind::one_wheelbase;
  if (one != nullptr && arc != nullptr && arc->tried && arc->supported &&
      arc->heldout_path_rms_mm <= (1.0 - fo_.min_gain) * one->heldout_path_rms_mm &&
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
}

bool AutoSession::report() {
  // What sigma_sys may be, as far as the runs' own degrees of freedom tell (target_met).
  const double bound = p_.stop_factor * p_.sigma_sys_mm;
  progress_.push_back({{"runs", in_use()},
                       {"sigma_sys_mm", p_.sigma_sys_mm},
                       {"sigma_sys_bound_mm",
                        std::isfinite(bound) ? nlohmann::json(bound) : nlohmann::json(nullptr)},
                       {"sigma_random_mm", p_.sigma_random_mm},
                       {"target_mm", p_.target_mm},
                       {"model", model_name(fitted_.geometry.model)}});
  c_.partial["precision"] = progress_;
  const bool done = (target_met() && !p_.arc_unresolved) || driven() >= budget_;
  c_.log << fmt::format(
      "Precision after {} runs: the factors leave about {:.1f} mm (1 sigma; {}) on the unseen "
      "path, target {:.1f} mm ({}). {}\n",
      in_use(), p_.sigma_sys_mm,
      std::isfinite(bound)
          ? fmt::format("up to {:.1f} mm as far as {} runs can tell", bound, in_use())
          : std::string("too few runs yet to tell how sure that is"),
      p_.target_mm,
      p_.sigma_random_mm > 0.05
          ? fmt::format("the robot's own random drift, as far as the runs show it, about {:.1f} mm",
                        p_.sigma_random_mm)
          : std::string("the robot's own random drift not estimated yet"),
      done ? fmt::format(
                 "{}: {} more measurements (the verification).",
                 target_met()
                     ? "Enough"
                     : fmt::format("That is the {} calibration runs there is room for", budget_),
                 auto_verify_runs)
      : !p_.reached_in_room
          ? fmt::format("The target is unlikely within the budget: expect about {:.1f} mm "
                        "after the {} calibration runs there is room for ({} more, then {} "
                        "to verify).",
                        p_.sigma_at_room_mm, budget_, p_.more, auto_verify_runs)
          : fmt::format("About {} more measurements expected ({} to calibrate, {} to "
                        "verify): the target within the budget if the runs scatter no more "
                        "than so far.",
                        p_.more + auto_verify_runs, p_.more, auto_verify_runs));
  return done;
}

void AutoSession::measure_until_known(Outcome& out) {
  plan_the_budget();
  if (walls_ != nullptr && plan_.floor_lines) {
    c_.log << "How it is measured: the turns in place by the walls (after each the robot looks, "
              "a turn in place stopping every few degrees to read its sensors), in the start "
              "cell; then the lines by a tape on an open floor (the session says when).\n";
  } else if (walls_ != nullptr) {
    c_.log << "How it is measured: by the walls. After each run the robot looks (a turn in "
              "place, stopping every few degrees to read its sensors) and the walls around it "
              "say where it stopped and which way it faces. Nothing to type, nothing to measure; "
              "the robot starts each run where the last one left it.\n";
  } else {
    c_.log << tape_how_to();
  }
  static_assert(kFirstRound == auto_first_round, "the first round's kinds, one per run");
  const Kind* first_round = first_round_of(plan_);
  for (std::size_t i = 0; i < kFirstRound; ++i) {
    drive_one(first_round[i], "first round: every parameter seen from two sides");
  }
  fo_.seed = c_.options.seed;
  fo_.replicates = 0;
  fo_.estimate_lag = false;
  fo_.noise_floor_mm = kMeasureSigmaMm;
  fo_.heading_length_mm = kHeadingLengthMm;
  fo_.max_relative_sd = 0.05;
  fo_.cluster_covariance = true;  // the runs' own scatter in the precision (precision_of)
  fitted_ = fit_now();
  if (lines_in_the_maze()) {
    drive_straighter();
  }
  p_ = precision_of(fitted_, nominal_, jury_->logs_in_use(), plan_, c_.options.target_mm, room(),
                    arc_runs_);
  while (!report() && !recorded_verification_next()) {
    c_.planned = selftest_runs_ + driven() + std::max<std::size_t>(p_.more, 1) + auto_verify_runs;
    drive_one(p_.next, p_.arc_unresolved
                           ? "the arcs seem to turn about another wheelbase: one more arc pins it"
                           : "lowers the unseen path's uncertainty the most");
    fitted_ = fit_now();
    p_ = precision_of(fitted_, nominal_, jury_->logs_in_use(), plan_, c_.options.target_mm, room(),
                      arc_runs_);
  }
  if (plan_.floor_lines) {
    out.result["tape"] = {{"why", tape_why_},
                          {"calibration_readings", c_.source.tape_readings(c_.runs.size())}};
  }
  out.result["runs_chosen"] = chosen_;
  out.result["disagreeing_runs"] = jury_->record();
  out.result["run_checks"] = jury_->checks();
  out.result["precision"] = progress_;
  out.result["target_mm"] = p_.target_mm;
  out.result["target_met"] = target_met();
  out.result["max_measurements"] = max_measurements_;
  out.result["expected_runs_before"] = expected_runs_;
  if (!target_met()) {
    // How many more the target would take: the same choice of runs, with room.
    const Precision beyond = precision_of(fitted_, nominal_, jury_->logs_in_use(), plan_,
                                          c_.options.target_mm, 500, arc_runs_);
    const bool reachable = beyond.more < 500;
    out.result["runs_to_target"] =
        reachable ? nlohmann::json(beyond.more) : nlohmann::json(nullptr);
    const double expect = std::hypot(p_.sigma_sys_mm, p_.sigma_random_mm);
    c_.log << fmt::format(
        "Target not met: the {} calibration runs the budget allows leave about {:.1f} mm (1 "
        "sigma) on the unseen path, against the target {:.1f} mm. With the robot's own drift "
        "({}), expect the unseen path to end about {:.1f} mm RMS from where it should. {}\n"
        "The factors are still the best these runs give.\n",
        in_use(), p_.sigma_sys_mm, p_.target_mm,
        p_.sigma_random_mm > 0.05 ? fmt::format("about {:.1f} mm", p_.sigma_random_mm)
                                  : std::string("not estimated"),
        expect,
        reachable ? fmt::format("About {} more calibration runs would reach the target "
                                "(--max-measurements {}).",
                                beyond.more, max_measurements_ + beyond.more)
                  : std::string("More than 500 more calibration runs would be needed: the "
                                "target is out of practical reach on this robot (a longer "
                                "--side-m helps the wheel ratio most)."));
  }
}

void AutoSession::apply_final_fit(Outcome& out) {
  fo_.replicates = 300;
  fo_.progress = [this](const std::string& message) { c_.log << "  " << message << "\n"; };
  fitted_ = fit_now();
  // The JSON of `odocal fit` on these logs (noise with its intervals): what `odocal ros2` reads.
  out.result["fit"] = fit_json(fitted_, noise_for_fit(jury_->logs_in_use(), fitted_, fo_));
  c_.log << fit_text_for_auto(fitted_);
  // The one apply step (model_in_force.hpp): the fitted geometry with F_lat = F_lon = 1, checked
  // against the one table of plausible results.
  const FitGeometry& g = fitted_.geometry;
  const Factors next = factors_for_fit(
      drive::model::Geometry<double>{
          g.wheel_diameter_left_mm, g.wheel_diameter_right_mm, g.wheelbase_mm,
          g.model == FitModelKind::arc_wheelbase ? g.second_wheelbase_mm : 0.0},
      nominal_.wheel_diameter_mm);
  // A run the fitted geometry cannot explain as it explains the others: named, so that the
  // owner checks its reading; the verification is then flagged whatever it shows.
  suspects_ = suspect_runs(jury_->logs_in_use(), nominal_, fitted_.geometry);
  const std::vector<std::size_t> numbered = jury_->runs_in_use();
  for (SuspectRun& s : suspects_) {
    s.index = numbered[s.index] - selftest_runs_;  // describe_suspects counts from the first
  }
  std::string named;
  const nlohmann::json listed = describe_suspects(suspects_, c_, selftest_runs_ + 1, named);
  out.result["suspect_runs"] = listed;
  const std::string refusal = implausible_factors(next, c_.initial.wheelbase_mm);
  if (!refusal.empty()) {
    throw std::runtime_error(
        "auto: " + refusal + ". Nothing applied: check the wiring (docs/wiring.md) and the " +
        (named.empty() ? std::string("measurements (a heading typed with the wrong sign?).")
                       : "readings of the runs that disagree with the others: " + named +
                             " (correct them in measurements.csv and --resume)."));
  }
  apply_fit(c_, next, c_.log);
  applied_ = next;
  out.applied = true;
  if (!named.empty()) {
    c_.log << "WARNING: runs that do not agree with the others: " << named
           << ". Check their readings (a heading's sign, a typo): the factors applied are bent by "
              "them. Answer n to the save question and put the readings right in "
              "measurements.csv: a new session with --measurements OUT/measurements.csv "
              "drives the same runs and takes them from there.\n";
  }
}

void AutoSession::verify(Outcome& out) {
  const UnseenPath unseen = unseen_path(c_);
  const PathEnd& goal = unseen.goal;
  c_.planned = c_.runs.size() + auto_verify_runs;
  c_.log << fmt::format(
      "Verify: the unseen path (100 cm square, 100 cm triangle, 80 cm semicircle), {} runs with "
      "the new factors; it should end {:.0f} mm ahead and {:.0f} mm to the left of the start.\n",
      auto_verify_runs, plain(goal.x_m * 1e3, 0), plain(goal.y_m * 1e3, 0));
  nlohmann::json stops = nlohmann::json::array();
  double sum2 = 0.0;
  for (const UnseenStop& stop : drive_unseen(c_, unseen, "verify", auto_verify_runs, true)) {
    const double ex = stop.error.x_mm;
    const double ey = stop.error.y_mm;
    sum2 += ex * ex + ey * ey;
    stops.push_back({{"x_mm", stop.x_mm},
                     {"y_mm", stop.y_mm},
                     {"error_x_mm", ex},
                     {"error_y_mm", ey},
                     {"error_mm", std::hypot(ex, ey)}});
  }
  const double rms = std::sqrt(sum2 / static_cast<double>(auto_verify_runs));
  // What the calibration answers for: the measured stop against where the calibrated odometry
  // says the robot stopped (the path's tracking, the drive's overrun at its end, is not the
  // factors' doing: a robot driven through ROSArduinoBridge's coarser loop overruns more).
  double odometry2 = 0.0;
  for (std::size_t i = c_.runs.size() - auto_verify_runs; i < c_.runs.size(); ++i) {
    const RunRecord& r = c_.runs[i];
    odometry2 +=
        std::pow(r.measured.x_mm - r.odom.x_mm, 2) + std::pow(r.measured.y_mm - r.odom.y_mm, 2);
  }
  const double odometry_rms = std::sqrt(odometry2 / static_cast<double>(auto_verify_runs));
  // Where these runs would have ended with the geometry in force before the session, at no
  // measurement's cost: moved by how far the old odometry of their counts ends from the new one's.
  const FitGeometry before_g =
      fit_geometry_of(geometry_in_force(c_.initial, nominal_.wheel_diameter_mm));
  const FitGeometry after_g =
      fit_geometry_of(geometry_in_force(applied_, nominal_.wheel_diameter_mm));
  double before2 = 0.0;
  for (std::size_t i = c_.runs.size() - auto_verify_runs; i < c_.runs.size(); ++i) {
    const RunRecord& r = c_.runs[i];
    const TickLog log = tick_log_of(r, false);
    const std::size_t last = log.rows.size() - 1;
    const EndSensitivity old_end = end_sensitivity(log, 0, last, nominal_, before_g);
    const EndSensitivity new_end = end_sensitivity(log, 0, last, nominal_, after_g);
    const double ex = r.measured.x_mm - goal.x_m * 1e3 - (old_end.end[0] - new_end.end[0]);
    const double ey = r.measured.y_mm - goal.y_m * 1e3 - (old_end.end[1] - new_end.end[1]);
    before2 += ex * ex + ey * ey;
  }
  const double before_rms = std::sqrt(before2 / static_cast<double>(auto_verify_runs));
  const double expected =
      std::sqrt(p_.sigma_sys_mm * p_.sigma_sys_mm + p_.sigma_random_mm * p_.sigma_random_mm);
  out.result["verify"] = {{"goal", {{"x_mm", goal.x_m * 1e3}, {"y_mm", goal.y_m * 1e3}}},
                          {"stops", stops},
                          {"rms_mm", rms},
                          {"before_rms_mm", before_rms},
                          {"odometry_rms_mm", odometry_rms},
                          {"expected_mm", expected}};
  std::ostringstream text;
  text << fmt::format(
      "Auto: {} calibration runs, {} to verify ({} measurements in all). Model {}. "
      "Unseen path end error {:.1f} mm RMS from the goal, {:.1f} mm from where the calibrated "
      "odometry says it stopped (the runs predict about {:.1f} mm there: {:.1f} of random "
      "drift, {:.1f} from what the factors are unsure of; the path's own tracking error comes "
      "on top of it at the goal).\n"
      "With the factors it had before the session, the robot would have ended about {:.1f} mm RMS "
      "from the goal on the same runs (their counts replayed; no extra measurement).\n",
      driven(), auto_verify_runs, c_.source.tape_readings(c_.runs.size()),
      model_name(fitted_.geometry.model), rms, odometry_rms, expected, p_.sigma_random_mm,
      p_.sigma_sys_mm, before_rms);
  const bool far_off =
      expected > 0.0 && odometry_rms > 3.0 * std::max(expected, 2.0 * kMeasureSigmaMm);
  if (far_off) {
    text << "WARNING: the verification ends much further off than the runs predict: check the "
            "measurements (a heading typed with the wrong sign?) and the floor.\n";
  }
  if (!suspects_.empty()) {
    text << fmt::format(
        "WARNING: the prediction is not to be trusted: {} run(s) disagree with the others "
        "(result.suspect_runs); check their readings.\n",
        suspects_.size());
  }
  out.result["verify"]["flagged"] = far_off || !suspects_.empty();
  c_.log << text.str();
  out.text += fit_text_for_auto(fitted_) + text.str();
}

Outcome run_auto(Context& c) {
  Outcome out;
  AutoSession session(c);
  session.check_wiring(out);
  const auto* walls = dynamic_cast<WallTruth*>(&c.source);
  if (walls != nullptr) {
    session.learn_the_walls(out);
  }
  session.measure_until_known(out);
  session.apply_final_fit(out);
  if (walls != nullptr && !walls->on_the_floor()) {
    session.verify_by_walls(out);
  } else {
    session.verify(out);  // with the tape: on the floor, where the robot is
  }
  if (walls != nullptr) {
    out.result["walls"] = walls->json();
  }
  return out;
}

}  // namespace odocal::host::session
