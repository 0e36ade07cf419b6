// `odocal session --procedure lateral`: Maddahi & Zareinia's straight-line trials at several
// cruise speeds, plus gentle timed arcs so that the body velocities (ẋ, ẏ, θ̇) of the training
// set span three dimensions (straight trials alone give ẏ and θ̇ proportional to ẋ: eq. 10 cannot
// tell the wheels apart). F_lat/F_lon from eq. 4-5 on the straight trials, and from the linear
// regression and the residual bootstrap (eq. 7 at the trials' mean speed); the bootstrap's are
// applied when its design is sound, eq. 4-5's otherwise.

#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "model_in_force.hpp"
#include "odocal/calib/bootstrap.hpp"
#include "odocal/calib/lateral.hpp"
#include "odocal/calib/quantile.hpp"
#include "odocal/drive/robot_model.hpp"
#include "odocal/host/calib_json.hpp"
#include "session_internal.hpp"

namespace odocal::host::session {
namespace {

using std::numbers::pi;
constexpr std::uint32_t replicates = 2000;

struct Arc {
  double speed_share;  ///< of the cruise speed
  double w_radps;
  int ms;
};
/// Gentle arcs: 20-45° of turn each, both ways, at different speeds.
constexpr Arc arcs[lateral_arcs] = {
    {0.6, 0.2, 3500}, {0.9, -0.15, 4000}, {1.2, 0.1, 3500}, {0.75, -0.2, 3000}};

/// One training row in the body frame of the trial's mean motion: ẋ the speed along the path
/// (arc length / T, from the chord and the heading change φ of a constant-curvature arc), ẏ the
/// sideways speed (the chord's lean away from φ/2, the direction an arc's chord has), θ̇ = φ/T.
/// Start-frame chord velocities would understate an arc's speed by sin(φ/2)/(φ/2) and bias eq. 10.
calib::TrainingRow training_row(const RunRecord& r, double counts_per_rev) {
  const double t = r.duration_ms / 1000.0;
  const double phi = r.measured.theta_deg.value_or(r.odom.theta_deg.value_or(0.0)) * pi / 180.0;
  const double x = r.measured.x_mm / 1000.0;
  const double y = r.measured.y_mm / 1000.0;
  const double chord = std::hypot(x, y);
  const double half = 0.5 * phi;
  const double arc = chord / drive::model::half_turn(half).sinc;  // the chord is arc·sinc(φ/2)
  const double lean = std::atan2(y, x) - half;
  const double per_count = 2.0 * pi / counts_per_rev;
  return {arc / t, chord * std::sin(lean) / t, phi / t,
          static_cast<double>(r.count_l) * per_count / t,
          static_cast<double>(r.count_r) * per_count / t};
}

bool in_range(const calib::LateralResult& f) {
  return f.f_lat >= 0.5 && f.f_lat <= 2.0 && f.f_lon >= 0.5 && f.f_lon <= 2.0;
}

/// Whether the straight trials show each correction: eq. 4-5 solved trial by trial, the mean and
/// a Student-t 95 % interval of the corrections.
struct Shown {
  bool ok = false;  ///< at least 3 trials each with an answer
  bool f_lat = false;
  bool f_lon = false;
  double lat_lo = 1.0, lat_hi = 1.0, lon_lo = 1.0, lon_hi = 1.0;
};

Shown shown_corrections(const std::vector<calib::StopPoint>& stops,
                        const std::vector<double>& theta_l, calib::LateralInput input) {
  std::vector<double> lat, lon;
  for (std::size_t i = 0; i < stops.size(); ++i) {
    // The solver takes two trials at least: this one twice has its own mean.
    const calib::StopPoint twice[2] = {stops[i], stops[i]};
    input.trials = twice;
    input.trial_count = 2;
    input.theta_l_rad = theta_l[i];
    calib::LateralResult one;
    if (calib::solve_lateral(input, one) == calib::LateralStatus::ok) {
      lat.push_back(one.f_lat);
      lon.push_back(one.f_lon);
    }
  }
  Shown shown;
  const std::size_t n = lat.size();
  if (n < 3) {
    return shown;
  }
  const double t = calib::student_t_quantile(0.975, static_cast<double>(n - 1));
  const auto interval = [&](const std::vector<double>& v, double& lo, double& hi) {
    double mean = 0.0;
    for (double x : v) {
      mean += x;
    }
    mean /= static_cast<double>(n);
    double ss = 0.0;
    for (double x : v) {
      ss += (x - mean) * (x - mean);
    }
    const double half = t * std::sqrt(ss / static_cast<double>(n - 1) / static_cast<double>(n));
    lo = mean - half;
    hi = mean + half;
    return lo > 1.0 || hi < 1.0;
  };
  shown.ok = true;
  shown.f_lat = interval(lat, shown.lat_lo, shown.lat_hi);
  shown.f_lon = interval(lon, shown.lon_lo, shown.lon_hi);
  return shown;
}

/// The lateral procedure's state and its steps, in the order run_lateral takes them.
class LateralProcedure {
 public:
  explicit LateralProcedure(Context& c)
      : c(c), n(c.options.runs.value_or(10)), length_m(c.options.side_m.value_or(1.0)) {}

