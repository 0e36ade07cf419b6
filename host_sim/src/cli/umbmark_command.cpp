// `odocal umbmark`: see docs/calibration.md.

#include "calib_cli.hpp"

namespace odocal::host::calib_cli {
namespace {

std::vector<calib::ReturnError> read_return_errors(const std::string& file, double path_mm,
                                                   CsvTable& table) {
  table = read_csv(file, {"x_mm", "y_mm"});
  if (table.rows.size() < 2) {
    too_few(table, 2, "runs in this direction");
  }
  if (table.rows.size() > calib::umbmark_max_runs) {
    throw InputError(file, table.rows[calib::umbmark_max_runs].line, "x_mm",
                     "too many runs (at most " + std::to_string(calib::umbmark_max_runs) + ")");
  }
  std::vector<calib::ReturnError> runs;
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const double x = table.number(r, 0);
    const double y = table.number(r, 1);
    if (std::hypot(x, y) > path_mm) {
      table.fail(r, std::fabs(x) >= std::fabs(y) ? 0 : 1,
                 fmt::format("return error of {:.1f} mm is larger than the whole path (4 sides = "
                             "{:.1f} mm): not a return error",
                             std::hypot(x, y), path_mm));
    }
    runs.push_back({x, y});
  }
  return runs;
}

}  // namespace

void run_umbmark(const UmbmarkOptions& o) {
  CsvTable cw_table, ccw_table;
  const auto cw = read_return_errors(o.cw_file, 4.0 * o.side_mm, cw_table);
  const auto ccw = read_return_errors(o.ccw_file, 4.0 * o.side_mm, ccw_table);
  calib::UmbmarkInput input;
  input.cw = cw.data();
  input.cw_count = cw.size();
  input.ccw = ccw.data();
  input.ccw_count = ccw.size();
  input.side_mm = o.side_mm;
  input.wheelbase_mm = o.wheelbase_mm;
  input.exact = o.exact;
  calib::UmbmarkResult result;
  const calib::UmbmarkStatus status = calib::solve_umbmark(input, result);
  if (status != calib::UmbmarkStatus::ok) {
    throw InputError(line_span(cw_table) + " and " + line_span(ccw_table), 0, "x_mm,y_mm",
                     calib::to_string(status));
  }
  Provenance p;
  p.method = o.exact ? "umbmark-exact" : "umbmark";
  p.runs = cw.size() + ccw.size();
  p.date = date_or_today(o.date);
  p.extra = {{"runs_cw", cw.size()},           {"runs_ccw", ccw.size()}, {"side_mm", o.side_mm},
             {"wheelbase_mm", o.wheelbase_mm}, {"cw_file", o.cw_file},   {"ccw_file", o.ccw_file}};
  if (o.exact) {
    p.extra["iterations"] = result.iterations;
  }
  const json out = umbmark_to_json(result);  // radius_mm is null for straight legs
  require_finite(out, line_span(cw_table) + " and " + line_span(ccw_table));
  if (o.json) {
    print_json(with_provenance(out, p));
    return;
  }
  std::printf("UMBmark (%s), %zu cw + %zu ccw runs, L = %g mm, b = %g mm\n",
              o.exact ? "exact square geometry" : "small-angle formulas", cw.size(), ccw.size(),
              o.side_mm, o.wheelbase_mm);
  print_number("centre cw x, y", result.x_cg_cw, "mm");
  print_number("", result.y_cg_cw, "mm");
  print_number("centre ccw x, y", result.x_cg_ccw, "mm");
  print_number("", result.y_cg_ccw, "mm");
  print_number("E_max,syst", result.e_max_syst_mm, "mm");
  print_number("alpha (turn error)", result.alpha_deg, "deg");
  print_number("beta (leg curvature)", result.beta_deg, "deg");
  if (std::isfinite(result.radius_mm)) {
    print_number("leg radius", result.radius_mm, "mm");
  } else {
    std::printf("%-26s %s\n", "leg radius", "inf (straight legs, beta = 0)");
  }
  print_number("E_d = D_R/D_L", result.e_d);
  print_number("E_b", result.e_b);
  print_number("c_l", result.c_l);
  print_number("c_r", result.c_r);
  print_number("new wheelbase", result.wheelbase_new_mm, "mm");
  print_number("sigma", result.sigma_mm, "mm");
  print_number("SEM", result.sem_mm, "mm");
  std::printf(
      "%-26s %s\n", "second pass recommended",
      result.second_pass_recommended ? "yes (E_max,syst >= 3 SEM)" : "no (E_max,syst < 3 SEM)");
}

// ---------------------------------------------------------------- accuracy

}  // namespace odocal::host::calib_cli
