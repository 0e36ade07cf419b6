// `odocal bootstrap`: see docs/calibration.md.

#include "calib_cli.hpp"

namespace odocal::host::calib_cli {
namespace {

/// Largest body speed (m/s), yaw rate and wheel rate (rad/s) taken: far beyond any wheeled
/// robot, small enough that the least-squares sums cannot overflow.
constexpr double bootstrap_max_speed_mps = 1e3;
constexpr double bootstrap_max_yaw_radps = 1e3;
constexpr double bootstrap_max_wheel_radps = 1e5;
// Unknowns one run takes, and predictions (unknowns x B) it computes: 1e7 predictions keep the
// scratch at 160 MB and the run at seconds.
constexpr std::size_t bootstrap_max_unknowns = 100000;
constexpr double bootstrap_max_predictions = 1e7;

/// Reads the three body-velocity columns (0..2) of a bootstrap CSV.
calib::UnknownRow read_body_velocity(const CsvTable& table, std::size_t r) {
  return {bounded_number(table, r, 0, bootstrap_max_speed_mps, "m/s"),
          bounded_number(table, r, 1, bootstrap_max_speed_mps, "m/s"),
          bounded_number(table, r, 2, bootstrap_max_yaw_radps, "rad/s")};
}

/// Names the design column that makes the training design degenerate, if one alone does.
[[noreturn]] void degenerate_design(const CsvTable& table,
                                    const std::vector<calib::TrainingRow>& rows) {
  const char* names[3] = {"xdot", "ydot", "thetadot"};
  for (int c = 0; c < 3; ++c) {
    bool all_zero = true;
    for (const auto& row : rows) {
      const double v = c == 0 ? row.xdot_mps : c == 1 ? row.ydot_mps : row.thetadot_radps;
      all_zero = all_zero && v == 0.0;
    }
    if (all_zero) {
      throw InputError(line_span(table), 0, names[c],
                       "degenerate design: the column is zero in every row, so its parameter is "
                       "not determined");
    }
  }
  throw InputError(line_span(table), 0, "xdot,ydot,thetadot",
                   calib::to_string(calib::BootstrapStatus::degenerate));
}

/// "%9.4f" of a ratio, or "n/a" where it is undefined.
std::string ratio_text(bool defined, double value) {
  char text[32] = "n/a";
  if (defined) {
    std::snprintf(text, sizeof text, "%.4f", value);
  }
  return text;
}

/// Whether the wheel geometry for the eq. 7 factors is given: all of it or none, else refused.
bool geometry_given(const BootstrapOptions& o) {
  const int given =
      (o.wheelbase_mm > 0.0 ? 1 : 0) + (o.dl_mm > 0.0 ? 1 : 0) + (o.dr_mm > 0.0 ? 1 : 0);
  if (given != 0 && given != 3) {
    throw InputError(
        "(command line)", 0,
        o.wheelbase_mm > 0.0 ? (o.dl_mm > 0.0 ? "--dr-mm" : "--dl-mm") : "--wheelbase-mm",
        "give all of --wheelbase-mm, --dl-mm and --dr-mm (for the eq. 7 factors), "
        "or none");
  }
  return given == 3;
}

/// Each unknown takes B predictions (2 doubles each, kept for the percentiles): bounds the
/// memory and the work before any of it is spent, rather than fail in the allocator.
void check_prediction_bounds(const BootstrapOptions& o, const CsvTable& unknowns_table) {
  if (unknowns_table.rows.size() > bootstrap_max_unknowns) {
    throw InputError(o.unknowns_file, unknowns_table.rows[bootstrap_max_unknowns].line, "xdot",
                     "too many unknowns: " + std::to_string(unknowns_table.rows.size()) +
                         ", at most " + std::to_string(bootstrap_max_unknowns));
  }
  if (static_cast<double>(unknowns_table.rows.size()) * o.replicates > bootstrap_max_predictions) {
    const std::size_t fit = static_cast<std::size_t>(bootstrap_max_predictions / o.replicates);
    throw InputError(o.unknowns_file,
                     unknowns_table.rows[fit < unknowns_table.rows.size() ? fit : 0].line, "xdot",
                     std::to_string(unknowns_table.rows.size()) +
                         " unknowns x B = " + std::to_string(o.replicates) + " is more than " +
                         bound_text(bootstrap_max_predictions) + " predictions: at most " +
                         std::to_string(fit) + " unknowns with this --b (split the file)");
  }
}

/// Reads the training trials: body velocity (columns 0..2) and wheel rates (3, 4).
std::vector<calib::TrainingRow> read_training(const CsvTable& table) {
  std::vector<calib::TrainingRow> training;
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const calib::UnknownRow x = read_body_velocity(table, r);
    training.push_back({x.xdot_mps, x.ydot_mps, x.thetadot_radps,
                        bounded_number(table, r, 3, bootstrap_max_wheel_radps, "rad/s"),
                        bounded_number(table, r, 4, bootstrap_max_wheel_radps, "rad/s")});
  }
  return training;
}

/// Runs the bootstrap on the rows read; a failure is reported against the training file.
std::vector<calib::BootstrapEstimate> solve_bootstrap(
    const BootstrapOptions& o, const CsvTable& training_table,
    const std::vector<calib::TrainingRow>& training, const std::vector<calib::UnknownRow>& unknowns,
    calib::BootstrapFit& fit) {
  calib::BootstrapInput input;
  input.training = training.data();
  input.training_count = training.size();
  input.unknowns = unknowns.data();
  input.unknown_count = unknowns.size();
  input.replicates = o.replicates;
  input.seed = o.seed;
  input.level = o.level;
  input.method = o.interval == "calibrated" ? calib::IntervalMethod::calibrated_percentile
                                            : calib::IntervalMethod::percentile;
  std::vector<double> scratch(calib::bootstrap_scratch_count(o.replicates, unknowns.size()));
  input.scratch = scratch.data();
  input.scratch_count = scratch.size();
  std::vector<calib::BootstrapEstimate> estimates(unknowns.size());
  const calib::BootstrapStatus status =
      calib::run_bootstrap(input, estimates.data(), estimates.size(), fit);
  switch (status) {
    case calib::BootstrapStatus::ok:
      break;
    case calib::BootstrapStatus::degenerate:
      degenerate_design(training_table, training);
    default:
      throw InputError(line_span(training_table), 0, "xdot,ydot,thetadot,omega_l,omega_r",
                       calib::to_string(status));
  }
  return estimates;
}

/// Maddahi eq. 7: adds to each unknown of `out` the corrective factors implied by each estimate
/// of its wheel velocities; null where eq. 7 has no finite positive solution (standing still).
void add_factors(json& out, const BootstrapOptions& o,
                 const std::vector<calib::UnknownRow>& unknowns,
                 const std::vector<calib::BootstrapEstimate>& estimates) {
  const calib::WheelGeometry g{o.wheelbase_mm, o.dl_mm, o.dr_mm};
  for (std::size_t u = 0; u < unknowns.size(); ++u) {
    const auto& x = unknowns[u];
    const auto& e = estimates[u];
    const auto factors = [&](double omega_l, double omega_r) {
      calib::LateralResult f;
      const auto s = calib::factors_from_wheel_rates(
          {x.xdot_mps, x.ydot_mps, x.thetadot_radps, omega_l, omega_r}, g, f);
      return s == calib::LateralStatus::ok ? json{{"f_lat", f.f_lat}, {"f_lon", f.f_lon}}
                                           : json(nullptr);
    };
    out["unknowns"][u]["factors_lr"] = factors(e.lr_l, e.lr_r);
    out["unknowns"][u]["factors_boot"] = factors(e.boot_l, e.boot_r);
  }
}

/// Prints the estimates as a table (and the factors, when `geometry`) for a person.
void print_bootstrap_text(const BootstrapOptions& o, const Provenance& p, std::size_t trials,
                          const std::vector<calib::BootstrapEstimate>& estimates, const json& out,
                          bool geometry) {
  std::printf("Residual bootstrap: %zu training trials, B = %u, seed %llu, %g%% %s interval\n",
              trials, o.replicates, static_cast<unsigned long long>(o.seed), 100.0 * o.level,
              p.interval->c_str());
  std::printf("%3s %9s %9s %21s %9s %9s %21s %7s %7s\n", "#", "lr_l", "boot_l", "ci_l", "lr_r",
              "boot_r", "ci_r", "r_l", "r_r");
  for (std::size_t u = 0; u < estimates.size(); ++u) {
    const auto& e = estimates[u];
    std::printf("%3zu %9.4f %9.4f (%9.4f,%9.4f) %9.4f %9.4f (%9.4f,%9.4f) %7s %7s\n", u + 1, e.lr_l,
                e.boot_l, e.ci_l_lo, e.ci_l_hi, e.lr_r, e.boot_r, e.ci_r_lo, e.ci_r_hi,
                ratio_text(e.r_l_defined, e.r_l).c_str(), ratio_text(e.r_r_defined, e.r_r).c_str());
  }
  if (geometry) {
    std::printf("%3s %9s %9s %9s %9s\n", "#", "f_lat_lr", "f_lon_lr", "f_lat_bt", "f_lon_bt");
    for (std::size_t u = 0; u < estimates.size(); ++u) {
      const auto& f = out["unknowns"][u];
      std::printf("%3zu", u + 1);
      for (const char* which : {"factors_lr", "factors_boot"}) {
        for (const char* key : {"f_lat", "f_lon"}) {
          const bool known = f[which].is_object();
          std::printf(" %9s", ratio_text(known, known ? f[which][key].get<double>() : 0.0).c_str());
        }
      }
      std::printf("\n");
    }
  }
}

}  // namespace

