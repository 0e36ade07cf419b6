// `odocal session --procedure auto --truth walls` (DESIGN "No tape measure"): the steps auto takes
// with the walls as the measurements: the sensors learnt before the first run, and the
// verification along a corridor no calibration run drove, judged by the walls.

#include <cmath>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "auto_session.hpp"
#include "model_in_force.hpp"
#include "odocal/host/fit_noise.hpp"
#include "odocal/host/path_geometry.hpp"

namespace odocal::host::session {

using namespace auto_plan;

namespace {

/// The unseen corridor: from the far end of the calibration's corridor, the longest corridor to
/// a side (no calibration run drove it), two cells or more, ending in a corner the walls can
/// place the robot in; `turn_rad` the turn into it. nullopt: the maze has none.
std::optional<Corridor> unseen_corridor(const MazeKnowledge& maze, const Corridor& first,
                                        double& turn_rad) {
  std::optional<Corridor> best;
  for (const double side : {-0.5 * kPi, 0.5 * kPi}) {
    const Corridor k =
        corridor_from(maze.maze, first.end_column, first.end_row, maze.start_heading_rad + side);
    if (k.cells >= 2u && k.end_has_side_wall && (!best || k.cells > best->cells)) {
      best = k;
      turn_rad = side;
    }
  }
  return best;
}

}  // namespace

void AutoSession::learn_the_walls(Outcome& out) {
  out.result["truth"] = "walls";
  c_.wait_for_enter("The walls: put the robot down in the start cell of " + walls_->maze().name +
                        ", facing out of it (no mark, nothing to measure), hands off;",
                    "the calibration turn");
  walls_->calibrate();
  c_.partial["walls"] = walls_->json();
}

void AutoSession::verify_by_walls(Outcome& out) {
  const MazeKnowledge& maze = walls_->maze();
  const Corridor out_corridor = walls_->calibration_corridor();
  double turn_rad = 0.0;
  const std::optional<Corridor> best = unseen_corridor(maze, out_corridor, turn_rad);
  if (!best) {
    c_.log << "Verify: the maze has no second corridor from the far end of the first (two cells "
              "or more, ending in a corner): the verification is left out; the unseen path "
              "(odocal session --procedure verify) checks the factors with a tape.\n";
    out.result["verify"] = nullptr;
    return;
  }
  const double length_m = best->length_mm() * 1e-3;
  c_.log << fmt::format(
      "Verify: {} runs with the new factors along a corridor no calibration run drove ({:.2f} m "
      "from cell ({}, {}) to cell ({}, {})), judged by the walls: each should stop {:.0f} mm "
      "ahead of where it starts, on the same line.\n",
      auto_verify_runs, length_m, out_corridor.end_column, out_corridor.end_row, best->end_column,
      best->end_row, length_m * 1e3);
  const double along = maze.start_heading_rad + turn_rad;
  if (walls_->in_start_cell()) {
    walls_->face(maze.start_heading_rad);
    walls_->move_and_look(Motion::line(plan_.line_m).command(),
                          c_.path_seconds(plan_.line_m, 0.0, 1) + 2.0);
  }
  walls_->face(along);
  c_.planned = c_.runs.size() + auto_verify_runs;
  const FitGeometry before_g =
      fit_geometry_of(geometry_in_force(c_.initial, nominal_.wheel_diameter_mm));
  const FitGeometry after_g =
      fit_geometry_of(geometry_in_force(applied_, nominal_.wheel_diameter_mm));
  nlohmann::json stops = nlohmann::json::array();
  double sum2 = 0.0;
  double before2 = 0.0;
  double odometry2 = 0.0;
  for (std::size_t i = 0; i < auto_verify_runs; ++i) {
    if (i > 0) {
      // Back to the corridor's start (no run), to drive it again.
      walls_->face(along + kPi);
      walls_->move_and_look(Motion::line(length_m).command(),
                            c_.path_seconds(length_m, 0.0, 1) + 2.0);
    }
    // Aimed at the far cell's centre: the goal is that far straight ahead.
    const Motion aimed = Motion::line(walls_->aim_at(best->end_column, best->end_row));
    const double goal_mm = aimed.length_m * 1e3;
    const RunRecord r = c_.run("verify", aimed, c_.path_seconds(aimed.length_m, 0.0, 1), true);
    const double ex = r.measured.x_mm - goal_mm;
    const double ey = r.measured.y_mm;
    sum2 += ex * ex + ey * ey;
    odometry2 +=
        std::pow(r.measured.x_mm - r.odom.x_mm, 2) + std::pow(r.measured.y_mm - r.odom.y_mm, 2);
    const TickLog log = tick_log_of(r, false);
    const std::size_t last = log.rows.size() - 1;
    const EndSensitivity old_end = end_sensitivity(log, 0, last, nominal_, before_g);
    const EndSensitivity new_end = end_sensitivity(log, 0, last, nominal_, after_g);
    before2 += std::pow(ex - (old_end.end[0] - new_end.end[0]), 2) +
               std::pow(ey - (old_end.end[1] - new_end.end[1]), 2);
    stops.push_back({{"goal_x_mm", goal_mm},
                     {"x_mm", r.measured.x_mm},
                     {"y_mm", r.measured.y_mm},
                     {"theta_deg", r.measured.theta_deg.value_or(0.0)},
                     {"error_x_mm", ex},
                     {"error_y_mm", ey},
                     {"error_mm", std::hypot(ex, ey)}});
  }
  const double n = static_cast<double>(auto_verify_runs);
  const double rms = std::sqrt(sum2 / n);
  out.result["verify"] = {{"judged_by", "walls"},
                          {"path", fmt::format("line {:.3f} m", length_m)},
                          {"from_cell", {out_corridor.end_column, out_corridor.end_row}},
                          {"to_cell", {best->end_column, best->end_row}},
                          {"goal", {{"x_mm", length_m * 1e3}, {"y_mm", 0.0}}},
                          {"stops", stops},
                          {"rms_mm", rms},
                          {"before_rms_mm", std::sqrt(before2 / n)},
                          {"odometry_rms_mm", std::sqrt(odometry2 / n)},
                          {"flagged", !suspects_.empty()}};
  out.result["walls"] = walls_->json();
  std::ostringstream text;
  text << fmt::format(
      "Auto (the walls): {} calibration runs, {} to verify, no tape reading. Model {}. The "
      "unseen corridor's stops, judged by the walls, end {:.1f} mm RMS from the goal ({:.1f} mm "
      "from where the calibrated odometry says they stopped); with the factors it had before the "
      "session, about {:.1f} mm (their counts replayed).\n",
      driven(), auto_verify_runs, model_name(fitted_.geometry.model), rms, std::sqrt(odometry2 / n),
      std::sqrt(before2 / n));
  if (!suspects_.empty()) {
    text << fmt::format(
        "WARNING: {} run(s) disagree with the others (result.suspect_runs): a look the walls "
        "misread, or a run that went wrong.\n",
        suspects_.size());
  }
  c_.log << text.str();
  out.text += fit_text_for_auto(fitted_) + text.str();
}

}  // namespace odocal::host::session