  /// The straight trials (cruise speeds spread from 0.5 to 1.5 of the robot's) and the arcs.
  void drive_trials() {
    c.need_measurements(n + lateral_arcs, "the lateral procedure (" + std::to_string(n) +
                                              " straight trials and " +
                                              std::to_string(lateral_arcs) + " arcs)");
    c.planned = n + lateral_arcs;
    in_force = c.factors();
    diameter = c.get(ParamId::wheel_diameter_mm);
    counts_per_rev = c.get(ParamId::counts_per_rev);
    cruise = c.get(ParamId::v_max_mps);
    c.log << "Lateral: " << n << " straight trials of " << fmt::format("{:.3f}", length_m)
          << " m at cruise speeds from " << fmt::format("{:.3f}", 0.5 * cruise) << " to "
          << fmt::format("{:.3f}", 1.5 * cruise) << " m/s, then " << lateral_arcs
          << " gentle arcs (timed drives).\nPlace the robot on the start mark, aligned with the "
             "line, before each run; measure where its reference point stopped.\n";

    try {
      for (std::size_t i = 0; i < n; ++i) {
        const double share = n > 1 ? static_cast<double>(i) / static_cast<double>(n - 1) : 0.5;
        const double v = c.set(ParamId::v_max_mps, cruise * (0.5 + share));
        const RunRecord r =
            c.run("line", Motion::line(length_m), c.path_seconds(length_m, 0.0, 1) * cruise / v);
        stops.push_back({r.measured.x_mm, r.measured.y_mm});
        training.push_back(training_row(r, counts_per_rev));
        xdot_sum += training.back().xdot_mps;
        theta_l.push_back(static_cast<double>(r.count_l) * 2.0 * pi / counts_per_rev);
        theta_l_sum += theta_l.back();
      }
    } catch (...) {
      static_cast<void>(c.robot.command("set v_max_mps " + fmt::format("{:.6f}", cruise)));
      throw;
    }
    c.set(ParamId::v_max_mps, cruise);
    for (const Arc& arc : arcs) {
      const RunRecord r = c.run("arc", Motion::timed(arc.speed_share * cruise, arc.w_radps, arc.ms),
                                arc.ms / 1000.0 + 2.0);
      training.push_back(training_row(r, counts_per_rev));
    }
  }

  /// lateral.csv and training.csv, what `odocal lateral` and `odocal bootstrap` read.
  void write_trial_files() {
    std::ostringstream lateral_csv, training_csv;
    lateral_csv << "# stop points of the straight trials, mm, start frame\nx_mm,y_mm\n";
    for (const auto& s : stops) {
      lateral_csv << fmt::format("{:.3f}", s.x_mm) << "," << fmt::format("{:.3f}", s.y_mm) << "\n";
    }
    training_csv << "# body frame of each trial's mean motion (see docs/calibration.md)\n"
                    "xdot,ydot,thetadot,omega_l,omega_r\n";
    for (const auto& t : training) {
      training_csv << fmt::format("{:.6f}", t.xdot_mps) << "," << fmt::format("{:.6f}", t.ydot_mps)
                   << "," << fmt::format("{:.6f}", t.thetadot_radps) << ","
                   << fmt::format("{:.6f}", t.omega_l_radps) << ","
                   << fmt::format("{:.6f}", t.omega_r_radps) << "\n";
    }
    c.write_file("lateral.csv", lateral_csv.str());
    c.write_file("training.csv", training_csv.str());
  }

