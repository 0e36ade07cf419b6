// `odocal lateral`: see docs/calibration.md.

#include "calib_cli.hpp"

namespace odocal::host::calib_cli {
namespace {

/// A measured θ_L further than this factor from the nominal 2L/D_L is not a rotation of that
/// wheel over the trial (wrong unit, wrong wheel), and would scale F_lat by the same factor.
constexpr double theta_l_max_factor = 2.0;

}  // namespace

void run_lateral(const LateralOptions& o) {
  if (o.theta_l_rad > 0.0) {
    const double nominal = 2.0 * o.length_mm / o.dl_mm;
    if (!(o.theta_l_rad >= nominal / theta_l_max_factor &&
          o.theta_l_rad <= nominal * theta_l_max_factor)) {
      throw InputError("(command line)", 0, "--theta-l-rad",
                       fmt::format("must be within a factor of {:g} of the nominal 2L/D_L = "
                                   "{:.6g} rad ({:.6g} to {:.6g} rad), got {:g}",
                                   theta_l_max_factor, nominal, nominal / theta_l_max_factor,
                                   nominal * theta_l_max_factor, o.theta_l_rad));
    }
  }
  CsvTable table = read_csv(o.file, {"x_mm", "y_mm"});
  if (table.rows.size() < 2) {
    too_few(table, 2, "trials");
  }
  if (table.rows.size() > calib::lateral_max_trials) {
    throw InputError(o.file, table.rows[calib::lateral_max_trials].line, "x_mm",
                     "too many trials: " + std::to_string(table.rows.size()) + ", at most " +
                         std::to_string(calib::lateral_max_trials));
  }
  std::vector<calib::StopPoint> trials;
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const double x = table.number(r, 0);
    const double y = table.number(r, 1);
    if (x <= 0.0) {
      table.fail(r, 0, "stop point is not ahead of the start (x <= 0)");
    }
    if (std::hypot(o.length_mm - x, y) > o.length_mm) {
      table.fail(r, std::fabs(o.length_mm - x) >= std::fabs(y) ? 0 : 1,
                 fmt::format("stop point is {:.1f} mm from the commanded end, more than the path "
                             "length {:.1f} mm",
                             std::hypot(o.length_mm - x, y), o.length_mm));
    }
    trials.push_back({x, y});
  }
  calib::LateralInput input;
  input.trials = trials.data();
  input.trial_count = trials.size();
  input.length_mm = o.length_mm;
  input.wheelbase_mm = o.wheelbase_mm;
  input.left_diameter_mm = o.dl_mm;
  input.right_diameter_mm = o.dr_mm;
  input.theta_l_rad = o.theta_l_rad;
  calib::LateralResult result;
  const calib::LateralStatus status = calib::solve_lateral(input, result);
  if (status != calib::LateralStatus::ok) {
    throw InputError(line_span(table), 0, "x_mm,y_mm", calib::to_string(status));
  }
  const json out = lateral_to_json(result);
  require_finite(out, line_span(table));
  if (o.json) {
    Provenance p;
    p.method = "maddahi-eq4-eq5";
    p.runs = trials.size();
    p.date = date_or_today(o.date);
    p.extra = {{"length_mm", o.length_mm},
               {"wheelbase_mm", o.wheelbase_mm},
               {"dl_mm", o.dl_mm},
               {"dr_mm", o.dr_mm},
               {"file", o.file}};
    print_json(with_provenance(out, p));
    return;
  }
  std::printf("Maddahi eq. 4-5, %zu straight trials of %g mm\n", trials.size(), o.length_mm);
  print_number("f_lat", result.f_lat);
  print_number("f_lon", result.f_lon);
  print_number("theta_L used", result.theta_l_rad, "rad");
}

// ---------------------------------------------------------------- bootstrap

}  // namespace odocal::host::calib_cli
