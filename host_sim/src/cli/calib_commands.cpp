#include "odocal/host/calib_commands.hpp"

#include <cmath>
#include <cstdio>
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

void add_date_option(CLI::App* cmd, std::string& date) {
  cmd->add_option("--date", date, "date recorded in the provenance (YYYY-MM-DD; default today)")
      ->check(CLI::Validator(
          [](std::string& value) {
            static const std::regex iso(R"(\d{4}-\d{2}-\d{2})");
            return std::regex_match(value, iso) ? std::string{}
                                                : std::string{"expected YYYY-MM-DD"};
          },
          "DATE"));
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
  std::printf("%-26s %.6g%s%s\n", name, value, *unit != '\0' ? " " : "", unit);
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
  if (o.json) {
    std::cout << with_provenance(umbmark_to_json(result), p).dump(2) << '\n';
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

void run_accuracy(const AccuracyOptions& o) {
  const CsvTable table = read_csv(o.file, {"scenario", "trial", "x_mm", "y_mm"});
  std::vector<AccuracyTrial> trials;
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    if (table.text(r, 0).empty()) {
      table.fail(r, 0, "empty scenario name");
    }
    (void)table.number(r, 1);
    trials.push_back({table.text(r, 0), {table.number(r, 2), table.number(r, 3)}});
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
  const auto scenarios = compute_accuracy(trials, baseline);
  if (o.json) {
    Provenance p;
    p.method = "rms-radial-error";
    p.runs = trials.size();
    p.date = date_or_today(o.date);
    p.extra = {{"file", o.file}};
    std::cout << with_provenance(accuracy_to_json(scenarios, baseline), p).dump(2) << '\n';
    return;
  }
  std::printf("%-12s %6s %12s %16s\n", "scenario", "trials", "rms_mm", "improvement_pct");
  for (const auto& s : scenarios) {
    std::printf("%-12s %6zu %12.1f %16.1f\n", s.name.c_str(), s.trials, s.rms_mm,
                s.improvement_pct.value_or(0.0));
  }
  std::printf("(improvement = 100 (1 - rms / rms of %s))\n", baseline.c_str());
}

// ---------------------------------------------------------------- lateral
struct LateralOptions {
  std::string file, date;
  double length_mm = 0.0, wheelbase_mm = 0.0, dl_mm = 0.0, dr_mm = 0.0, theta_l_rad = 0.0;
  bool json = false;
};

void run_lateral(const LateralOptions& o) {
  CsvTable table = read_csv(o.file, {"x_mm", "y_mm"});
  if (table.rows.size() < 2) {
    too_few(table, 2, "trials");
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
    std::cout << with_provenance(lateral_to_json(result), p).dump(2) << '\n';
    return;
  }
  std::printf("Maddahi eq. 4-5, %zu straight trials of %g mm\n", trials.size(), o.length_mm);
  print_number("f_lat", result.f_lat);
  print_number("f_lon", result.f_lon);
  print_number("theta_L used", result.theta_l_rad, "rad");
}

// ---------------------------------------------------------------- bootstrap
struct BootstrapOptions {
  std::string training_file, unknowns_file, date, interval = "calibrated";
  std::uint32_t replicates = 2000;
  std::uint64_t seed = 1;
  double level = 0.95;
  double wheelbase_mm = 0.0, dl_mm = 0.0, dr_mm = 0.0;
  bool json = false;
};

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

void run_bootstrap(const BootstrapOptions& o) {
  const CsvTable training_table =
      read_csv(o.training_file, {"xdot", "ydot", "thetadot", "omega_l", "omega_r"});
  const CsvTable unknowns_table = read_csv(o.unknowns_file, {"xdot", "ydot", "thetadot"});
  std::vector<calib::TrainingRow> training;
  for (std::size_t r = 0; r < training_table.rows.size(); ++r) {
    training.push_back({training_table.number(r, 0), training_table.number(r, 1),
                        training_table.number(r, 2), training_table.number(r, 3),
                        training_table.number(r, 4)});
  }
  std::vector<calib::UnknownRow> unknowns;
  for (std::size_t r = 0; r < unknowns_table.rows.size(); ++r) {
    unknowns.push_back(
        {unknowns_table.number(r, 0), unknowns_table.number(r, 1), unknowns_table.number(r, 2)});
  }
  if (training.size() < calib::bootstrap_min_training) {
    too_few(training_table, calib::bootstrap_min_training, "training trials");
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
  input.method = o.interval == "percentile" ? calib::IntervalMethod::percentile
                                            : calib::IntervalMethod::calibrated_percentile;
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
    case calib::BootstrapStatus::degenerate_estimate:
      throw InputError(line_span(unknowns_table), 0, "xdot,ydot,thetadot",
                       calib::to_string(status));
    default:
      throw InputError(line_span(training_table), 0, "xdot,ydot,thetadot,omega_l,omega_r",
                       calib::to_string(status));
  }

  json out = bootstrap_to_json(estimates, fit);
  const bool geometry = o.wheelbase_mm > 0.0 && o.dl_mm > 0.0 && o.dr_mm > 0.0;
  if (geometry) {
    // Maddahi eq. 7: the corrective factors implied by each estimate of the wheel velocities.
    const calib::WheelGeometry g{o.wheelbase_mm, o.dl_mm, o.dr_mm};
    for (std::size_t u = 0; u < unknowns.size(); ++u) {
      const auto& x = unknowns[u];
      const auto& e = estimates[u];
      calib::LateralResult lr, boot;
      const auto s1 = calib::factors_from_wheel_rates(
          {x.xdot_mps, x.ydot_mps, x.thetadot_radps, e.lr_l, e.lr_r}, g, lr);
      const auto s2 = calib::factors_from_wheel_rates(
          {x.xdot_mps, x.ydot_mps, x.thetadot_radps, e.boot_l, e.boot_r}, g, boot);
      if (s1 != calib::LateralStatus::ok || s2 != calib::LateralStatus::ok) {
        throw InputError(o.unknowns_file, unknowns_table.rows[u].line, "xdot,ydot,thetadot",
                         std::string("eq. 7 factors: ") +
                             calib::to_string(s1 != calib::LateralStatus::ok ? s1 : s2));
      }
      out["unknowns"][u]["factors_lr"] = {{"f_lat", lr.f_lat}, {"f_lon", lr.f_lon}};
      out["unknowns"][u]["factors_boot"] = {{"f_lat", boot.f_lat}, {"f_lon", boot.f_lon}};
    }
  }
  Provenance p;
  p.method = "maddahi-residual-bootstrap";
  p.runs = training.size();
  p.interval = o.interval == "percentile" ? "percentile" : "percentile-t-calibrated";
  p.level = o.level;
  p.date = date_or_today(o.date);
  p.extra = {{"replicates", o.replicates},
             {"seed", o.seed},
             {"effective_level", fit.effective_level},
             {"unknowns", unknowns.size()},
             {"training_file", o.training_file},
             {"unknowns_file", o.unknowns_file}};
  if (o.json) {
    std::cout << with_provenance(out, p).dump(2) << '\n';
    return;
  }
  std::printf("Residual bootstrap: %zu training trials, B = %u, seed %llu, %g%% %s interval\n",
              training.size(), o.replicates, static_cast<unsigned long long>(o.seed),
              100.0 * o.level, p.interval->c_str());
  std::printf("%3s %9s %9s %21s %9s %9s %21s %7s %7s\n", "#", "lr_l", "boot_l", "ci_l", "lr_r",
              "boot_r", "ci_r", "r_l", "r_r");
  for (std::size_t u = 0; u < estimates.size(); ++u) {
    const auto& e = estimates[u];
    std::printf("%3zu %9.4f %9.4f (%9.4f,%9.4f) %9.4f %9.4f (%9.4f,%9.4f) %7.4f %7.4f\n", u + 1,
                e.lr_l, e.boot_l, e.ci_l_lo, e.ci_l_hi, e.lr_r, e.boot_r, e.ci_r_lo, e.ci_r_hi,
                e.r_l, e.r_r);
  }
  if (geometry) {
    std::printf("%3s %9s %9s %9s %9s\n", "#", "f_lat_lr", "f_lon_lr", "f_lat_bt", "f_lon_bt");
    for (std::size_t u = 0; u < estimates.size(); ++u) {
      const auto& f = out["unknowns"][u];
      std::printf("%3zu %9.4f %9.4f %9.4f %9.4f\n", u + 1, f["factors_lr"]["f_lat"].get<double>(),
                  f["factors_lr"]["f_lon"].get<double>(), f["factors_boot"]["f_lat"].get<double>(),
                  f["factors_boot"]["f_lon"].get<double>());
    }
  }
}

// ---------------------------------------------------------------- ros2
struct Ros2Options {
  std::string from_file, controller = "diff_drive_controller";
  std::optional<double> c_l, c_r, e_b;
};

double positive_key(const json& object, const std::string& file, const char* key) {
  if (!object.contains(key)) {
    throw InputError(file, 0, key, "missing key (expected the JSON of `odocal umbmark --json`)");
  }
  const json& value = object.at(key);
  if (!value.is_number() || !std::isfinite(value.get<double>()) || !(value.get<double>() > 0.0)) {
    throw InputError(file, 0, key, "must be a finite number > 0, got " + value.dump());
  }
  return value.get<double>();
}

void run_ros2(const Ros2Options& o) {
  double c_l = 0.0, c_r = 0.0, e_b = 0.0;
  std::string source;
  if (!o.from_file.empty()) {
    std::ifstream in(o.from_file);
    if (!in) {
      throw InputError(o.from_file, 0, "", "cannot open file");
    }
    json doc;
    try {
      doc = json::parse(in);
    } catch (const json::parse_error& e) {
      // nlohmann reports the byte offset; turn it into a line number.
      std::ifstream again(o.from_file);
      std::size_t line = 1, offset = 0;
      char c = 0;
      while (offset + 1 < e.byte && again.get(c)) {
        ++offset;
        line += c == '\n' ? 1 : 0;
      }
      throw InputError(o.from_file, line, "", std::string("not valid JSON: ") + e.what());
    }
    if (!doc.is_object()) {
      throw InputError(o.from_file, 1, "", "expected a JSON object");
    }
    c_l = positive_key(doc, o.from_file, "c_l");
    c_r = positive_key(doc, o.from_file, "c_r");
    e_b = positive_key(doc, o.from_file, "e_b");
    source = o.from_file;
    if (doc.contains("provenance") && doc["provenance"].is_object()) {
      const auto& p = doc["provenance"];
      source += " (" + p.value("method", std::string("?")) + ", " +
                std::to_string(p.value("runs", 0)) + " runs, " + p.value("date", std::string("?")) +
                ")";
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
  // E_b scales the wheelbase, c_L and c_R scale each wheel's distance per radian.
  std::printf("# ROS 2 diff_drive_controller parameters from odocal (%s)\n", source.c_str());
  std::printf("%s:\n  ros__parameters:\n", o.controller.c_str());
  std::printf("    wheel_separation_multiplier: %.9g\n", e_b);
  std::printf("    left_wheel_radius_multiplier: %.9g\n", c_l);
  std::printf("    right_wheel_radius_multiplier: %.9g\n", c_r);
}

}  // namespace

void register_calib_commands(CLI::App& app, int& exit_code) {
  {
    auto o = std::make_shared<UmbmarkOptions>();
    auto* cmd = app.add_subcommand("umbmark", "UMBmark: E_d, E_b, c_L, c_R from cw/ccw runs");
    cmd->add_option("--side-mm", o->side_mm, "side L of the square, mm")
        ->required()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--wheelbase-mm", o->wheelbase_mm, "wheelbase b used during the runs, mm")
        ->required()
        ->check(CLI::PositiveNumber);
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
        ->check(CLI::PositiveNumber);
    cmd->add_option("--wheelbase-mm", o->wheelbase_mm, "wheelbase l, mm")
        ->required()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--dl-mm", o->dl_mm, "left wheel diameter D_L, mm")
        ->required()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--dr-mm", o->dr_mm, "right wheel diameter D_R, mm")
        ->required()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--theta-l-rad", o->theta_l_rad,
                    "left wheel rotation per trial, rad (default 2L/D_L)")
        ->check(CLI::PositiveNumber);
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
        ->check(CLI::Range(calib::bootstrap_min_replicates, calib::bootstrap_max_replicates))
        ->capture_default_str();
    cmd->add_option("--seed", o->seed, "random seed")->capture_default_str();
    cmd->add_option("--level", o->level, "interval level")
        ->check(CLI::Range(0.5, 0.9999))
        ->capture_default_str();
    cmd->add_option("--interval", o->interval,
                    "percentile (the paper's) or calibrated (t-widened percentile)")
        ->check(CLI::IsMember({"percentile", "calibrated"}))
        ->capture_default_str();
    cmd->add_option("--wheelbase-mm", o->wheelbase_mm,
                    "with --dl-mm and --dr-mm: also F_lat, F_lon per unknown (eq. 7)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--dl-mm", o->dl_mm, "left wheel diameter, mm")->check(CLI::PositiveNumber);
    cmd->add_option("--dr-mm", o->dr_mm, "right wheel diameter, mm")->check(CLI::PositiveNumber);
    cmd->add_flag("--json", o->json, "print one JSON object");
    add_date_option(cmd, o->date);
    cmd->callback([o, &exit_code] { guarded("bootstrap", exit_code, [o] { run_bootstrap(*o); }); });
  }
  {
    auto o = std::make_shared<Ros2Options>();
    auto* cmd = app.add_subcommand("ros2", "ROS 2 diff_drive_controller parameter file");
    auto* from = cmd->add_option("--from", o->from_file, "JSON of `odocal umbmark --json`");
    auto* c_l =
        cmd->add_option("--c-l", o->c_l, "left wheel factor c_L")->check(CLI::PositiveNumber);
    auto* c_r =
        cmd->add_option("--c-r", o->c_r, "right wheel factor c_R")->check(CLI::PositiveNumber);
    auto* e_b =
        cmd->add_option("--e-b", o->e_b, "wheelbase factor E_b")->check(CLI::PositiveNumber);
    from->excludes(c_l)->excludes(c_r)->excludes(e_b);
    cmd->add_option("--controller", o->controller, "controller name")->capture_default_str();
    cmd->callback([o, &exit_code] { guarded("ros2", exit_code, [o] { run_ros2(*o); }); });
  }
}

}  // namespace odocal::host