  /// Eq. 4-5 for the drive that ran the trials, composed with the factors in force.
  void solve_eq45() {
    // Eq. 4-5: a correction of the drive that ran the trials. That drive already applied c_l, c_r
    // and the wheelbase in force, so eq. 4 sees equal diameters (their ratio is not counted
    // twice) and the result composes with the factors in force, as the robot's `lateral solve`.
    const double d_l = diameter;
    const double d_r = diameter;
    input.trials = stops.data();
    input.trial_count = stops.size();
    input.length_mm = length_m * 1000.0;
    input.wheelbase_mm = in_force.wheelbase_mm;
    input.left_diameter_mm = d_l;
    input.right_diameter_mm = d_r;
    input.theta_l_rad = theta_l_sum / static_cast<double>(n);
    eq45_status = calib::solve_lateral(input, eq45);
    eq45_total = calib::compose(calib::LateralResult{in_force.f_lat, in_force.f_lon, 0.0}, eq45);
    if (eq45_status == calib::LateralStatus::ok) {
      outcome.result["eq45"] = lateral_to_json(eq45);
      outcome.result["eq45"]["f_lat_in_force"] = eq45_total.f_lat;
      outcome.result["eq45"]["f_lon_in_force"] = eq45_total.f_lon;
      text << "Maddahi eq. 4-5 (" << n << " straight trials): correction f_lat "
           << fmt::format("{:.6f}", eq45.f_lat) << ", f_lon " << fmt::format("{:.6f}", eq45.f_lon)
           << " -> in force f_lat " << fmt::format("{:.6f}", eq45_total.f_lat) << ", f_lon "
           << fmt::format("{:.6f}", eq45_total.f_lon) << "\n";
    } else {
      outcome.result["eq45"] = nullptr;
      text << "Maddahi eq. 4-5: no answer (" << calib::to_string(eq45_status) << ")\n";
    }
  }

  /// Whether the trials show each correction.
  void show_corrections() {
    // Is each correction shown? Eq. 4-5 trial by trial gives the scatter of the correction; a
    // factor is changed only where its 95 % interval excludes "no correction" (1), so that noise
    // is never applied (after UMBmark the straight trials of a calibrated robot drift by noise).
    shown = shown_corrections(stops, theta_l, input);
    if (shown.ok) {
      outcome.result["shown"] = {{"f_lat", shown.f_lat},
                                 {"f_lon", shown.f_lon},
                                 {"ci_correction_f_lat", {shown.lat_lo, shown.lat_hi}},
                                 {"ci_correction_f_lon", {shown.lon_lo, shown.lon_hi}},
                                 {"level", 0.95}};
      text << "Shown by the trials (95% interval of the correction excludes 1): f_lat "
           << (shown.f_lat ? "yes" : "no") << " (" << fmt::format("{:.6f}", shown.lat_lo) << " .. "
           << fmt::format("{:.6f}", shown.lat_hi) << "), f_lon " << (shown.f_lon ? "yes" : "no")
           << " (" << fmt::format("{:.6f}", shown.lon_lo) << " .. "
           << fmt::format("{:.6f}", shown.lon_hi) << ")\n";
    }
  }

