// `odocal session --procedure extended`: the extended UMBmark (DESIGN "Non-systematic errors";
// Borenstein & Feng's report, section 3.4): UMBmark squares on the bump-free floor, then the same
// over ten cables laid under one wheel along the first leg; the figure from the runs' heading
// errors (host::extended_figure, as `odocal sim extended`). A measurement, not a calibration:
// nothing is applied and nothing is saved.

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <numbers>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "odocal/host/calib_json.hpp"
#include "odocal/host/csv.hpp"
#include "odocal/host/extended_figure.hpp"
#include "odocal/host/path_geometry.hpp"
#include "odocal/host/robot_client.hpp"
#include "odocal/toolkit/numbers.hpp"
#include "session_internal.hpp"

namespace odocal::host::session {
namespace {

using std::numbers::pi;
/// The published test: ten cables of 10 mm on the first leg, under one wheel.
constexpr std::size_t cable_count = 10;
constexpr double cable_height_mm = 10.0;
constexpr bool cables_under_right_wheel = true;
/// A heading error beyond this is no square that closed near its start: a measurement typo, a
/// heading measured the wrong way round, or a robot that lost its way (docs/calibration.md).
constexpr double max_heading_error_deg = 90.0;

const char* const heading_howto =
    "How to measure the heading with a tape: put two marks on the robot on its centre line, as "
    "far apart as it allows (front F, back B, d mm apart), and chalk the start line on the floor "
    "(the first leg's direction, through the start mark). After the run measure how far each "
    "mark lies to the left of that line (y_F, y_B, mm; right of it negative): heading = "
    "asin((y_F - y_B) / d) in degrees, counter-clockwise (to the left) positive, e.g. marks 300 mm "
    "apart and y_F - y_B = 5 mm give 0.95 deg. Type it as the third number of the measurement "
    "(x_mm y_mm theta_deg), or give --measurements FILE with the header x_mm,y_mm,theta_deg.";

/// Measured minus odometry (as UMBmark), the heading wrapped to ±180°.
ExtendedRun error_of(const RunRecord& r, bool clockwise) {
  ExtendedRun e;
  e.clockwise = clockwise;
  e.theta_error_deg =
      std::remainder(r.measured.theta_deg.value_or(0.0) - r.odom.theta_deg.value_or(0.0), 360.0);
  e.x_mm = r.measured.x_mm - r.odom.x_mm;
  e.y_mm = r.measured.y_mm - r.odom.y_mm;
  return e;
}

nlohmann::json run_json(const ExtendedRun& r) {
  return {{"direction", r.clockwise ? "cw" : "ccw"},
          {"theta_error_deg", r.theta_error_deg},
          {"x_mm", r.x_mm},
          {"y_mm", r.y_mm}};
}

/// The robot is odocal-sim (--sim, whatever the measurements come from): it lays the cables.
bool on_simulator(const Context& c) {
  const auto sim = c.options.recorded.find("sim");
  const bool sim_option =
      sim != c.options.recorded.end() && sim->is_string() && !sim->get<std::string>().empty();
  return sim_option || c.source.describe().find("'measure'") != std::string::npos;
}

bool from_file(const Context& c) {
  return c.source.available(0) != std::numeric_limits<std::size_t>::max();
}

/// Refuses, before anything moves, a measurement file without the heading of every run.
void check_file_headings(const Context& c, std::size_t total) {
  const std::string path = c.source.describe();
  const std::unique_ptr<MeasurementSource> rows = file_measurements(path);
  std::size_t missing = 0;
  std::size_t first_missing = 0;
  const RunRecord none;
  for (std::size_t i = 0; i < total; ++i) {
    if (!rows->take(none, i, total).theta_deg) {
      first_missing = missing == 0 ? i + 1 : first_missing;
      ++missing;
    }
  }
  if (missing == 0) {
    return;
  }
  const std::string what =
      missing == total
          ? "has no theta_deg column (header x_mm,y_mm,theta_deg)"
          : fmt::format("has no theta_deg on {} of its {} rows (the first: measurement row {})",
                        missing, total, first_missing);
  throw InputError(path, 0, "theta_deg",
                   "the extended UMBmark needs each run's measured heading; the file " + what +
                       ". Nothing was run. " + heading_howto);
}

bool typed_at_terminal(const Context& c) {
  return !from_file(c) && c.source.describe().find("terminal") != std::string::npos;
}

/// A run typed at the terminal without its heading: asks for the heading alone (again until it is
/// a number), and keeps it with the run. Elsewhere (a file is checked before the start) a missing
/// heading is left to need_heading.
void complete_heading(Context& c, std::size_t number) {
  RunRecord& r = c.runs.back();
  if (r.measured.theta_deg || !typed_at_terminal(c) || c.options.start_in == nullptr) {
    return;
  }
  c.log << "The extended UMBmark needs each run's heading. " << heading_howto << "\n";
  for (;;) {
    c.log << fmt::format("Heading of run {} ({}), degrees, counter-clockwise positive: ", number,
                         r.label)
          << std::flush;
    std::string line;
    if (!read_typed_line(*c.options.start_in, line)) {
      throw InputError("standard input", 0, "",
                       fmt::format("end of input at the heading of run {}", number));
    }
    if (c.options.confirm_in == nullptr) {
      c.log << line << "\n";  // input from a file or pipe: show what was read
    }
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) {
      line.pop_back();
    }
    const std::optional<double> value = toolkit::parse_real(line);
    if (value && std::fabs(*value) <= 3600.0) {
      r.measured.theta_deg = *value;
      c.rewrite_journal();  // the heading on the disk before the next run
      c.write_session_json(false, c.partial, false, false);
      return;
    }
    c.log << "  Not taken: '" << line << "' is not a heading in degrees (e.g. -1.5)\n";
  }
}

/// Every run has its heading, and one a square can end with.
void need_heading(const RunRecord& r, std::size_t number) {
  if (!r.measured.theta_deg) {
    throw std::runtime_error(fmt::format(
        "run {} ({}) was measured without its heading (theta_deg, the third number): the "
        "extended UMBmark's figure is made of headings. {}",
        number, r.label, heading_howto));
  }
  const double error = std::remainder(*r.measured.theta_deg - r.odom.theta_deg.value_or(0.0), 360);
  if (std::fabs(error) > max_heading_error_deg) {
    throw std::runtime_error(fmt::format(
        "run {} ({}): measured heading {:.1f} deg against {:.1f} deg by odometry, {:.1f} deg "
        "apart (at most {:.0f}): no square ends that far off. Check the heading (counter-clockwise "
        "positive, from the start line), that the run started on the mark, and the wiring "
        "(docs/wiring.md).",
        number, r.label, *r.measured.theta_deg, r.odom.theta_deg.value_or(0.0), error,
        max_heading_error_deg));
  }
}

std::string describe(const ExtendedFigure& f, const std::vector<ExtendedRun>& reference,
                     const std::vector<ExtendedRun>& bumps, std::size_t n, double side_mm) {
  std::string text = fmt::format(
      "Extended UMBmark: {} cw + {} ccw runs on each floor, L = {:.0f} mm\n"
      "  heading errors (measured - odometry), deg\n",
      n, n, side_mm);
  const auto row = [&text](const char* title, const std::vector<ExtendedRun>& runs) {
    text += fmt::format("  {:<16}", title);
    for (const ExtendedRun& r : runs) {
      text += fmt::format(" {}{:+.2f}", r.clockwise ? "cw" : "ccw", plain(r.theta_error_deg, 2));
    }
    text += "\n";
  };
  row("bump-free", reference);
  row("over the cables", bumps);
  text += fmt::format(
      "  bump-free average  cw {:+.3f} deg, ccw {:+.3f} deg (the systematic part, left out)\n"
      "  mean |bump run - bump-free average|  cw {:.3f} deg, ccw {:.3f} deg\n"
      "  e_nonsys_deg       {:.3f} deg (95%: {:.3f} .. {:.3f} deg)\n"
      "  (a measurement, not a calibration: nothing applied, nothing saved)\n",
      plain(f.reference_cw_deg, 3), plain(f.reference_ccw_deg, 3), f.e_cw_deg, f.e_ccw_deg,
      f.e_nonsys_deg, f.ci_lo_deg, f.ci_hi_deg);
  return text;
}

/// Where to lay the cables, for the person who lays them.
std::string cables_text(std::size_t n, double first_m, double spacing_m, const char* wheel) {
  const std::size_t total = 4 * n;
  const char* const clear_wheel = cables_under_right_wheel ? "left" : "right";
  std::string lay = fmt::format(
      "\n=== Now lay the cables (before run {} of {}) ===\n"
      "  {} cables about {:.0f} mm thick (round cable or dowel), taped down across the first leg,\n"
      "  under the {} wheel only (the {} wheel rolls on clear floor), where the {} wheel rolls,\n"
      "  at these distances from the start mark along the first leg, mm:\n    ",
      2 * n + 1, total, cable_count, cable_height_mm, wheel, clear_wheel, wheel);
  for (std::size_t i = 0; i < cable_count; ++i) {
    lay += fmt::format("{}{:.0f}", i == 0 ? "" : ", ",
                       (first_m + static_cast<double>(i) * spacing_m) * 1000.0);
  }
  lay += fmt::format(
      "\n  (half a spacing from the start, then every {:.0f} mm). They stay down for all {} runs\n"
      "  over the cables; same start mark as before.\n",
      spacing_m * 1000.0, 2 * n);
  return lay;
}

/// The figure with its runs, intervals and provenance (every run of both floors).
Outcome outcome_of(const Context& c, const ExtendedFigure& figure,
                   const std::vector<ExtendedRun> (&runs)[2][2],
                   const nlohmann::json& reference_runs, const nlohmann::json& bumps, std::size_t n,
                   double side_mm) {
  const std::size_t total = 4 * n;
  nlohmann::json bump_runs = nlohmann::json::array();
  for (const auto& side : runs[1]) {
    for (const ExtendedRun& r : side) {
      bump_runs.push_back(run_json(r));
    }
  }
  Outcome outcome;
  outcome.result = {
      {"e_nonsys_deg", figure.e_nonsys_deg},
      {"e_nonsys_cw_deg", figure.e_cw_deg},
      {"e_nonsys_ccw_deg", figure.e_ccw_deg},
      {"ci", {figure.ci_lo_deg, figure.ci_hi_deg}},
      {"sd_deg", figure.sd_deg},
      {"intervals",
       {{"level", 0.95},
        {"method", "Student t, Welch-Satterthwaite, from the run-to-run scatter"},
        {"e_nonsys_deg", {figure.ci_lo_deg, figure.ci_hi_deg}}}},
      {"runs", bump_runs},
      {"reference", {{"cw", figure.reference_cw_deg}, {"ccw", figure.reference_ccw_deg}}},
      {"reference_runs", reference_runs},
      {"bumps", bumps},
      {"side_mm", side_mm}};
  // Provenance: every run the figure came from (both floors), the session's date.
  Provenance p;
  p.method = "extended-umbmark";
  p.runs = total;
  p.interval = "student-t";
  p.level = 0.95;
  p.date = today_utc();
  p.extra = {{"side_mm", side_mm}, {"date_unix_s", c.date()}};
  outcome.result = with_provenance(outcome.result, p);
  std::vector<ExtendedRun> reference = runs[0][0];
  reference.insert(reference.end(), runs[0][1].begin(), runs[0][1].end());
  std::vector<ExtendedRun> over = runs[1][0];
  over.insert(over.end(), runs[1][1].begin(), runs[1][1].end());
  outcome.text = describe(figure, reference, over, n, side_mm);
  outcome.applied = false;
  return outcome;
}

}  // namespace

