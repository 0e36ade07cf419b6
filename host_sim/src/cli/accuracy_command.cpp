// `odocal accuracy`: see docs/calibration.md.

#include "calib_cli.hpp"

namespace odocal::host::calib_cli {
namespace {

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

}  // namespace

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

}  // namespace odocal::host::calib_cli
