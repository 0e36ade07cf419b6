#pragma once
// Internal to the session: `--procedure auto`'s steps (session_auto.cpp), and those with the walls
// as the measurements (session_auto_walls.cpp).

#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "auto_plan.hpp"
#include "odocal/host/fit.hpp"
#include "run_jury.hpp"
#include "session_internal.hpp"
#include "wall_truth.hpp"

namespace odocal::host::session {

/// `odocal fit`'s text without what is advice for its own command line (held-out logs, the
/// console lines to type): auto applies the result itself.
std::string fit_text_for_auto(const FitResult& r);
/// How a tape measures a run's stop (the start mark, the two marks on the robot, x, y, heading).
std::string tape_how_to();

/// One auto session's state and its steps, in the order run_auto takes them.
class AutoSession {
 public:
  explicit AutoSession(Context& c) : c_(c), walls_(dynamic_cast<WallTruth*>(&c.source)) {}

  /// `--truth walls`: the sensors learnt from the start cell before the first run (the owner's
  /// one moment: the robot put down in the start cell).
  void learn_the_walls(Outcome& out);

  /// 1. The wiring: a miswired robot passes for a bad calibration. Throws when a fault stays.
  void check_wiring(Outcome& out);
  /// The runs: a first round that sees every parameter from two sides, then one at a time the
  /// kind that lowers the unseen path's uncertainty the most, until the target or the budget.
  void measure_until_known(Outcome& out);
  /// 2. The final fit with its intervals, checked and applied (the one apply step).
  void apply_final_fit(Outcome& out);
  /// 3. Verification on the unseen path with the factors in force (the verify procedure's step).
  void verify(Outcome& out);
  /// 3. With the walls: a corridor the calibration never drove, judged by the walls.
  void verify_by_walls(Outcome& out);
  /// With the walls, after the first round: its fit put in force (no save), so that the robot
  /// drives straight enough for the route's runs (a quarter turn between two corridors) to keep
  /// to their corridors. The fit takes every run's counts whatever was in force.
  void drive_straighter();

 private:
  /// With the walls, when the start cell's `corridor` cannot give the wheels' scale (under two
  /// cells, or no corner at its end): says so and plans the fewest tape readings that can (the
  /// turns in place still by the walls, then lines on an open floor), or throws when the session
  /// has no tape to ask.
  void scale_by_tape(const Corridor& corridor);
  /// The owner takes the robot out of the maze to an open floor; the tape measures from here on.
  void to_the_floor();
  /// The walls measure the lines too: the maze's corridors give the scale (no floor_lines).
  [[nodiscard]] bool lines_in_the_maze() const { return walls_ != nullptr && !plan_.floor_lines; }
  /// The runs' sizes, the budget of measurements and the count the target likely takes, said
  /// before the first run.
  void plan_the_budget();
  void drive_one(auto_plan::Kind k, const std::string& why);
  FitResult fit_with(const FitOptions& options);
  FitResult fit_now();
  /// The target met by the runs so far (their precision widened by its own uncertainty,
  /// p_.stop_factor, and enough runs, p_.min_runs).
  bool target_met() const {
    return p_.stop_factor * p_.sigma_sys_mm <= p_.target_mm && in_use() >= p_.min_runs;
  }
  /// Calibration runs measured (each a tape measurement of the budget), and those the fit uses
  /// (every one but those that disagreed and were driven again or left out).
  std::size_t driven() const { return jury_->size(); }
  std::size_t in_use() const { return jury_->runs_in_use().size(); }
  /// Calibration measurements the budget has left.
  std::size_t room() const { return budget_ > driven() ? budget_ - driven() : 0; }
  /// --resume: the kind of the run the interrupted session drove next (nullopt: none, or a
  /// verification run).
  std::optional<auto_plan::Kind> recorded_kind() const {
    if (c_.runs.size() >= c_.options.replay.size()) {
      return std::nullopt;
    }
    return auto_plan::kind_of_label(c_.options.replay[c_.runs.size()].label);
  }
  bool recorded_verification_next() const {
    return c_.runs.size() < c_.options.replay.size() && !recorded_kind();
  }
  /// Records and says the precision so far; true when measuring is done.
  bool report();

  Context& c_;
  FitNominal nominal_;
  auto_plan::Plan plan_;
  std::size_t selftest_runs_ = 0;
  std::size_t budget_ = 0;
  std::size_t max_measurements_ = 0;
  nlohmann::json expected_runs_ = nullptr;  ///< before the first run: runs the target likely takes
  std::vector<auto_plan::SuspectRun> suspects_;  ///< runs the final fit cannot explain
  std::unique_ptr<RunJury> jury_;                ///< every calibration run judged by the others
  Factors applied_;                              ///< the factors the session applied
  std::size_t arc_runs_ = 0;
  nlohmann::json chosen_ = nlohmann::json::array();
  nlohmann::json progress_ = nlohmann::json::array();
  FitOptions fo_;
  FitResult fitted_;
  auto_plan::Precision p_;
  WallTruth* walls_ = nullptr;   ///< the walls measure the runs (--truth walls), else a tape
  bool straighter_ = false;      ///< drive_straighter put the first round's fit in force
  std::size_t walls_lines_ = 0;  ///< lines driven with the walls (WallTruth::corridor_line)
  std::string tape_why_;         ///< what the walls cannot tell, when a tape gives it
};

}  // namespace odocal::host::session
