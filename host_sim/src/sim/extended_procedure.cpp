// `odocal sim extended`: the extended UMBmark (non-systematic errors; Borenstein & Feng's report,
// section 3.4, and their 1996 paper, section V; our reading in docs/architecture.md).

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "odocal/host/sim_procedures.hpp"
#include "odocal/host/svg_plot.hpp"

namespace odocal::host {
namespace {

using std::numbers::pi;
constexpr double deg_per_rad = 180.0 / pi;

/// Drives `runs` cw then `runs` ccw squares and records their return errors.
bool drive_squares(SimulatedRobot& robot, const ExtendedOptions& o, const char* floor,
                   std::vector<ExtendedRun>& out, std::vector<std::vector<PathPoint>>& paths,
                   std::string& error, const ProgressFn& progress) {
  const std::size_t total = 2 * o.runs;
  for (std::size_t i = 0; i < total; ++i) {
    const bool clockwise = i < o.runs;
    if (progress) {
      progress(std::string("extended: ") + floor + ", run " + std::to_string(i + 1) + "/" +
               std::to_string(total) + (clockwise ? " (cw)" : " (ccw)"));
    }
    std::vector<PathPoint> trace;
    TraceFn tracer;
    if (o.record_paths) {
      tracer = [&trace](const sim::WorldPose& p) { trace.push_back(PathPoint{p.x_m, p.y_m}); };
    }
    const std::uint32_t bumps_before = robot.plant().bumps_crossed();
    const RunOutcome outcome = robot.run_path(
        drive::make_umbmark_square(clockwise, static_cast<float>(o.side_m)), 3600.0, tracer, 200u);
    if (!outcome.completed) {
      error = std::string(floor) + ", " + (clockwise ? "cw" : "ccw") + " run " +
              std::to_string(i % o.runs + 1) + ": the square did not complete";
      return false;
    }
    ExtendedRun run;
    run.clockwise = clockwise;
    // Errors are measured (absolute) minus perceived (odometry), as UMBmark's return errors.
    run.theta_error_deg =
        std::remainder(outcome.measured.theta_rad - static_cast<double>(outcome.odometry.theta_rad),
                       2.0 * pi) *
        deg_per_rad;
    run.x_mm = (outcome.measured.x_m - static_cast<double>(outcome.odometry.x_m)) * 1e3;
    run.y_mm = (outcome.measured.y_m - static_cast<double>(outcome.odometry.y_m)) * 1e3;
    run.bumps_crossed = robot.plant().bumps_crossed() - bumps_before;
    out.push_back(run);
    if (o.record_paths) {
      paths.push_back(std::move(trace));
    }
  }
  return true;
}

std::vector<ExtendedRun> direction(const std::vector<ExtendedRun>& runs, bool clockwise) {
  std::vector<ExtendedRun> out;
  std::copy_if(runs.begin(), runs.end(), std::back_inserter(out),
               [clockwise](const ExtendedRun& r) { return r.clockwise == clockwise; });
  return out;
}

nlohmann::json run_json(const ExtendedRun& r) {
  return {{"direction", r.clockwise ? "cw" : "ccw"},
          {"theta_error_deg", r.theta_error_deg},
          {"x_mm", r.x_mm},
          {"y_mm", r.y_mm},
          {"bumps_crossed", r.bumps_crossed}};
}

}  // namespace

ExtendedReport run_extended(const RobotSpec& robot_spec, std::uint64_t seed,
                            const ExtendedOptions& options, const ProgressFn& progress) {
  ExtendedReport report;
  report.seed = seed;
  report.options = options;
  RobotSpec spec = robot_spec;
  spec.nominal.v_max_mps = static_cast<float>(options.v_max_mps);
  // The published test lays 10 mm cables; a robot file's bump_height_mm replaces that height (its
  // bump_spacing_mm does not apply: the cables lie as published, evenly along the first leg).
  report.bump_height_m = options.bump_height_m > 0.0      ? options.bump_height_m
                         : spec.truth.bump_height_m > 0.0 ? spec.truth.bump_height_m
                                                          : 0.010;
  extended_bump_layout(options.side_m, options.bumps, report.bump_first_m, report.bump_spacing_m);
  const double wheel_radius_m =
      0.5 * (options.right_wheel ? spec.truth.right_diameter_m : spec.truth.left_diameter_m);
  if (!(report.bump_height_m < wheel_radius_m)) {
    report.error = fmt::format(FMT_STRING("bump height {:.1f} mm: must be below the wheel's radius "
                                          "({:.1f} mm)"),
                               report.bump_height_m * 1e3, wheel_radius_m * 1e3);
    return report;
  }
  SimulatedRobot robot(spec, seed);
  if (!robot.configure(spec.nominal)) {
    report.error = "the robot's nominal geometry is outside the firmware's parameter ranges";
    return report;
  }
  // 1. The bump-free runs: the robot's systematic orientation error in each direction.
  robot.plant().set_bumps(0.0, 0.0);
  if (!drive_squares(robot, options, "bump-free floor", report.reference, report.reference_paths,
                     report.error, progress)) {
    report.simulated_s = robot.simulated_s();
    return report;
  }
  // 2. The same squares with the cables under one wheel along the first leg.
  robot.plant().lay_cables(options.right_wheel, report.bump_height_m, report.bump_first_m,
                           report.bump_spacing_m, static_cast<std::uint32_t>(options.bumps));
  if (!drive_squares(robot, options, "bumps", report.bump_runs, report.bump_paths, report.error,
                     progress)) {
    report.simulated_s = robot.simulated_s();
    return report;
  }
  report.simulated_s = robot.simulated_s();
  if (!extended_figure(direction(report.reference, true), direction(report.reference, false),
                       direction(report.bump_runs, true), direction(report.bump_runs, false),
                       report.figure)) {
    report.error = "at least 2 runs per direction are needed";
    return report;
  }
  report.ok = true;
  return report;
}

nlohmann::json extended_report_json(const ExtendedReport& r) {
  nlohmann::json j;
  j["simulated_s"] = r.simulated_s;
  j["seed"] = r.seed;
  if (!r.ok) {
    j["error"] = r.error;
    return j;
  }
  const ExtendedFigure& f = r.figure;
  j["e_nonsys_deg"] = f.e_nonsys_deg;
  j["e_nonsys_cw_deg"] = f.e_cw_deg;
  j["e_nonsys_ccw_deg"] = f.e_ccw_deg;
  j["ci"] = {f.ci_lo_deg, f.ci_hi_deg};
  j["sd_deg"] = f.sd_deg;
  j["reference"] = {{"cw", f.reference_cw_deg}, {"ccw", f.reference_ccw_deg}};
  nlohmann::json runs = nlohmann::json::array();
  for (const ExtendedRun& run : r.bump_runs) {
    runs.push_back(run_json(run));
  }
  j["runs"] = runs;
  nlohmann::json reference_runs = nlohmann::json::array();
  for (const ExtendedRun& run : r.reference) {
    reference_runs.push_back(run_json(run));
  }
  j["reference_runs"] = reference_runs;
  j["bumps"] = {{"count", r.options.bumps},
                {"height_mm", r.bump_height_m * 1e3},
                {"first_mm", r.bump_first_m * 1e3},
                {"spacing_mm", r.bump_spacing_m * 1e3},
                {"wheel", r.options.right_wheel ? "right" : "left"}};
  j["side_mm"] = r.options.side_m * 1e3;
  return j;
}

std::string extended_report_text(const ExtendedReport& r) {
  std::ostringstream out;
  out << "Extended UMBmark on the simulated robot ("
      << fmt::format(FMT_STRING("{:.0f}"), r.options.side_m * 1e3) << " mm square, "
      << r.options.runs << " cw + " << r.options.runs << " ccw runs on each floor, seed " << r.seed
      << ")\n";
  if (!r.ok) {
    out << "failed: " << r.error << "\n";
    return out.str();
  }
  out << fmt::format(FMT_STRING("{} cables of {:.1f} mm under the {} wheel on the first leg, the "
                                "first {:.0f} mm from the start, then every {:.0f} mm\n"),
                     r.options.bumps, r.bump_height_m * 1e3,
                     r.options.right_wheel ? "right" : "left", r.bump_first_m * 1e3,
                     r.bump_spacing_m * 1e3);
  out << "return errors (measured minus odometry): heading deg, x mm, y mm\n";
  const auto table = [&out](const char* title, const std::vector<ExtendedRun>& runs) {
    out << "  " << title << "\n";
    for (const ExtendedRun& run : runs) {
      out << fmt::format(FMT_STRING("    {:<3} {:9.3f} {:9.1f} {:9.1f}   ({} cables crossed)\n"),
                         run.clockwise ? "cw" : "ccw", run.theta_error_deg, run.x_mm, run.y_mm,
                         run.bumps_crossed);
    }
  };
  table("bump-free runs", r.reference);
  table("runs over the cables", r.bump_runs);
  const ExtendedFigure& f = r.figure;
  out << fmt::format(FMT_STRING("bump-free average heading error: cw {:.3f} deg, ccw {:.3f} deg\n"),
                     f.reference_cw_deg, f.reference_ccw_deg);
  out << fmt::format(FMT_STRING("average |bump run - bump-free average|: cw {:.3f} deg, ccw {:.3f} "
                                "deg\n"),
                     f.e_cw_deg, f.e_ccw_deg);
  out << fmt::format(FMT_STRING("e_nonsys = {:.3f} deg (95 % interval {:.3f} to {:.3f} deg)\n"),
                     f.e_nonsys_deg, f.ci_lo_deg, f.ci_hi_deg);
  out << fmt::format(FMT_STRING("simulated {:.0f} s of robot time\n"), r.simulated_s);
  return out.str();
}

std::string extended_report_svg(const ExtendedReport& r) {
  SvgFigure fig;
  if (!r.ok) {
    return fig.finish();
  }
  SvgPanel& scatter = fig.panel(0, "Return errors: heading (deg) against run", "run",
                                "heading "
                                "error, deg");
  for (std::size_t i = 0; i < r.reference.size(); ++i) {
    scatter.add_marker(static_cast<double>(i + 1), r.reference[i].theta_error_deg, "#2471a3",
                       r.reference[i].clockwise ? 'o' : 's');
  }
  for (std::size_t i = 0; i < r.bump_runs.size(); ++i) {
    scatter.add_marker(static_cast<double>(i + 1), r.bump_runs[i].theta_error_deg, "#c0392b",
                       r.bump_runs[i].clockwise ? 'o' : 's');
  }
  scatter.legend({{"#2471a3", "bump-free (o cw, square ccw)"}, {"#c0392b", "over the cables"}});
  SvgPanel& paths =
      fig.panel(1, "True paths: bump-free (blue), over the cables (red)", "x, m", "y, m");
  for (const auto& path : r.reference_paths) {
    paths.add_line(path, "#2471a3");
  }
  for (const auto& path : r.bump_paths) {
    paths.add_line(path, "#c0392b");
  }
  return fig.finish();
}

}  // namespace odocal::host
