// `odocal session --procedure lateral`: Maddahi & Zareinia's straight-line trials at several
// cruise speeds, plus gentle timed arcs so that the body velocities (ẋ, ẏ, θ̇) of the training
// set span three dimensions (straight trials alone give ẏ and θ̇ proportional to ẋ: eq. 10 cannot
// tell the wheels apart). F_lat/F_lon from eq. 4-5 on the straight trials, and from the linear
// regression and the residual bootstrap (eq. 7 at the trials' mean speed); the bootstrap's are
// applied when its design is sound, eq. 4-5's otherwise.

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "odocal/calib/bootstrap.hpp"
#include "odocal/calib/lateral.hpp"
#include "odocal/host/calib_json.hpp"
#include "session_internal.hpp"

namespace odocal::host::session {
namespace {

constexpr double pi = 3.14159265358979323846;
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
  const double arc = std::fabs(half) > 1e-9 ? chord * half / std::sin(half) : chord;
  const double lean = std::atan2(y, x) - half;
  const double per_count = 2.0 * pi / counts_per_rev;
  return {arc / t, chord * std::sin(lean) / t, phi / t,
          static_cast<double>(r.count_l) * per_count / t,
          static_cast<double>(r.count_r) * per_count / t};
}

bool in_range(const calib::LateralResult& f) {
  return f.f_lat >= 0.5 && f.f_lat <= 2.0 && f.f_lon >= 0.5 && f.f_lon <= 2.0;
}

}  // namespace

