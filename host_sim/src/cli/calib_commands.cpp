#include "odocal/host/calib_commands.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "odocal/calib/accuracy.hpp"
#include "odocal/calib/bootstrap.hpp"
#include "odocal/calib/lateral.hpp"
#include "odocal/calib/umbmark.hpp"
#include "odocal/host/calib_json.hpp"
#include "odocal/host/csv.hpp"

namespace odocal::host {
namespace {

using nlohmann::json;

/// Runs a handler; bad input (any exception) becomes exit status 2 and one line on stderr.
void guarded(const char* command, int& exit_code, const std::function<void()>& body) {
  try {
    body();
    exit_code = 0;
  } catch (const std::exception& e) {
    std::cerr << "odocal " << command << ": " << e.what() << '\n';
    exit_code = 2;
  }
}

std::string date_or_today(const std::string& date) {
  return date.empty() ? today_utc() : date;
}

/// Bounds as a person writes them: 1000000, 0.5 (no exponent for the bounds used here).
std::string bound(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.15g", value);
  return text;
}

/// A CLI11 check on a command-line number: the whole argument is a finite decimal number (no
/// nan, inf, hex or trailing junk) for which `ok` holds; otherwise CLI11 reports
/// "--FLAG: must be ALLOWED, got 'TEXT'" and `odocal` exits with status 2.
CLI::Validator number_check(const std::string& allowed, const std::function<bool(double)>& ok) {
  return CLI::Validator(
      [allowed, ok](std::string& text) {
        double value = 0.0;
        if (parse_finite(text, value) && ok(value)) {
          return std::string{};
        }
        return "must be " + allowed + ", got '" + text + "'";
      },
      "NUMBER");
}

/// A finite number in [low, high], with its unit in the message.
CLI::Validator range_check(double low, double high, const std::string& unit) {
  return number_check("a finite number from " + bound(low) + " to " + bound(high) + " " + unit,
                      [low, high](double v) { return v >= low && v <= high; });
}

/// A whole number in [low, high] (digits only: no sign, so -1 cannot wrap to 2^64 - 1).
CLI::Validator whole_check(std::uint64_t low, std::uint64_t high, const std::string& what) {
  return CLI::Validator(
      [low, high, what](std::string& text) {
        const std::string allowed = "a whole number " + what + (what.empty() ? "" : " ") + "from " +
                                    std::to_string(low) + " to " + std::to_string(high) +
                                    ", got '" + text + "'";
        if (text.empty() || text.size() > 20 ||
            text.find_first_not_of("0123456789") != std::string::npos) {
          return "must be " + allowed;
        }
        errno = 0;
        const unsigned long long value = std::strtoull(text.c_str(), nullptr, 10);
        if (errno == ERANGE || value < low || value > high) {
          return "must be " + allowed;
        }
        return std::string{};
      },
      "UINT");
}

bool leap_year(int year) {
  return (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
}

void add_date_option(CLI::App* cmd, std::string& date) {
  cmd->add_option("--date", date, "date recorded in the provenance (YYYY-MM-DD; default today)")
      ->check(CLI::Validator(
          [](std::string& value) {
            static const std::regex iso(R"(\d{4}-\d{2}-\d{2})");
            const std::string error =
                "must be a real date YYYY-MM-DD from 1970-01-01 to "
                "9999-12-31, got '" +
                value + "'";
            if (!std::regex_match(value, iso)) {
              return error;
            }
            const int year = std::stoi(value.substr(0, 4));
            const int month = std::stoi(value.substr(5, 2));
            const int day = std::stoi(value.substr(8, 2));
            const int days[12] = {31, leap_year(year) ? 29 : 28, 31, 30, 31, 30, 31, 31, 30, 31, 30,
                                  31};
            if (year < 1970 || month < 1 || month > 12 || day < 1 || day > days[month - 1]) {
              return error;
            }
            return std::string{};
          },
          "DATE"));
}

/// One JSON object on stdout. Strings that are not UTF-8 (e.g. a file name) come out with
/// U+FFFD instead of throwing.
void print_json(const json& object) {
  std::cout << object.dump(2, ' ', false, json::error_handler_t::replace) << '\n';
}

/// The path of the first number in `value` that is not finite, or "" if there is none.
std::string non_finite_at(const json& value, const std::string& path) {
  if (value.is_number_float() && !std::isfinite(value.get<double>())) {
    return path;
  }
  if (value.is_object()) {
    for (const auto& [key, item] : value.items()) {
      const std::string at = non_finite_at(item, path.empty() ? key : path + "." + key);
      if (!at.empty()) {
        return at;
      }
    }
  } else if (value.is_array()) {
    for (std::size_t i = 0; i < value.size(); ++i) {
      const std::string at = non_finite_at(value[i], path + "[" + std::to_string(i) + "]");
      if (!at.empty()) {
        return at;
      }
    }
  }
  return {};
}

/// Refuses a result with a NaN or infinity in it: nothing is printed that is not a number.
void require_finite(const json& result, const std::string& inputs) {
  const std::string at = non_finite_at(result, "");
  if (!at.empty()) {
    throw InputError(inputs, 0, at,
                     "the result is not a finite number: the inputs are too extreme to use");
  }
}

/// Reads a number and refuses it when its size is beyond anything the quantity can be.
double bounded_number(const CsvTable& table, std::size_t row, std::size_t column, double limit,
                      const char* unit) {
  const double value = table.number(row, column);
  if (std::fabs(value) > limit) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", value);
    table.fail(row, column,
               "absurd magnitude " + std::string(text) + ": must be at most " + bound(limit) + " " +
                   unit + " in size");
  }
  return value;
}

std::string line_span(const CsvTable& table) {
  if (table.rows.empty()) {
    return table.file;
  }
  return table.file + ":" + std::to_string(table.rows.front().line) + "-" +
         std::to_string(table.rows.back().line);
}

/// Too few data rows: the error points at the line after the header / last row.
[[noreturn]] void too_few(const CsvTable& table, std::size_t need, const std::string& what) {
  const std::size_t line = table.rows.empty() ? 1 : table.rows.back().line;
  throw InputError(table.file, line, table.columns.front(),
                   "too few " + what + ": " + std::to_string(table.rows.size()) +
                       ", need at least " + std::to_string(need));
}

std::string mm(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f mm", value);
  return text;
}

void print_number(const char* name, double value, const char* unit = "") {
  const double shown = value == 0.0 ? 0.0 : value;  // never "-0"
  std::printf("%-26s %.6g%s%s\n", name, shown, *unit != '\0' ? " " : "", unit);
}

// ---------------------------------------------------------------- umbmark
struct UmbmarkOptions {
  double side_mm = 0.0;
  double wheelbase_mm = 0.0;
  std::string cw_file, ccw_file, date;
  bool json = false;
  bool exact = false;
};

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
                 "return error of " + mm(std::hypot(x, y)) +
                     " is larger than the whole path (4 sides = " + mm(path_mm) +
                     "): not a return error");
    }
    runs.push_back({x, y});
  }
  return runs;
}

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
struct AccuracyOptions {
  std::string file, baseline, date;
  bool json = false;
};

