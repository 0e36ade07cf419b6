// `odocal session --procedure verify`: Maddahi's unseen path driven --runs times with the
// nominal factors ("before": c_l = c_r = f_lat = f_lon = 1, the default wheelbase) and --runs
// times with the factors in force ("after"); the end errors in the `odocal accuracy` format.

#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>

#include <fmt/format.h>

#include "odocal/drive/motion_executor.hpp"
#include "odocal/host/calib_json.hpp"
#include "odocal/host/path_geometry.hpp"
#include "odocal/toolkit/numbers.hpp"
#include "session_internal.hpp"
#include "unseen_path.hpp"

namespace odocal::host::session {
namespace {

/// The `default=` of `name` in the `params` listing (the target's own default).
double parameter_default(Context& c, ParamId id) {
  const std::string name = params::param_info(id).name;
  std::vector<std::string> lines;
  const Reply reply = c.robot.command("params", 10000, &lines);
  if (!reply.ok) {
    throw LinkError("robot refused 'params': err " + reply.code);
  }
  for (const std::string& line : lines) {
    const auto pairs = hash_line_pairs(line);
    if (pairs.count(name) != 0u && pairs.count("default") != 0u) {
      const auto value = toolkit::parse_real(pairs.at("default"));
      if (value) {
        return *value;
      }
    }
  }
  throw LinkError("'params' lists no default for " + name);
}

}  // namespace

UnseenPath unseen_path(Context& c) {
  UnseenPath u;
  u.path = drive::make_unseen_path();
  u.goal = path_end(u.path);
  double length_m = 0.0;
  double turn_rad = 0.0;
  for (std::uint8_t i = 0; i < u.path.count; ++i) {
    length_m += std::fabs(static_cast<double>(u.path.segments[i].distance_m));
    if (u.path.segments[i].distance_m == 0.0f) {
      turn_rad += std::fabs(static_cast<double>(u.path.segments[i].angle_rad));
    }
  }
  u.expected_s = c.path_seconds(length_m, turn_rad, u.path.count);
  return u;
}

std::vector<UnseenStop> drive_unseen(Context& c, const UnseenPath& unseen, const std::string& label,
                                     std::size_t n, bool log_ticks) {
  std::vector<UnseenStop> stops;
  for (std::size_t i = 0; i < n; ++i) {
    const RunRecord r = c.run(label, Motion::unseen(), unseen.expected_s, log_ticks);
    stops.push_back(UnseenStop{r.measured.x_mm, r.measured.y_mm,
                               calib::EndError{r.measured.x_mm - unseen.goal.x_m * 1e3,
                                               r.measured.y_mm - unseen.goal.y_m * 1e3}});
  }
  return stops;
}

Outcome run_verify(Context& c) {
  const std::size_t n = c.options.runs.value_or(5);
  c.need_measurements(
      2 * n, "verify (" + std::to_string(n) + " runs before and " + std::to_string(n) + " after)");
  c.planned = 2 * n;
  const UnseenPath unseen = unseen_path(c);
  const PathEnd& goal = unseen.goal;

  const Factors in_force = c.factors();
  Factors nominal;
  nominal.wheelbase_mm = parameter_default(c, ParamId::wheelbase_mm);
  const bool saved_state = c.robot.status().text("unsaved") == "0";

  c.log << "Verify: the unseen path (100 cm square, 100 cm triangle, 80 cm semicircle; it should "
           "end "
        << fmt::format("{:.0f}", goal.x_m * 1e3) << " mm ahead and "
        << fmt::format("{:.0f}", goal.y_m * 1e3) << " mm to the left of the start), " << n
        << " runs with the nominal factors, then " << n << " with the factors in force.\n";
  std::vector<AccuracyTrial> trials;
  std::ostringstream csv;
  csv << "scenario,trial,x_mm,y_mm\n";
  const auto drive_scenario = [&](const std::string& name) {
    const std::vector<UnseenStop> stops = drive_unseen(c, unseen, name, n);
    for (std::size_t i = 0; i < stops.size(); ++i) {
      trials.push_back(AccuracyTrial{name, stops[i].error});
      char line[128];
      std::snprintf(line, sizeof line, "%s,%zu,%.3f,%.3f\n", name.c_str(), i + 1,
                    stops[i].error.x_mm, stops[i].error.y_mm);
      csv << line;
    }
  };
  // An interruption in the runs before is the engine's way out: it puts back what was in force.
  c.set_factors(nominal);
  drive_scenario("before");
  // Put the factors back exactly: `load` restores the saved set and its provenance when nothing
  // was unsaved; otherwise `set` them (their provenance then reads manual).
  bool restored = false;
  if (saved_state) {
    const Reply load = c.robot.command("load");
    restored = load.ok;
  }
  if (!restored) {
    c.set_factors(in_force);
    if (saved_state) {
      c.log << "(no saved set to reload: the factors were set back by hand)\n";
    } else {
      c.log << "Note: the factors in force were unsaved; they were set back with 'set', so "
               "'provenance' now reads manual for them.\n";
    }
  }
  drive_scenario("after");
  c.write_file("accuracy.csv", csv.str());

  const std::vector<ScenarioAccuracy> scenarios = compute_accuracy(trials, "before");
  Outcome outcome;
  outcome.result = accuracy_to_json(scenarios, "before");
  outcome.result["goal"] = {{"x_mm", goal.x_m * 1e3},
                            {"y_mm", goal.y_m * 1e3},
                            {"theta_deg", goal.theta_rad * 180.0 / std::numbers::pi}};
  std::ostringstream text;
  text << "Verify: end error on the unseen path (measured minus where it should end)\n"
       << "scenario     trials       rms_mm  improvement_pct\n";
  for (const ScenarioAccuracy& s : scenarios) {
    char line[160];
    if (s.improvement_pct) {
      std::snprintf(line, sizeof line, "%-10s %8zu %12.1f %16.1f\n", s.name.c_str(), s.trials,
                    s.rms_mm, *s.improvement_pct);
    } else {
      std::snprintf(line, sizeof line, "%-10s %8zu %12.1f %16s\n", s.name.c_str(), s.trials,
                    s.rms_mm, "n/a");
    }
    text << line;
  }
  text << "(improvement = 100 (1 - rms / rms before); files: accuracy.csv for odocal accuracy)\n";
  c.log << text.str();
  outcome.text = text.str();
  return outcome;
}

}  // namespace odocal::host::session