Outcome run_extended(Context& c) {
  const std::size_t n = c.options.runs.value_or(5);
  const double side_m = c.options.side_m.value_or(4.0);
  const double side_mm = side_m * 1000.0;
  const std::size_t total = 4 * n;
  c.need_measurements(total, "the extended UMBmark (" + std::to_string(n) + " cw + " +
                                 std::to_string(n) + " ccw runs, bump-free and over the cables)");
  const bool simulated = on_simulator(c);
  if (from_file(c)) {
    check_file_headings(c, total);
  }
  c.planned = total;
  double first_m = 0.0;
  double spacing_m = 0.0;
  extended_bump_layout(side_m, cable_count, first_m, spacing_m);
  const char* const wheel = cables_under_right_wheel ? "right" : "left";
  nlohmann::json bumps = {{"count", cable_count},
                          {"height_mm", cable_height_mm},
                          {"first_mm", first_m * 1000.0},
                          {"spacing_mm", spacing_m * 1000.0},
                          {"wheel", wheel},
                          {"laid_by", simulated ? "odocal-sim" : "you"}};
  char side_text[32];
  std::snprintf(side_text, sizeof side_text, "%.3f", side_m);
  const double expected_s = c.path_seconds(4.0 * side_m, 2.0 * pi, 8);
  c.log << "Extended UMBmark: " << count_of(n, "run", "runs") << " clockwise, then " << n
        << " counter-clockwise, around a " << side_text
        << " m square on your bump-free floor; then the same " << 2 * n
        << " runs with ten cables under the " << wheel
        << " wheel on the first leg (you will be told when and where).\n"
        << "Each run is measured with its heading: x_mm y_mm theta_deg.\n";
  if (!simulated && !from_file(c)) {
    c.log << heading_howto << "\n";
  }
  if (simulated) {
    // The rehearsal's floor: smooth for the bump-free runs, as `odocal sim extended`.
    c.robot.expect_ok("measure cables off");
  }

  std::vector<ExtendedRun> runs[2][2];  // [bumps][direction]
  const auto drive = [&](int floor) {
    for (int direction = 0; direction < 2; ++direction) {
      const std::string name = direction == 0 ? "cw" : "ccw";
      for (std::size_t i = 0; i < n; ++i) {
        static_cast<void>(c.run(floor == 0 ? name : "bumps-" + name,
                                Motion::square(direction == 0, side_m), expected_s));
        complete_heading(c, c.runs.size());
        need_heading(c.runs.back(), c.runs.size());
        runs[floor][direction].push_back(error_of(c.runs.back(), direction == 0));
      }
    }
  };
  drive(0);
  nlohmann::json reference_runs = nlohmann::json::array();
  for (const auto& side : runs[0]) {
    for (const ExtendedRun& r : side) {
      reference_runs.push_back(run_json(r));
    }
  }
  c.partial = {{"side_mm", side_mm}, {"bumps", bumps}, {"reference_runs", reference_runs}};

  // The user's moment to lay the cables (on --port, the Enter before the next run).
  c.log << cables_text(n, first_m, spacing_m, wheel);
  if (simulated) {
    const Reply laid =
        c.robot.expect_ok(fmt::format("measure cables {:.3f} {:.3f} {} {}", first_m * 1000.0,
                                      spacing_m * 1000.0, cable_count, wheel));
    bumps["height_mm"] = laid.number("height_mm");
    c.log << "  (odocal-sim laid them: " << laid.line << ")\n";
  }
  c.partial["bumps"] = bumps;
  drive(1);
  if (!simulated) {
    c.log << "All runs done: the cables can go.\n";
  }

  ExtendedFigure figure;
  if (!extended_figure(runs[0][0], runs[0][1], runs[1][0], runs[1][1], figure)) {
    throw std::runtime_error("the extended UMBmark needs at least 2 runs per direction (--runs)");
  }
  Outcome outcome = outcome_of(c, figure, runs, reference_runs, bumps, n, side_mm);
  c.log << outcome.text;
  return outcome;
}

}  // namespace odocal::host::session