/// Largest end error `odocal accuracy` takes, mm: 10 km is no trial of a calibration path.
constexpr double accuracy_max_error_mm = 1e7;

/// Scenario names are printed in tables and JSON: printable ASCII only, so a stray byte of a
/// spreadsheet export cannot make the JSON invalid.
bool printable_ascii(const std::string& text) {
  for (const char c : text) {
    if (c < 0x20 || c > 0x7e) {
      return false;
    }
  }
  return true;
}

void run_accuracy(const AccuracyOptions& o) {
  const CsvTable table = read_csv(o.file, {"scenario", "trial", "x_mm", "y_mm"});
  std::vector<AccuracyTrial> trials;
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    if (table.text(r, 0).empty()) {
      table.fail(r, 0, "empty scenario name");
    }
    if (!printable_ascii(table.text(r, 0))) {
      table.fail(r, 0,
                 "scenario name has a character that is not printable ASCII (letters, digits, "
                 "spaces and punctuation only)");
    }
    (void)table.number(r, 1);
    trials.push_back({table.text(r, 0),
                      {bounded_number(table, r, 2, accuracy_max_error_mm, "mm"),
                       bounded_number(table, r, 3, accuracy_max_error_mm, "mm")}});
  }
  if (trials.empty()) {
    too_few(table, 1, "trials");
  }
  if (!o.baseline.empty()) {
    bool found = false;
    for (const auto& t : trials) {
      found = found || t.scenario == o.baseline;
    }
    if (!found) {
      throw InputError(o.file, 0, "scenario",
                       "no trials of the baseline scenario '" + o.baseline + "'");
    }
  }
  const std::string baseline = o.baseline.empty() ? trials.front().scenario : o.baseline;
  std::vector<ScenarioAccuracy> scenarios;
  try {
    scenarios = compute_accuracy(trials, baseline);
  } catch (const std::invalid_argument& e) {
    throw InputError(line_span(table), 0, "x_mm,y_mm", e.what());
  }
  const json out = accuracy_to_json(scenarios, baseline);
  require_finite(out, line_span(table));
  if (o.json) {
    Provenance p;
    p.method = "rms-radial-error";
    p.runs = trials.size();
    p.date = date_or_today(o.date);
    p.extra = {{"file", o.file}};
    print_json(with_provenance(out, p));
    return;
  }
  std::printf("%-12s %6s %12s %16s\n", "scenario", "trials", "rms_mm", "improvement_pct");
  for (const auto& s : scenarios) {
    char improvement[32] = "n/a";  // baseline RMS 0: nothing to improve on (JSON null)
    if (s.improvement_pct) {
      std::snprintf(improvement, sizeof improvement, "%.1f", *s.improvement_pct);
    }
    std::printf("%-12s %6zu %12.1f %16s\n", s.name.c_str(), s.trials, s.rms_mm, improvement);
  }
  std::printf("(improvement = 100 (1 - rms / rms of %s))\n", baseline.c_str());
}