Outcome run_lateral(Context& c) {
  const std::size_t n = c.options.runs.value_or(10);
  const double length_m = c.options.side_m.value_or(1.0);
  c.need_measurements(n + lateral_arcs, "the lateral procedure (" + std::to_string(n) +
                                            " straight trials and " + std::to_string(lateral_arcs) +
                                            " arcs)");
  c.planned = n + lateral_arcs;
  const Factors in_force = c.factors();
  const double diameter = c.get("wheel_diameter_mm");
  const double counts_per_rev = c.get("counts_per_rev");
  const double cruise = c.get("v_max_mps");
  c.log << "Lateral: " << n << " straight trials of " << fmt::format("{:.3f}", length_m)
        << " m at cruise speeds from " << fmt::format("{:.3f}", 0.5 * cruise) << " to "
        << fmt::format("{:.3f}", 1.5 * cruise) << " m/s, then " << lateral_arcs
        << " gentle arcs (timed drives).\nPlace the robot on the start mark, aligned with the "
           "line, before each run; measure where its reference point stopped.\n";

  std::vector<calib::StopPoint> stops;
  std::vector<calib::TrainingRow> training;
  double xdot_sum = 0.0;
  double theta_l_sum = 0.0;
  char line[96];
  try {
    for (std::size_t i = 0; i < n; ++i) {
      const double share = n > 1 ? static_cast<double>(i) / static_cast<double>(n - 1) : 0.5;
      const double v = c.set("v_max_mps", cruise * (0.5 + share));
      std::snprintf(line, sizeof line, "run line %.3f", length_m);
      const RunRecord r = c.run("line", line, c.path_seconds(length_m, 0.0, 1) * cruise / v);
      stops.push_back({r.measured.x_mm, r.measured.y_mm});
      training.push_back(training_row(r, counts_per_rev));
      xdot_sum += training.back().xdot_mps;
      theta_l_sum += static_cast<double>(r.count_l) * 2.0 * pi / counts_per_rev;
    }
  } catch (...) {
    static_cast<void>(c.robot.command("set v_max_mps " + fmt::format("{:.6f}", cruise)));
    throw;
  }
  c.set("v_max_mps", cruise);
  for (const Arc& arc : arcs) {
    std::snprintf(line, sizeof line, "drive %.3f %.3f %d", arc.speed_share * cruise, arc.w_radps,
                  arc.ms);
    const RunRecord r = c.run("arc", line, arc.ms / 1000.0 + 2.0);
    training.push_back(training_row(r, counts_per_rev));
  }

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

  Outcome outcome;
  std::ostringstream text;
  // Eq. 4-5: a correction of what drove the trials, so it composes with the factors in force.
  const double d_l = diameter * in_force.c_l;
  const double d_r = diameter * in_force.c_r;
  calib::LateralInput input;
  input.trials = stops.data();
  input.trial_count = stops.size();
  input.length_mm = length_m * 1000.0;
  input.wheelbase_mm = in_force.wheelbase_mm;
  input.left_diameter_mm = d_l;
  input.right_diameter_mm = d_r;
  input.theta_l_rad = theta_l_sum / static_cast<double>(n);
  calib::LateralResult eq45;
  const calib::LateralStatus eq45_status = calib::solve_lateral(input, eq45);
  calib::LateralResult eq45_total{in_force.f_lat * eq45.f_lat, in_force.f_lon * eq45.f_lon,
                                  eq45.theta_l_rad};
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

  // Regression and bootstrap of the wheel rates (absolute: eq. 7 with the diameters in force).
  calib::BootstrapFit fit;
  const calib::BootstrapStatus fit_status =
      calib::fit_wheel_model(training.data(), training.size(), fit);
  const bool degenerate = fit_status != calib::BootstrapStatus::ok;
  outcome.result["degenerate"] = degenerate;
  std::optional<calib::LateralResult> boot;
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
    const calib::WheelGeometry geometry{in_force.wheelbase_mm, d_l, d_r};
    calib::LateralResult cl, cb;
    calib::WheelRateSample sample{unknown.xdot_mps, 0.0, 0.0, estimate.lr_l, estimate.lr_r};
    const bool cl_ok =
        status == calib::BootstrapStatus::ok &&
        calib::factors_from_wheel_rates(sample, geometry, cl) == calib::LateralStatus::ok;
    sample.omega_l_radps = estimate.boot_l;
    sample.omega_r_radps = estimate.boot_r;
    const bool cb_ok =
        cl_ok && calib::factors_from_wheel_rates(sample, geometry, cb) == calib::LateralStatus::ok;
    if (cb_ok) {
      // Eq. 7 straight ahead: F_lon = θ̇_R·D_R/(2v) and F_lat = θ̇_L·D_L/(F_lon·2v), so the
      // wheel-rate prediction intervals map one to one (F_lat's at the point F_lon).
      const double two_v_mm = 2.0 * unknown.xdot_mps * 1000.0;
      const double lon_lo = estimate.ci_r_lo * d_r / two_v_mm;
      const double lon_hi = estimate.ci_r_hi * d_r / two_v_mm;
      const double lat_lo = estimate.ci_l_lo * d_l / (cb.f_lon * two_v_mm);
      const double lat_hi = estimate.ci_l_hi * d_l / (cb.f_lon * two_v_mm);
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

  std::optional<calib::LateralResult> chosen;
  std::string from;
  if (boot && in_range(*boot)) {
    chosen = boot;
    from = "bootstrap";
  } else if (eq45_status == calib::LateralStatus::ok && in_range(eq45_total)) {
    chosen = eq45_total;
    from = "eq45";
  }
  if (!chosen) {
    text << "Nothing applied: no factor in the firmware's range 0.5 .. 2.\n";
    outcome.result["applied_from"] = nullptr;
  } else {
    if (from == "bootstrap") {
      // `lateral set` keeps the provenance honest: maddahi-bootstrap (docs/console.md).
      char line[96];
      std::snprintf(line, sizeof line, "lateral set %.6f %.6f", chosen->f_lat, chosen->f_lon);
      static_cast<void>(c.robot.expect_ok(line));
    } else {
      c.set("f_lat", chosen->f_lat);  // eq. 4-5 computed on the host: provenance `manual`
      c.set("f_lon", chosen->f_lon);
    }
    outcome.applied = true;
    outcome.result["applied_from"] = from;
    outcome.result["f_lat"] = chosen->f_lat;
    outcome.result["f_lon"] = chosen->f_lon;
    text << "Applied (" << from << "): f_lat " << fmt::format("{:.6f}", chosen->f_lat) << ", f_lon "
         << fmt::format("{:.6f}", chosen->f_lon) << "\n";
  }
  c.log << text.str();
  outcome.text = text.str();
  return outcome;
}

}  // namespace odocal::host::session