  /// Eq. 10 and the bootstrap of the wheel rates, turned into F_lat, F_lon by eq. 7.
  void bootstrap() {
    // Regression and bootstrap of the wheel rates (absolute: eq. 7 with the diameters in force).
    calib::BootstrapFit fit;
    const calib::BootstrapStatus fit_status =
        calib::fit_wheel_model(training.data(), training.size(), fit);
    const bool degenerate = fit_status != calib::BootstrapStatus::ok;
    outcome.result["degenerate"] = degenerate;
    if (degenerate) {
      text << "The bootstrap's design is degenerate (" << calib::to_string(fit_status)
           << "): the trials' body velocities do not span x, y and heading, so eq. 10 cannot "
              "separate the wheels. Its factors are not used.\n";
      outcome.result["bootstrap"] = nullptr;
    } else {
      const calib::UnknownRow unknown{xdot_sum / static_cast<double>(n), 0.0, 0.0};
      std::vector<double> scratch(calib::bootstrap_scratch_count(replicates, 1));
      calib::BootstrapInput b;
      b.training = training.data();
      b.training_count = training.size();
      b.unknowns = &unknown;
      b.unknown_count = 1;
      b.replicates = replicates;
      b.seed = c.options.seed;
      b.scratch = scratch.data();
      b.scratch_count = scratch.size();
      calib::BootstrapEstimate estimate;
      const calib::BootstrapStatus status = calib::run_bootstrap(b, &estimate, 1, fit);
      const calib::WheelGeometry geometry{in_force.wheelbase_mm, diameter * in_force.c_l,
                                          diameter * in_force.c_r};
      calib::LateralResult cl, cb;
      calib::WheelRateSample sample{unknown.xdot_mps, 0.0, 0.0, estimate.lr_l, estimate.lr_r};
      const bool cl_ok =
          status == calib::BootstrapStatus::ok &&
          calib::factors_from_wheel_rates(sample, geometry, cl) == calib::LateralStatus::ok;
      sample.omega_l_radps = estimate.boot_l;
      sample.omega_r_radps = estimate.boot_r;
      const bool cb_ok = cl_ok && calib::factors_from_wheel_rates(sample, geometry, cb) ==
                                      calib::LateralStatus::ok;
      if (cb_ok) {
        // Eq. 7 straight ahead: F_lon = θ̇_R·D_R/(2v) and F_lat = θ̇_L·D_L/(F_lon·2v), so the
        // wheel-rate prediction intervals map one to one (F_lat's at the point F_lon).
        const double two_v_mm = 2.0 * unknown.xdot_mps * 1000.0;
        const double lon_lo = estimate.ci_r_lo * geometry.right_diameter_mm / two_v_mm;
        const double lon_hi = estimate.ci_r_hi * geometry.right_diameter_mm / two_v_mm;
        const double lat_lo = estimate.ci_l_lo * geometry.left_diameter_mm / (cb.f_lon * two_v_mm);
        const double lat_hi = estimate.ci_l_hi * geometry.left_diameter_mm / (cb.f_lon * two_v_mm);
        outcome.result["regression"] = {{"f_lat", cl.f_lat}, {"f_lon", cl.f_lon}};
        outcome.result["bootstrap"] = {{"f_lat", cb.f_lat},
                                       {"f_lon", cb.f_lon},
                                       {"ci_f_lat", {lat_lo, lat_hi}},
                                       {"ci_f_lon", {lon_lo, lon_hi}},
                                       {"level", 0.95},
                                       {"replicates", replicates},
                                       {"seed", c.options.seed}};
        outcome.result["estimate"] = bootstrap_to_json({estimate}, fit);
        text << "Linear regression (eq. 10, " << training.size() << " trials): f_lat "
             << fmt::format("{:.6f}", cl.f_lat) << ", f_lon " << fmt::format("{:.6f}", cl.f_lon)
             << "\n"
             << "Bootstrap (B = " << replicates << "): f_lat " << fmt::format("{:.6f}", cb.f_lat)
             << " (95% " << fmt::format("{:.6f}", lat_lo) << " .. " << fmt::format("{:.6f}", lat_hi)
             << "), f_lon " << fmt::format("{:.6f}", cb.f_lon) << " (95% "
             << fmt::format("{:.6f}", lon_lo) << " .. " << fmt::format("{:.6f}", lon_hi)
             << ")\n  (prediction intervals: where one trial's factor would fall)\n";
        boot = cb;
      } else {
        outcome.result["bootstrap"] = nullptr;
        text << "The bootstrap gave no usable factors (eq. 7 has no positive solution).\n";
      }
    }
    std::ostringstream unknowns_csv;
    unknowns_csv << "xdot,ydot,thetadot\n"
                 << fmt::format("{:.6f}", xdot_sum / static_cast<double>(n)) << ",0,0\n";
    c.write_file("unknowns.csv", unknowns_csv.str());
  }

