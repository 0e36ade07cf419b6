// `odocal sim validate`: the Maddahi & Zareinia protocol on the simulated robot.

#include <cmath>
#include <numbers>
#include <sstream>

#include <fmt/format.h>

#include "odocal/drive/robot_model.hpp"
#include "odocal/host/sim_procedures.hpp"
#include "odocal/host/svg_plot.hpp"

namespace odocal::host {

namespace {

void report_progress(const ProgressFn& progress, const std::string& floor, const std::string& what,
                     std::size_t i, std::size_t n) {
  if (progress) {
    progress("validate (" + floor + "): " + what + " " + std::to_string(i + 1) + "/" +
             std::to_string(n));
  }
}

/// CF trials (squares; the straight trials are already logged) and the fit.
bool run_cf(SimulatedRobot& robot, const drive::DriveConfig& base, const ValidateOptions& o,
            ValidateFloor& floor, FitGeometry& fitted, std::string& error,
            const ProgressFn& progress) {
  if (!robot.configure(base)) {
    error = "CF trial configuration refused";
    return false;
  }
  const std::size_t squares = 2 * o.cf_squares;
  for (std::size_t i = 0; i < squares; ++i) {
    report_progress(progress, floor.name, "CF square", i, squares);
    const bool clockwise = i % 2 == 0;
    TickLog log;
    log.source = floor.name + (clockwise ? " cw" : " ccw") + " square " + std::to_string(i / 2 + 1);
    const RunOutcome out = run_path_logged(
        robot, drive::make_umbmark_square(clockwise, static_cast<float>(o.cf_side_m)), log);
    if (!out.completed) {
      error = "a CF square did not complete";
      return false;
    }
    floor.cf_logs.push_back(std::move(log));
  }
  // Turns in place, alternately clockwise and counter-clockwise: the wheelbase's best witness.
  const std::size_t spins = 2 * o.cf_spins;
  for (std::size_t i = 0; i < spins; ++i) {
    report_progress(progress, floor.name, "CF turn in place", i, spins);
    constexpr double two_pi = 2.0 * std::numbers::pi;
    const double sign = i % 2 == 0 ? -1.0 : 1.0;
    drive::Path spin;
    static_cast<void>(
        spin.push(drive::Segment{0.0f, static_cast<float>(sign * o.cf_spin_turns * two_pi)}));
    TickLog log;
    log.source = floor.name + " turn in place " + std::to_string(i + 1);
    const RunOutcome out = run_path_logged(robot, spin, log);
    if (!out.completed) {
      error = "a CF turn in place did not complete";
      return false;
    }
    floor.cf_logs.push_back(std::move(log));
  }
  FitNominal nominal;
  nominal.wheel_diameter_mm = static_cast<double>(base.wheel_diameter_mm);
  nominal.wheelbase_mm = static_cast<double>(base.wheelbase_mm);
  nominal.counts_per_rev = static_cast<double>(base.counts_per_rev);
  FitOptions options;
  options.replicates = 0;  // the point estimate is what the robot is given
  // The procedure determines every parameter by design (lines: the scale and E_d; squares and
  // turns: the wheelbase); only the bumps' noise can make it loose, and then the fit is still the
  // best guess.
  options.max_relative_sd = 0.05;
  const FitOutcome outcome = fit_geometry(floor.cf_logs, nominal, options);
  if (!outcome) {
    error = "CF fit: " + outcome.error.message;
    return false;
  }
  floor.cf_fit = outcome.result;
  fitted = outcome.result->geometry;
  return true;
}

/// Runs one floor: the straight calibration trials, the two estimates, and the unseen path.
/// The wheelbase to tell the firmware so that it drives the paper's eq. 7 as printed, where F_lat
/// and F_lon multiply the turn terms too, with the wheelbase l = `c.wheelbase_mm`. odocal's
/// drive keeps turn angles under F_lat, F_lon (the one model's composition rule,
/// drive::model::geometry_in_force: the wheelbase in force is s·wheelbase_mm); the protocol
/// reproduces the paper's drive, so the firmware is told l/s, which puts l itself in force
/// (docs/results.md, "Maddahi & Zareinia protocol"). With F_lat = F_lon = 1, s = 1: l unchanged.
float paper_wheelbase(const drive::DriveConfig& c) {
  const double l = static_cast<double>(c.wheelbase_mm);
  const drive::model::Geometry<double> in_force =
      drive::model::geometry_in_force(drive::model::Parameters<double>{
          static_cast<double>(c.wheel_diameter_mm), l, 0.0, static_cast<double>(c.c_l),
          static_cast<double>(c.c_r), static_cast<double>(c.f_lat), static_cast<double>(c.f_lon)});
  return static_cast<float>(l / (in_force.wheelbase / l));
}

/// 1. Straight trials with no correction (Maddahi section II): the end point and the wheel
///    rotations give one training row each, Ẋ = displacement / T and θ̇ = wheel angle / T. The
///    cruise speed is spread over the trials so that the regression sees a range of Ẋ.
///    @return false, with `error`, when a trial cannot run; `xdot_sum` the sum of the trials' Ẋ.
bool straight_trials(SimulatedRobot& robot, const drive::DriveConfig& base,
                     const ValidateOptions& o, ValidateFloor& floor, double& xdot_sum,
                     std::string& error, const ProgressFn& progress) {
  const drive::Path line = drive::make_line(static_cast<float>(floor.line_m));
  xdot_sum = 0.0;
  for (std::size_t i = 0; i < o.trials; ++i) {
    report_progress(progress, floor.name, "straight trial", i, o.trials);
    drive::DriveConfig c = base;
    const double f =
        o.trials > 1 ? static_cast<double>(i) / static_cast<double>(o.trials - 1) : 0.5;
    c.v_max_mps =
        static_cast<float>(o.trial_v_min_mps + f * (o.trial_v_max_mps - o.trial_v_min_mps));
    // Also spread the commanded curvature (a lateral factor around 1, in an order unrelated to
    // the speed): with both wheels always commanded alike, ẏ and θ̇ of every trial would be
    // proportional to ẋ and eq. 10 could not tell the wheels apart.
    const double g = std::fmod(static_cast<double>(i) * 0.6180339887498949, 1.0) * 2.0 - 1.0;
    c.f_lat = static_cast<float>(1.0 + o.trial_lateral_spread * g);
    c.wheelbase_mm = paper_wheelbase(c);
    if (!robot.configure(c)) {
      error = "trial configuration refused";
      return false;
    }
    TickLog log;
    log.source = floor.name + " straight trial " + std::to_string(i + 1);
    const RunOutcome out = run_path_logged(robot, line, log);
    floor.cf_logs.push_back(std::move(log));
    if (!out.completed || !(out.duration_s > 0.0)) {
      error = "a straight trial did not complete";
      return false;
    }
    const double t = out.duration_s;
    floor.training.push_back(calib::TrainingRow{out.measured.x_m / t, out.measured.y_m / t,
                                                out.measured.theta_rad / t, out.left_wheel_rad / t,
                                                out.right_wheel_rad / t});
    floor.stops.push_back(calib::StopPoint{out.measured.x_m * 1e3, out.measured.y_m * 1e3});
    xdot_sum += out.measured.x_m / t;
  }
  return true;
}

/// 2. The factors: eq. 4/5 from the stop points (reported for reference), then the linear
///    regression (CL) and the bootstrap (CB) of the wheel rates for the desired motion, straight
///    ahead at the trials' mean speed, Ẋ = (v, 0, 0), turned into F_lat, F_lon by eq. 7.
bool lateral_factors(const drive::DriveConfig& base, const ValidateOptions& o, std::uint64_t seed,
                     double xdot_sum, ValidateFloor& floor, calib::LateralResult& cl,
                     calib::LateralResult& cb, std::string& error) {
  const double nominal_d = static_cast<double>(base.wheel_diameter_mm);
  const double wheelbase = static_cast<double>(base.wheelbase_mm);
  calib::LateralInput lateral;
  lateral.trials = floor.stops.data();
  lateral.trial_count = floor.stops.size();
  lateral.length_mm = floor.line_m * 1e3;
  lateral.wheelbase_mm = wheelbase;
  lateral.left_diameter_mm = nominal_d;
  lateral.right_diameter_mm = nominal_d;
  if (calib::solve_lateral(lateral, floor.eq45) != calib::LateralStatus::ok) {
    floor.eq45 = calib::LateralResult{};
  }
  floor.unknown = calib::UnknownRow{xdot_sum / static_cast<double>(o.trials), 0.0, 0.0};
  std::vector<double> scratch(calib::bootstrap_scratch_count(o.replicates, 1));
  calib::BootstrapInput input;
  input.training = floor.training.data();
  input.training_count = floor.training.size();
  input.unknowns = &floor.unknown;
  input.unknown_count = 1;
  input.replicates = o.replicates;
  input.seed = seed;
  input.scratch = scratch.data();
  input.scratch_count = scratch.size();
  calib::BootstrapFit fit;
  const calib::BootstrapStatus status = calib::run_bootstrap(input, &floor.estimate, 1, fit);
  if (status != calib::BootstrapStatus::ok) {
    error = std::string("bootstrap: ") + calib::to_string(status);
    return false;
  }
  const calib::WheelGeometry geometry{wheelbase, nominal_d, nominal_d};
  calib::WheelRateSample sample{floor.unknown.xdot_mps, 0.0, 0.0, floor.estimate.lr_l,
                                floor.estimate.lr_r};
  if (calib::factors_from_wheel_rates(sample, geometry, cl) != calib::LateralStatus::ok) {
    error = "linear-regression factors are degenerate";
    return false;
  }
  sample.omega_l_radps = floor.estimate.boot_l;
  sample.omega_r_radps = floor.estimate.boot_r;
  if (calib::factors_from_wheel_rates(sample, geometry, cb) != calib::LateralStatus::ok) {
    error = "bootstrap factors are degenerate";
    return false;
  }
  return true;
}

/// 4. The unseen path, `o.runs` runs each with no correction, LR factors, bootstrap factors,
///    the true geometry (OR) and the fitted one (CF).
bool unseen_scenarios(SimulatedRobot& robot, const drive::DriveConfig& base,
                      const ValidateOptions& o, const calib::LateralResult& cl,
                      const calib::LateralResult& cb, const FitGeometry& cf, ValidateFloor& floor,
                      std::string& error, const ProgressFn& progress) {
  const double nominal_d = static_cast<double>(base.wheel_diameter_mm);
  const double wheelbase = static_cast<double>(base.wheelbase_mm);
  const drive::Path unseen = drive::make_unseen_path();
  const PathEnd goal = path_end(unseen);
  const calib::LateralResult none{};
  const sim::RobotModel& truth = robot.spec().truth;
  const FitGeometry oracle{truth.left_diameter_m * 1e3, truth.right_diameter_m * 1e3,
                           truth.wheelbase_m * 1e3};
  const FitGeometry told{nominal_d, nominal_d, wheelbase};
  struct Scenario {
    const char* name;
    calib::LateralResult factors;
    FitGeometry geometry;
  };
  const Scenario scenarios[5] = {{"NC", none, told},
                                 {"CL", cl, told},
                                 {"CB", cb, told},
                                 {"OR", none, oracle},
                                 {"CF", none, cf}};
  std::vector<AccuracyTrial> trials;
  for (const auto& [name, factors, geometry] : scenarios) {
    ValidateScenario s;
    s.name = name;
    s.factors = factors;
    s.c_l = geometry.wheel_diameter_left_mm / nominal_d;
    s.c_r = geometry.wheel_diameter_right_mm / nominal_d;
    s.wheelbase_mm = geometry.wheelbase_mm;
    drive::DriveConfig c = base;
    c.f_lat = static_cast<float>(factors.f_lat);
    c.f_lon = static_cast<float>(factors.f_lon);
    c.c_l = static_cast<float>(s.c_l);
    c.c_r = static_cast<float>(s.c_r);
    c.wheelbase_mm = static_cast<float>(s.wheelbase_mm);
    c.wheelbase_mm = paper_wheelbase(c);
    if (!robot.configure(c)) {
      error = std::string(name) + " factors outside the firmware's range";
      return false;
    }
    for (std::size_t i = 0; i < o.runs; ++i) {
      report_progress(progress, floor.name, std::string("unseen path ") + name, i, o.runs);
      std::vector<PathPoint> trace;
      TraceFn tracer;
      if (o.record_paths) {
        tracer = [&trace](const sim::WorldPose& p) { trace.push_back(PathPoint{p.x_m, p.y_m}); };
      }
      const RunOutcome out = robot.run_path(unseen, 600.0, tracer, 100u);
      if (!out.completed) {
        error = "an unseen-path run did not complete";
        return false;
      }
      const calib::EndError e{(out.measured.x_m - goal.x_m) * 1e3,
                              (out.measured.y_m - goal.y_m) * 1e3};
      s.errors.push_back(e);
      trials.push_back(AccuracyTrial{name, e});
      if (o.record_paths) {
        s.paths.push_back(std::move(trace));
      }
    }
    floor.scenarios.push_back(std::move(s));
  }
  try {
    floor.accuracy = compute_accuracy(trials, "NC");
  } catch (const std::exception& e) {
    error = e.what();
    return false;
  }
  return true;
}

bool run_floor(SimulatedRobot& robot, const drive::DriveConfig& base, const ValidateOptions& o,
               std::uint64_t seed, ValidateFloor& floor, std::string& error,
               const ProgressFn& progress) {
  robot.plant().set_bumps(floor.bump_height_m, floor.bump_spacing_m);
  double xdot_sum = 0.0;
  if (!straight_trials(robot, base, o, floor, xdot_sum, error, progress)) {
    return false;
  }
  calib::LateralResult cl;
  calib::LateralResult cb;
  if (!lateral_factors(base, o, seed, xdot_sum, floor, cl, cb, error)) {
    return false;
  }
  // 3. CF: the recommended calibration, fitted to the straight trials and to squares driven
  //    with the nominal geometry, all measured only where they stopped.
  FitGeometry cf;
  if (!run_cf(robot, base, o, floor, cf, error, progress)) {
    return false;
  }

  return unseen_scenarios(robot, base, o, cl, cb, cf, floor, error, progress);
}

}  // namespace

ValidateReport run_validate(const RobotSpec& robot_spec, std::uint64_t seed,
                            const ValidateOptions& options, const ProgressFn& progress) {
  ValidateReport report;
  report.seed = seed;
  report.options = options;
  RobotSpec spec = robot_spec;
  // Maddahi eq. 6/7 use the actual wheelbase l̂: the protocol corrects the wheels, not the
  // wheelbase. Tell the firmware the wheelbase that makes its turns right (what UMBmark's E_b
  // would give), so the figures measure what F_lat and F_lon can fix.
  const TrueErrors truth = true_errors(spec);
  spec.nominal.wheelbase_mm = static_cast<float>(truth.e_b * spec.nominal.wheelbase_mm);
  report.wheelbase_told_mm = static_cast<double>(spec.nominal.wheelbase_mm);
  SimulatedRobot robot(spec, seed);

  ValidateFloor smooth;
  smooth.name = "systematic";
  smooth.line_m = options.line_m;
  ValidateFloor bumps;
  bumps.name = "bumps";
  bumps.line_m = options.line_bumps_m;
  const bool robot_bumps = spec.truth.bump_height_m > 0.0;
  bumps.bump_height_m = robot_bumps ? spec.truth.bump_height_m : options.bump_height_m;
  bumps.bump_spacing_m = robot_bumps ? spec.truth.bump_spacing_m : options.bump_spacing_m;
  for (ValidateFloor* floor : {&smooth, &bumps}) {
    if (!run_floor(robot, spec.nominal, options, seed, *floor, report.error, progress)) {
      report.error = floor->name + ": " + report.error;
      report.simulated_s = robot.simulated_s();
      return report;
    }
    report.floors.push_back(std::move(*floor));
  }
  report.simulated_s = robot.simulated_s();
  report.ok = true;
  return report;
}

nlohmann::json validate_report_json(const ValidateReport& r) {
  nlohmann::json j;
  j["simulated_s"] = r.simulated_s;
  j["seed"] = r.seed;
  if (!r.ok) {
    j["error"] = r.error;
    return j;
  }
  j["wheelbase_told_mm"] = r.wheelbase_told_mm;
  for (const ValidateFloor& f : r.floors) {
    nlohmann::json fj = accuracy_to_json(f.accuracy, "NC");
    fj["bump_height_mm"] = f.bump_height_m * 1e3;
    fj["bump_spacing_mm"] = f.bump_spacing_m * 1e3;
    fj["line_mm"] = f.line_m * 1e3;
    fj["training_trials"] = f.training.size();
    nlohmann::json factors;
    for (const ValidateScenario& s : f.scenarios) {
      factors[s.name] = lateral_to_json(s.factors);
      nlohmann::json trials = nlohmann::json::array();
      for (const calib::EndError& e : s.errors) {
        trials.push_back(
            {{"x_mm", e.x_mm}, {"y_mm", e.y_mm}, {"r_mm", std::hypot(e.x_mm, e.y_mm)}});
      }
      for (nlohmann::json& sj : fj["scenarios"]) {
        if (sj["name"] == s.name) {
          sj["f_lat"] = s.factors.f_lat;
          sj["f_lon"] = s.factors.f_lon;
          sj["c_l"] = s.c_l;
          sj["c_r"] = s.c_r;
          sj["wheelbase_mm"] = s.wheelbase_mm;
          sj["runs"] = trials;
        }
      }
    }
    fj["eq4_5"] = lateral_to_json(f.eq45);
    if (f.cf_fit) {
      nlohmann::json cf = fit_result_json(*f.cf_fit);
      fj["cf"] = {{"procedure",
                   {{"straight_trials", f.training.size()},
                    {"squares_per_direction", r.options.cf_squares},
                    {"square_side_mm", r.options.cf_side_m * 1e3}}},
                  {"wheel_diameter_left_mm", cf["wheel_diameter_left_mm"]},
                  {"wheel_diameter_right_mm", cf["wheel_diameter_right_mm"]},
                  {"wheelbase_mm", cf["wheelbase_mm"]},
                  {"relative_sd", cf["relative_sd"]},
                  {"fit", cf["fit"]}};
    }
    fj["estimate"] = {{"xdot_mps", f.unknown.xdot_mps},
                      {"lr_l", f.estimate.lr_l},
                      {"lr_r", f.estimate.lr_r},
                      {"boot_l", f.estimate.boot_l},
                      {"boot_r", f.estimate.boot_r},
                      {"ci_l", {f.estimate.ci_l_lo, f.estimate.ci_l_hi}},
                      {"ci_r", {f.estimate.ci_r_lo, f.estimate.ci_r_hi}}};
    j[f.name] = fj;
  }
  return j;
}

std::string validate_report_text(const ValidateReport& r) {
  std::ostringstream out;
  out << "Maddahi & Zareinia protocol on the simulated robot (seed " << r.seed << ")\n";
  if (!r.ok) {
    out << "failed: " << r.error << "\n";
    return out.str();
  }
  out << fmt::format(
      FMT_STRING("firmware told the actual wheelbase l = {:.2f} mm (eq. 7 assumes it known)\n"),
      r.wheelbase_told_mm);
  for (const ValidateFloor& f : r.floors) {
    out << "\n== " << f.name;
    if (f.bump_height_m > 0.0) {
      out << fmt::format(FMT_STRING(" ({:.0f} mm bumps every {:.0f} mm)"), f.bump_height_m * 1e3,
                         f.bump_spacing_m * 1e3);
    }
    out << fmt::format(FMT_STRING(": {:.0f} straight trials of {:.0f} mm\n"),
                       static_cast<double>(f.training.size()), f.line_m * 1e3);
    out << fmt::format(FMT_STRING("  eq. 4/5 from the stop points:  F_lat {:.5f}  F_lon {:.5f}\n"),
                       f.eq45.f_lat, f.eq45.f_lon);
    for (const ValidateScenario& s : f.scenarios) {
      if (s.name == "CL" || s.name == "CB") {
        out << "  " << s.name
            << fmt::format(FMT_STRING(" factors:  F_lat {:.5f}  F_lon {:.5f}\n"), s.factors.f_lat,
                           s.factors.f_lon);
      } else if (s.name != "NC") {
        out << "  " << s.name
            << fmt::format(FMT_STRING(" geometry: c_l {:.5f}  c_r {:.5f}  wheelbase {:.2f} mm"),
                           s.c_l, s.c_r, s.wheelbase_mm)
            << (s.name == "OR" ? " (the truth)\n" : " (odocal fit of the CF trials)\n");
      }
    }
    out << "  Unseen path (100 cm square, 100 cm triangle, 80 cm semicircle), END-point error:\n";
    out << "  scenario trial     x_e mm     y_e mm     r_e mm     RMS mm    k_I\n";
    for (const ValidateScenario& s : f.scenarios) {
      const ScenarioAccuracy* acc = nullptr;
      for (const ScenarioAccuracy& a : f.accuracy) {
        if (a.name == s.name)
          acc = &a;
      }
      for (std::size_t i = 0; i < s.errors.size(); ++i) {
        const calib::EndError& e = s.errors[i];
        out << "  " << s.name
            << fmt::format(FMT_STRING("       {:2.0f} {:10.1f} {:10.1f} {:10.1f}"), i + 1.0, e.x_mm,
                           e.y_mm, std::hypot(e.x_mm, e.y_mm));
        if (i == s.errors.size() / 2 && acc != nullptr) {
          out << fmt::format(FMT_STRING(" {:10.1f}"), acc->rms_mm);
          if (s.name != "NC" && acc->improvement_pct) {
            out << fmt::format(FMT_STRING("  {:5.1f}%"), *acc->improvement_pct);
          }
        }
        out << "\n";
      }
    }
  }
  out << fmt::format(FMT_STRING("\nsimulated {:.0f} s of robot time\n"), r.simulated_s);
  return out.str();
}

std::string validate_report_svg(const ValidateReport& r) {
  SvgFigure fig;
  if (!r.ok) {
    return fig.finish();
  }
  const char* colours[5] = {"#c0392b", "#e67e22", "#2471a3", "#7f8c8d", "#27ae60"};
  for (std::size_t i = 0; i < r.floors.size(); ++i) {
    const ValidateFloor& f = r.floors[i];
    SvgPanel& p = fig.panel(i, "Unseen path, " + f.name, "x, m", "y, m");
    for (std::size_t k = 0; k < f.scenarios.size() && k < 5; ++k) {
      for (const auto& path : f.scenarios[k].paths) {
        p.add_line(path, colours[k]);
      }
    }
    const PathEnd goal = path_end(drive::make_unseen_path());
    p.add_marker(goal.x_m, goal.y_m, "#000000", '+');
    p.add_marker(0.0, 0.0, "#000000", 'o');
    p.legend({{colours[0], "NC"},
              {colours[1], "CL"},
              {colours[2], "CB"},
              {colours[3], "OR"},
              {colours[4], "CF"},
              {"#000000", "start o, END +"}});
  }
  return fig.finish();
}

}  // namespace odocal::host
