// `odocal session --procedure auto --truth walls` (DESIGN "No tape measure"): the steps auto takes
// with the walls as the measurements: the sensors learnt before the first run, and the
// verification along a corridor no calibration run drove, judged by the walls.

#include <cmath>
#include <optional>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "auto_session.hpp"
#include "model_in_force.hpp"
#include "odocal/host/fit_noise.hpp"
#include "odocal/host/path_geometry.hpp"

namespace odocal::host::session {

using namespace auto_plan;

namespace {

/// The unseen corridor: from the cell (column, row) where the calibration's route ends, the
/// route arriving along `along_rad`, the longest corridor to a side (no calibration run drove
/// it), two cells or more, ending in a corner the walls can place the robot in; `turn_rad` its
/// heading. nullopt: the maze has none.
std::optional<Corridor> unseen_corridor(const MazeKnowledge& maze, std::uint32_t column,
                                        std::uint32_t row, double along_rad, double& turn_rad) {
  std::optional<Corridor> best;
  for (const double side : {-0.5 * kPi, 0.5 * kPi}) {
    const Corridor k = corridor_from(maze.maze, column, row, along_rad + side);
    if (k.cells >= 2u && k.end_has_side_wall && (!best || k.cells > best->cells)) {
      best = k;
      turn_rad = along_rad + side;
    }
  }
  return best;
}

}  // namespace

void AutoSession::learn_the_walls(Outcome& out) {
  out.result["truth"] = "walls";
  c_.partial["truth"] = "walls";
  c_.wait_for_enter("The walls: put the robot down in the start cell of " + walls_->maze().name +
                        ", facing out of it (no mark, nothing to measure), hands off;",
                    "the calibration turn");
  walls_->calibrate();
  c_.partial["walls"] = walls_->json();
}

void AutoSession::scale_by_tape(const Corridor& corridor) {
  tape_why_ = fmt::format(
      "the start cell's corridor in {} runs {} cell(s) and {} at its end: the walls cannot give "
      "the wheels' scale without a straight corridor of two cells or more that ends in a corner "
      "(a turn in place has no distance in it)",
      walls_->maze().name, corridor.cells,
      corridor.end_has_side_wall ? "has a side wall" : "has no side wall");
  if (!walls_->has_tape()) {
    throw std::runtime_error("--truth walls: " + tape_why_ +
                             " (calibrate with a tape: leave --truth out)");
  }
  plan_.floor_lines = true;
  c_.partial["tape"] = {{"why", tape_why_}};  // an interrupted session's report says it too
  c_.log << fmt::format(
      "The walls cannot tell everything here: {}. They still measure the turns in place, in the "
      "start cell. The scale takes a tape: {:.2f} m lines on an open floor, two at least (the "
      "scale and the wheels' ratio), more only while they buy the most precision, then the "
      "verification there ({} readings); --side-m sets the lines' length to the floor there "
      "is.\n",
      tape_why_, plan_.line_m, auto_verify_runs);
}

void AutoSession::to_the_floor() {
  static_cast<void>(walls_->to_the_floor());
  // The unseen path (verification) turns left: a 1 m square and triangle ahead, a 0.8 m
  // semicircle behind the start to 1.6 m on its left (unseen_path.hpp).
  c_.log << fmt::format(
      "The tape: the turns in the maze are done. Take the robot out of the maze to an open "
      "floor: {:.1f} m clear ahead of a start mark and half a metre to its right for the lines, "
      "1.8 m to its left and 1 m behind it for the verification's path. A tape measures every "
      "run from here on.\n",
      plan_.line_m + 0.3);
  c_.log << tape_how_to();
  if (c_.options.start_in == nullptr && walls_->by_hand()) {
    // --no-wait starts each run without an Enter, but the robot has to leave the maze first:
    // the person who types the readings says when.
    static_cast<void>(walls_->ask(
        "The tape: press Enter when the robot stands on the open floor (Ctrl-C ends the "
        "session): "));
  }
}

void AutoSession::drive_straighter() {
  const FitGeometry& g = fitted_.geometry;
  const Factors next = factors_for_fit(
      drive::model::Geometry<double>{g.wheel_diameter_left_mm, g.wheel_diameter_right_mm,
                                     g.wheelbase_mm, 0.0},
      nominal_.wheel_diameter_mm);
  if (!implausible_factors(next, c_.initial.wheelbase_mm).empty()) {
    return;  // the final fit says what is wrong; the runs stay in the start cell's corridor
  }
  c_.log << "The walls: the first round's factors put in force (not saved), so that the robot "
            "drives straight enough for the runs along the route to keep to its corridors; the "
            "fit takes every run's counts whatever was in force.\n";
  static_cast<void>(apply_fit(c_, next, c_.log));
  straighter_ = true;
}

void AutoSession::verify_by_walls(Outcome& out) {
  const MazeKnowledge& maze = walls_->maze();
  double second_rad = 0.0;
  const std::optional<Corridor> second = walls_->second_corridor(second_rad);
  const double arriving = maze.start_heading_rad + (second ? second_rad : 0.0);
  const Corridor first = walls_->calibration_corridor();
  const Corridor route_end = second ? *second : first;
  double along = 0.0;
  const std::optional<Corridor> best =
      unseen_corridor(maze, route_end.end_column, route_end.end_row, arriving, along);
  if (!best) {
    c_.log << "Verify: no corridor to a side where the route ends (two cells or more, to a "
              "corner): left out (--procedure verify checks the factors with a tape).\n";
    out.result["verify"] = nullptr;
    return;
  }
  const double length_m = best->length_mm() * 1e-3;
  c_.log << fmt::format(
      "Verify: {} runs with the new factors along a corridor no calibration run drove, from cell "
      "({}, {}) to cell ({}, {}) ({:.2f} m), each judged by the walls at its end.\n",
      auto_verify_runs, route_end.end_column, route_end.end_row, best->end_column, best->end_row,
      length_m);
  if (walls_->in_start_cell()) {
    // To where the route ends (no run): each leg looked at.
    for (const Corridor* leg : {&first, second ? &*second : nullptr}) {
      if (leg != nullptr) {
        const double m = walls_->aim_at(leg->end_column, leg->end_row);
        walls_->move_and_look(Motion::line(m).command(), c_.path_seconds(m, 0.0, 1) + 2.0);
      }
    }
  }
  walls_->face(along);
  c_.planned = c_.runs.size() + auto_verify_runs;
  const FitGeometry before_g =
      fit_geometry_of(geometry_in_force(c_.initial, nominal_.wheel_diameter_mm));
  const FitGeometry after_g =
      fit_geometry_of(geometry_in_force(applied_, nominal_.wheel_diameter_mm));
  nlohmann::json stops = nlohmann::json::array();
  double sum2 = 0.0, before2 = 0.0, odometry2 = 0.0;
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
                          {"from_cell", {route_end.end_column, route_end.end_row}},
                          {"to_cell", {best->end_column, best->end_row}},
                          {"goal", {{"x_mm", length_m * 1e3}, {"y_mm", 0.0}}},
                          {"stops", stops},
                          {"rms_mm", rms},
                          {"before_rms_mm", std::sqrt(before2 / n)},
                          {"odometry_rms_mm", std::sqrt(odometry2 / n)},
                          {"flagged", !suspects_.empty()}};
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