// ---------------------------------------------------------------- lateral
struct LateralOptions {
  std::string file, date;
  double length_mm = 0.0, wheelbase_mm = 0.0, dl_mm = 0.0, dr_mm = 0.0, theta_l_rad = 0.0;
  bool json = false;
};

/// A measured θ_L further than this factor from the nominal 2L/D_L is not a rotation of that
/// wheel over the trial (wrong unit, wrong wheel), and would scale F_lat by the same factor.
constexpr double theta_l_max_factor = 2.0;

void run_lateral(const LateralOptions& o) {
  if (o.theta_l_rad > 0.0) {
    const double nominal = 2.0 * o.length_mm / o.dl_mm;
    if (!(o.theta_l_rad >= nominal / theta_l_max_factor &&
          o.theta_l_rad <= nominal * theta_l_max_factor)) {
      char allowed[160];
      std::snprintf(allowed, sizeof allowed,
                    "must be within a factor of %g of the nominal 2L/D_L = %.6g rad (%.6g to "
                    "%.6g rad), got %g",
                    theta_l_max_factor, nominal, nominal / theta_l_max_factor,
                    nominal * theta_l_max_factor, o.theta_l_rad);
      throw InputError("(command line)", 0, "--theta-l-rad", allowed);
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
                 "stop point is " + mm(std::hypot(o.length_mm - x, y)) +
                     " from the commanded end, more than the path length " + mm(o.length_mm));
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
struct BootstrapOptions {
  std::string training_file, unknowns_file, date, interval = "percentile";
  std::uint32_t replicates = 2000;
  std::uint64_t seed = 1;
  double level = 0.95;
  double wheelbase_mm = 0.0, dl_mm = 0.0, dr_mm = 0.0;
  bool json = false;
};

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

void run_bootstrap(const BootstrapOptions& o) {
  const int geometry_given =
      (o.wheelbase_mm > 0.0 ? 1 : 0) + (o.dl_mm > 0.0 ? 1 : 0) + (o.dr_mm > 0.0 ? 1 : 0);
  if (geometry_given != 0 && geometry_given != 3) {
    throw InputError(
        "(command line)", 0,
        o.wheelbase_mm > 0.0 ? (o.dl_mm > 0.0 ? "--dr-mm" : "--dl-mm") : "--wheelbase-mm",
        "give all of --wheelbase-mm, --dl-mm and --dr-mm (for the eq. 7 factors), "
        "or none");
  }
  const bool geometry = geometry_given == 3;
  const CsvTable training_table =
      read_csv(o.training_file, {"xdot", "ydot", "thetadot", "omega_l", "omega_r"});
  const CsvTable unknowns_table = read_csv(o.unknowns_file, {"xdot", "ydot", "thetadot"});
  // Each unknown takes B predictions (2 doubles each, kept for the percentiles): bound the
  // memory and the work before any of it is spent, rather than fail in the allocator.
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
                         bound(bootstrap_max_predictions) + " predictions: at most " +
                         std::to_string(fit) + " unknowns with this --b (split the file)");
  }
  std::vector<calib::TrainingRow> training;
  for (std::size_t r = 0; r < training_table.rows.size(); ++r) {
    const calib::UnknownRow x = read_body_velocity(training_table, r);
    training.push_back({x.xdot_mps, x.ydot_mps, x.thetadot_radps,
                        bounded_number(training_table, r, 3, bootstrap_max_wheel_radps, "rad/s"),
                        bounded_number(training_table, r, 4, bootstrap_max_wheel_radps, "rad/s")});
  }
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
  calib::BootstrapFit fit;
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

  json out = bootstrap_to_json(estimates, fit);
  if (geometry) {
    // Maddahi eq. 7: the corrective factors implied by each estimate of the wheel velocities;
    // null for an unknown where eq. 7 has no finite positive solution (e.g. standing still).
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
  std::printf("Residual bootstrap: %zu training trials, B = %u, seed %llu, %g%% %s interval\n",
              training.size(), o.replicates, static_cast<unsigned long long>(o.seed),
              100.0 * o.level, p.interval->c_str());
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

// ---------------------------------------------------------------- ros2
struct Ros2Options {
  std::string from_file, controller = "diff_drive_controller";
  std::optional<double> c_l, c_r, e_b;
};

/// Largest multiplier `odocal ros2` writes: a factor of 10 corrects no real robot.
constexpr double ros2_max_multiplier = 10.0;

const std::string multiplier_allowed =
    "a finite number > 0 and at most " + bound(ros2_max_multiplier);

double multiplier_key(const json& object, const std::string& file, const char* key) {
  if (!object.contains(key)) {
    throw InputError(file, 0, key, "missing key (expected the JSON of `odocal umbmark --json`)");
  }
  const json& value = object.at(key);
  if (!value.is_number() || !std::isfinite(value.get<double>()) || !(value.get<double>() > 0.0) ||
      value.get<double>() > ros2_max_multiplier) {
    throw InputError(file, 0, key,
                     "must be " + multiplier_allowed + ", got " +
                         value.dump(-1, ' ', false, json::error_handler_t::replace));
  }
  return value.get<double>();
}

/// A ROS 2 node / controller name: a letter or '_', then letters, digits or '_'
/// (rmw_validate_node_name), at most 255 characters.
bool ros2_name(const std::string& name) {
  static const std::regex pattern("[A-Za-z_][A-Za-z0-9_]*");
  return name.size() <= 255 && std::regex_match(name, pattern);
}

/// The shortest text that reads back as exactly `value`, always with a '.' so that YAML (and
/// rcl_yaml_param_parser) reads a double, never an integer: 1 -> "1.0", 1e-05 -> "1.0e-05".
std::string yaml_double(double value) {
  char text[64];
  const auto [end, error] = std::to_chars(text, text + sizeof text, value);
  std::string out = error == std::errc{} ? std::string(text, end) : std::string("0");
  if (out.find('.') == std::string::npos) {
    const auto exponent = out.find_first_of("eE");
    out.insert(exponent == std::string::npos ? out.size() : exponent, ".0");
  }
  return out;
}

/// Text from a JSON file that goes into a YAML comment: printable ASCII only, so that a newline
/// in it cannot start a YAML line of its own.
std::string comment_text(const json& value) {
  std::string text = value.is_string() ? value.get<std::string>()
                                       : value.dump(-1, ' ', false, json::error_handler_t::replace);
  for (char& c : text) {
    if (c < 0x20 || c > 0x7e) {
      c = '?';
    }
  }
  return text;
}

void run_ros2(const Ros2Options& o) {
  if (!ros2_name(o.controller)) {
    throw InputError("(command line)", 0, "--controller",
                     "must be a ROS 2 controller name: a letter or '_', then letters, digits or "
                     "'_' (at most 255), got '" +
                         comment_text(json(o.controller)) + "'");
  }
  double c_l = 0.0, c_r = 0.0, e_b = 0.0;
  std::string source;
  if (!o.from_file.empty()) {
    const std::string text = read_text_file(o.from_file);
    json doc;
    JsonProblem problem;
    if (!parse_json_strict(text, doc, problem)) {
      throw InputError(o.from_file, problem.line, problem.key, problem.message);
    }
    if (!doc.is_object()) {
      throw InputError(o.from_file, 1, "", "expected a JSON object");
    }
    c_l = multiplier_key(doc, o.from_file, "c_l");
    c_r = multiplier_key(doc, o.from_file, "c_r");
    e_b = multiplier_key(doc, o.from_file, "e_b");
    source = comment_text(json(o.from_file));
    if (doc.contains("provenance") && doc["provenance"].is_object()) {
      const auto& p = doc["provenance"];
      const auto field = [&p](const char* key) {
        return p.contains(key) ? comment_text(p[key]) : std::string("?");
      };
      source += " (" + field("method") + ", " + field("runs") + " runs, " + field("date") + ")";
    }
  } else {
    if (!o.c_l || !o.c_r || !o.e_b) {
      throw InputError("(command line)", 0,
                       !o.c_l   ? "--c-l"
                       : !o.c_r ? "--c-r"
                                : "--e-b",
                       "give --from FILE, or all of --c-l, --c-r and --e-b");
    }
    c_l = *o.c_l;
    c_r = *o.c_r;
    e_b = *o.e_b;
    source = "command line";
  }
  // diff_drive_controller multiplies the wheel separation and each wheel radius it is given:
  // E_b scales the wheelbase, c_L and c_R scale each wheel's distance per radian. ROS 2 declares
  // them as doubles and refuses an integer, so each value is written as a float literal.
  std::printf("# ROS 2 diff_drive_controller parameters from odocal (%s)\n", source.c_str());
  std::printf("%s:\n  ros__parameters:\n", o.controller.c_str());
  std::printf("    wheel_separation_multiplier: %s\n", yaml_double(e_b).c_str());
  std::printf("    left_wheel_radius_multiplier: %s\n", yaml_double(c_l).c_str());
  std::printf("    right_wheel_radius_multiplier: %s\n", yaml_double(c_r).c_str());
}

}  // namespace

// Command-line bounds: wide enough for any robot, narrow enough that no result overflows.
constexpr double min_length_mm = 1.0;
constexpr double max_path_length_mm = 1e6;  // 1 km: side of the square, length of a trial
constexpr double max_robot_size_mm = 1e4;   // 10 m: wheelbase, wheel diameter

CLI::Validator path_length_check() {
  return range_check(min_length_mm, max_path_length_mm, "mm");
}
CLI::Validator robot_size_check() {
  return range_check(min_length_mm, max_robot_size_mm, "mm");
}

void register_calib_commands(CLI::App& app, int& exit_code) {
  {
    auto o = std::make_shared<UmbmarkOptions>();
    auto* cmd = app.add_subcommand("umbmark", "UMBmark: E_d, E_b, c_L, c_R from cw/ccw runs");
    cmd->add_option("--side-mm", o->side_mm, "side L of the square, mm")
        ->required()
        ->check(path_length_check());
    cmd->add_option("--wheelbase-mm", o->wheelbase_mm, "wheelbase b used during the runs, mm")
        ->required()
        ->check(robot_size_check());
    cmd->add_option("--cw", o->cw_file, "CSV x_mm,y_mm of the clockwise return errors")->required();
    cmd->add_option("--ccw", o->ccw_file, "CSV x_mm,y_mm of the counter-clockwise return errors")
        ->required();
    cmd->add_flag("--json", o->json, "print one JSON object");
    cmd->add_flag("--exact", o->exact, "solve the square geometry without small angles");
    add_date_option(cmd, o->date);
    cmd->callback([o, &exit_code] { guarded("umbmark", exit_code, [o] { run_umbmark(*o); }); });
  }
  {
    auto o = std::make_shared<AccuracyOptions>();
    auto* cmd = app.add_subcommand("accuracy", "RMS radial error per scenario, improvement");
    cmd->add_option("file", o->file, "CSV scenario,trial,x_mm,y_mm")->required();
    cmd->add_option("--baseline", o->baseline, "scenario to compare with (default: the first)");
    cmd->add_flag("--json", o->json, "print one JSON object");
    add_date_option(cmd, o->date);
    cmd->callback([o, &exit_code] { guarded("accuracy", exit_code, [o] { run_accuracy(*o); }); });
  }
  {
    auto o = std::make_shared<LateralOptions>();
    auto* cmd = app.add_subcommand("lateral", "Maddahi F_lat (eq. 4), F_lon (eq. 5)");
    cmd->add_option("--trials", o->file, "CSV x_mm,y_mm of the stop points")->required();
    cmd->add_option("--length-mm", o->length_mm, "commanded length L, mm")
        ->required()
        ->check(path_length_check());
    cmd->add_option("--wheelbase-mm", o->wheelbase_mm, "wheelbase l, mm")
        ->required()
        ->check(robot_size_check());
    cmd->add_option("--dl-mm", o->dl_mm, "left wheel diameter D_L, mm")
        ->required()
        ->check(robot_size_check());
    cmd->add_option("--dr-mm", o->dr_mm, "right wheel diameter D_R, mm")
        ->required()
        ->check(robot_size_check());
    cmd->add_option("--theta-l-rad", o->theta_l_rad,
                    "left wheel rotation per trial, rad (default 2L/D_L; within a factor of 2 "
                    "of it)")
        ->check(number_check("a finite number of rad > 0", [](double v) { return v > 0.0; }));
    cmd->add_flag("--json", o->json, "print one JSON object");
    add_date_option(cmd, o->date);
    cmd->callback([o, &exit_code] { guarded("lateral", exit_code, [o] { run_lateral(*o); }); });
  }
  {
    auto o = std::make_shared<BootstrapOptions>();
    auto* cmd = app.add_subcommand("bootstrap", "Maddahi residual bootstrap of wheel velocities");
    cmd->add_option("--training", o->training_file,
                    "CSV xdot,ydot,thetadot,omega_l,omega_r (m/s, rad/s)")
        ->required();
    cmd->add_option("--unknowns", o->unknowns_file, "CSV xdot,ydot,thetadot")->required();
    cmd->add_option("--b", o->replicates, "bootstrap replicates B")
        ->check(whole_check(calib::bootstrap_min_replicates, calib::bootstrap_max_replicates,
                            "of replicates"))
        ->capture_default_str();
    cmd->add_option("--seed", o->seed, "random seed")
        ->check(whole_check(0, UINT64_MAX, ""))
        ->capture_default_str();
    cmd->add_option("--level", o->level, "interval level")
        ->check(number_check("a finite number strictly between 0 and 1 (e.g. 0.95)",
                             [](double v) { return v > 0.0 && v < 1.0; }))
        ->capture_default_str();
    cmd->add_option("--interval", o->interval,
                    "percentile (the paper's, default) or calibrated (t-widened percentile)")
        ->check(CLI::IsMember({"percentile", "calibrated"}))
        ->capture_default_str();
    cmd->add_option("--wheelbase-mm", o->wheelbase_mm,
                    "with --dl-mm and --dr-mm: also F_lat, F_lon per unknown (eq. 7)")
        ->check(robot_size_check());
    cmd->add_option("--dl-mm", o->dl_mm, "left wheel diameter, mm")->check(robot_size_check());
    cmd->add_option("--dr-mm", o->dr_mm, "right wheel diameter, mm")->check(robot_size_check());
    cmd->add_flag("--json", o->json, "print one JSON object");
    add_date_option(cmd, o->date);
    cmd->callback([o, &exit_code] { guarded("bootstrap", exit_code, [o] { run_bootstrap(*o); }); });
  }
  {
    auto o = std::make_shared<Ros2Options>();
    auto* cmd = app.add_subcommand("ros2", "ROS 2 diff_drive_controller parameter file");
    auto* from = cmd->add_option("--from", o->from_file, "JSON of `odocal umbmark --json`");
    const auto multiplier = [] {
      return number_check(multiplier_allowed,
                          [](double v) { return v > 0.0 && v <= ros2_max_multiplier; });
    };
    auto* c_l = cmd->add_option("--c-l", o->c_l, "left wheel factor c_L")->check(multiplier());
    auto* c_r = cmd->add_option("--c-r", o->c_r, "right wheel factor c_R")->check(multiplier());
    auto* e_b = cmd->add_option("--e-b", o->e_b, "wheelbase factor E_b")->check(multiplier());
    from->excludes(c_l)->excludes(c_r)->excludes(e_b);
    cmd->add_option("--controller", o->controller, "controller name ([A-Za-z_][A-Za-z0-9_]*)")
        ->capture_default_str();
    cmd->callback([o, &exit_code] { guarded("ros2", exit_code, [o] { run_ros2(*o); }); });
  }
}

}  // namespace odocal::host