  /// Keeps what the trials do not show wrong, checks the rest against the one plausibility
  /// table, and puts it in force.
  void choose_and_apply() {
    if (boot && in_range(*boot)) {
      chosen = boot;
      from = "bootstrap";
    } else if (eq45_status == calib::LateralStatus::ok && in_range(eq45_total)) {
      chosen = eq45_total;
      from = "eq45";
    }
    // F_lat scales the left wheel's effective diameter (odometry and eq. 7 alike): the wheel ratio.
    // Where UMBmark or a fit measured that ratio (on squares of several metres, about ten times
    // more precisely than these 1 m lines), the straight trials do not replace it.
    const std::string wheel_method = c.robot.expect_ok("provenance").text("wheel_method");
    const bool ratio_calibrated =
        wheel_method == "umbmark" || wheel_method == "umbmark-exact" || wheel_method == "fit";
    outcome.result["ratio_calibrated_by"] =
        ratio_calibrated ? nlohmann::json(wheel_method) : nlohmann::json(nullptr);
    if (ratio_calibrated) {
      text << "The wheel ratio in force comes from " << wheel_method
           << ", which measures it more precisely than straight trials: f_lat is kept.\n";
    }
    if (chosen && shown.ok) {
      // Keep what the trials do not show wrong.
      if (!shown.f_lat || ratio_calibrated) {
        chosen->f_lat = in_force.f_lat;
      }
      if (!shown.f_lon) {
        chosen->f_lon = in_force.f_lon;
      }
      if ((!shown.f_lat || ratio_calibrated) && !shown.f_lon) {
        text << "Neither correction is shown by the trials: the factors in force are kept.\n";
        chosen.reset();
        outcome.result["applied_from"] = nullptr;
      }
    }
    if (chosen) {
      // The one table of plausible results (model_in_force.hpp).
      using plausible::maddahi;
      const PlausibleCheck checks[] = {{{"f_lat", maddahi[0], maddahi[1]}, chosen->f_lat},
                                       {{"f_lon", maddahi[0], maddahi[1]}, chosen->f_lon}};
      const std::string refusal = first_implausible(checks);
      if (!refusal.empty()) {
        throw std::runtime_error(
            "lateral: " + refusal +
            ". Nothing applied: check the wiring (docs/wiring.md), that each trial started on the "
            "mark, and the measurements.");
      }
    }
    if (!chosen) {
      if (!outcome.result.contains("applied_from")) {
        text << "Nothing applied: no factor in the firmware's range 0.5 .. 2.\n";
      }
      outcome.result["applied_from"] = nullptr;
    } else {
      if (from == "bootstrap") {
        // `lateral set` keeps the provenance honest: maddahi-bootstrap (docs/console.md).
        char line[96];
        std::snprintf(line, sizeof line, "lateral set %.6f %.6f %llu %zu", chosen->f_lat,
                      chosen->f_lon, static_cast<unsigned long long>(c.date()), c.runs.size());
        static_cast<void>(c.robot.expect_ok(line));
      } else {
        c.set(ParamId::f_lat, chosen->f_lat);  // eq. 4-5 computed on the host: provenance `manual`
        c.set(ParamId::f_lon, chosen->f_lon);
      }
      outcome.applied = true;
      outcome.result["applied_from"] = from;
      outcome.result["f_lat"] = chosen->f_lat;
      outcome.result["f_lon"] = chosen->f_lon;
      text << "Applied (" << from << "): f_lat " << fmt::format("{:.6f}", chosen->f_lat)
           << ", f_lon " << fmt::format("{:.6f}", chosen->f_lon) << "\n";
    }
  }

  Outcome finish() {
    c.log << text.str();
    outcome.text = text.str();
    return outcome;
  }

 private:
  Context& c;
  const std::size_t n;
  const double length_m;
  Factors in_force;
  double diameter = 0.0;
  double counts_per_rev = 0.0;
  double cruise = 0.0;
  std::vector<calib::StopPoint> stops;
  std::vector<calib::TrainingRow> training;
  double xdot_sum = 0.0;
  double theta_l_sum = 0.0;
  std::vector<double> theta_l;  // per straight trial, rad
  Outcome outcome;
  std::ostringstream text;
  calib::LateralInput input;
  calib::LateralResult eq45;
  calib::LateralStatus eq45_status = calib::LateralStatus::ok;
  calib::LateralResult eq45_total;
  Shown shown;
  std::optional<calib::LateralResult> boot;
  std::optional<calib::LateralResult> chosen;
  std::string from;
};

}  // namespace

Outcome run_lateral(Context& c) {
  LateralProcedure procedure(c);
  procedure.drive_trials();
  procedure.write_trial_files();
  procedure.solve_eq45();
  procedure.show_corrections();
  procedure.bootstrap();
  procedure.choose_and_apply();
  return procedure.finish();
}

}  // namespace odocal::host::session
