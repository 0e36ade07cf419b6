// `odocal session --procedure auto`: the budget and the runs' sizes, said before the first run
// (docs/calibration.md "The budget"); with the walls, what the maze allows (docs/maze.md).

#include <algorithm>
#include <string>

#include <fmt/format.h>

#include "auto_plan.hpp"
#include "auto_session.hpp"
#include "model_in_force.hpp"
#include "run_jury.hpp"
#include "session_internal.hpp"
#include "wall_truth.hpp"

namespace odocal::host::session {

using namespace auto_plan;

void AutoSession::plan_the_budget() {
  nominal_.wheel_diameter_mm = c_.get(ParamId::wheel_diameter_mm);
  nominal_.wheelbase_mm = c_.get(ParamId::wheelbase_mm);
  nominal_.counts_per_rev = c_.get(ParamId::counts_per_rev);
  plan_ = plan_for(c_, nominal_.wheelbase_mm);
  if (walls_ != nullptr) {
    // The lines run the start cell's corridor to the wall at its end; a look there fixes both
    // coordinates only with a wall to a side too. Without such a corridor the walls cannot give
    // the wheels' scale (a turn in place has no distance in it).
    const Corridor corridor = walls_->calibration_corridor();
    plan_.arcs = false;
    if (corridor.cells < 2u || !corridor.end_has_side_wall) {
      scale_by_tape(corridor);
    } else {
      plan_.line_m = corridor.length_mm() * 1e-3;
    }
  }
  // The jury judges every run about the geometry in force when the session started.
  jury_ = std::make_unique<RunJury>(
      c_, nominal_, fit_geometry_of(geometry_in_force(c_.initial, nominal_.wheel_diameter_mm)));
  // The budget: every tape measurement of the session (--max-measurements), the self-test's
  // and the verification's included; the first round always fits.
  const std::size_t total = c_.options.max_measurements.value_or(
      plan_.floor_lines ? kFloorMaxMeasurements : kDefaultMaxMeasurements);
  // With the walls and a tape for the scale the self-test and the first turns were looked at:
  // no tape reading (the budget's room counts the turns as runs, so they are added to it).
  const std::size_t spent =
      plan_.floor_lines ? auto_verify_runs : selftest_runs_ + auto_verify_runs;
  const std::size_t room_for_tape = total > spent ? total - spent : 0;
  budget_ = plan_.floor_lines
                ? std::max(room_for_tape, auto_first_round - kFloorFirstTurns) + kFloorFirstTurns
                : std::max(auto_first_round, room_for_tape);
  const double target = target_in_force(c_.options.target_mm, 0.0);
  const Expectation likely = expected_before_runs(plan_, nominal_, target, auto_first_round, 200);
  const Expectation at_budget =
      expected_before_runs(plan_, nominal_, target, auto_first_round, budget_);
  // "Run N/M": M the runs the forecast expects within the budget, from the first run on.
  c_.planned = selftest_runs_ + std::min(budget_, std::max(auto_first_round, likely.runs)) +
               auto_verify_runs;
  // The free turns of a floor_lines plan are runs, not tape readings.
  const std::size_t free = plan_.floor_lines ? kFloorFirstTurns : 0u;
  const std::size_t tape_budget = budget_ - free;
  const std::string first =
      plan_.floor_lines
          ? fmt::format(
                "({:.0f} turns in place each way twice in the start cell, looked at by the "
                "walls; then two {:.2f} m lines on an open floor, each a tape reading)",
                plan_.spin_turns, plan_.line_m)
      : walls_ != nullptr
          ? fmt::format(
                "(four {:.2f} m lines along the start cell's corridor, {:.0f} turns in "
                "place each way)",
                plan_.line_m, plan_.spin_turns)
          : fmt::format(
                "(a {:.2f} m line, {:.0f} turns in place each way, arcs of {:.2f} m radius "
                "each way, a second line)",
                plan_.line_m, plan_.spin_turns, plan_.arc_radius_m);
  c_.log << fmt::format(
      "Auto: {} measured runs first {}, more only where they buy precision, then {} runs {} to "
      "verify.\n"
      "Budget: {} measurements in all (--max-measurements): {} for the self-test, {} to "
      "calibrate, {} to verify. A robot this size that scatters no more than the tape would "
      "reach the target ({:.1f} mm on the unseen path, 1 sigma) in about {} calibration runs{}{}; "
      "a robot that slips more needs more, and the count is updated after every run.{}\n",
      auto_first_round, first, auto_verify_runs,
      lines_in_the_maze() ? "along a corridor no run drove" : "of the unseen path",
      std::max(total, spent + tape_budget), plan_.floor_lines ? 0u : selftest_runs_, tape_budget,
      auto_verify_runs, target, likely.runs,
      plan_.floor_lines ? " (the first four the walls' turns)" : "",
      likely.reached ? (likely.runs > budget_
                            ? fmt::format(": more than the budget, which leaves about {:.1f} mm "
                                          "(--max-measurements {} would do)",
                                          at_budget.sigma_sys_mm, likely.runs + spent - free)
                            : std::string())
                     : std::string(" or more (not within 200)"),
      std::string());
  expected_runs_ = likely.reached ? nlohmann::json(likely.runs) : nlohmann::json(nullptr);
  max_measurements_ = std::max(total, spent + tape_budget);
}

}  // namespace odocal::host::session