void run_bootstrap(const BootstrapOptions& o) {
  const bool geometry = geometry_given(o);
  const CsvTable training_table =
      read_csv(o.training_file, {"xdot", "ydot", "thetadot", "omega_l", "omega_r"});
  const CsvTable unknowns_table = read_csv(o.unknowns_file, {"xdot", "ydot", "thetadot"});
  check_prediction_bounds(o, unknowns_table);
  const std::vector<calib::TrainingRow> training = read_training(training_table);
  std::vector<calib::UnknownRow> unknowns;
  for (std::size_t r = 0; r < unknowns_table.rows.size(); ++r) {
    unknowns.push_back(read_body_velocity(unknowns_table, r));
  }
  if (training.size() < calib::bootstrap_min_training) {
    too_few(training_table, calib::bootstrap_min_training, "training trials");
  }
  if (training.size() > calib::bootstrap_max_training) {
    throw InputError(
        o.training_file, training_table.rows[calib::bootstrap_max_training].line, "xdot",
        "too many training trials (at most " + std::to_string(calib::bootstrap_max_training) + ")");
  }
  if (unknowns.empty()) {
    too_few(unknowns_table, 1, "unknowns");
  }
  calib::BootstrapFit fit;
  const std::vector<calib::BootstrapEstimate> estimates =
      solve_bootstrap(o, training_table, training, unknowns, fit);

  json out = bootstrap_to_json(estimates, fit);
  if (geometry) {
    add_factors(out, o, unknowns, estimates);
  }
  require_finite(out, line_span(training_table) + " and " + line_span(unknowns_table));
  Provenance p;
  p.method = "maddahi-residual-bootstrap";
  p.runs = training.size();
  p.interval = o.interval == "calibrated" ? "percentile-t-calibrated" : "percentile";
  p.level = o.level;
  p.date = date_or_today(o.date);
  p.extra = {{"replicates", o.replicates},
             {"seed", o.seed},
             {"effective_level", fit.effective_level},
             {"unknowns", unknowns.size()},
             {"training_file", o.training_file},
             {"unknowns_file", o.unknowns_file}};
  if (o.json) {
    print_json(with_provenance(out, p));
    return;
  }
  print_bootstrap_text(o, p, training.size(), estimates, out, geometry);
}

// ---------------------------------------------------------------- ros2

}  // namespace odocal::host::calib_cli
