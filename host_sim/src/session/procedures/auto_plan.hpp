#pragma once
// Internal to the session: how `--procedure auto` plans its runs (docs/calibration.md "How auto
// chooses its runs"): the kinds of run, their commands and instructions, and the precision the
// runs so far leave on the unseen path, with the run that lowers it the most.

#include <cstddef>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "odocal/host/fit.hpp"
#include "session_internal.hpp"

namespace odocal::host::session::auto_plan {

constexpr double kPi = std::numbers::pi;
constexpr double kMeasureSigmaMm = 2.0;        ///< a tape over a few metres (docs/calibration.md)
constexpr double kHeadingLengthMm = 286.4789;  ///< 2 mm per 0.4 degree, as odocal fit
/// --max-measurements' default: every tape measurement of the session (self-test, calibration,
/// verification). docs/calibration.md "The budget" says where it comes from.
constexpr std::size_t kDefaultMaxMeasurements = 20;
/// Its default with the walls and a tape for the scale (Plan::floor_lines): the fewest the option
/// allows, eight lines and the verification's two. Past the first lines a mouse's own drift
/// outweighs the tape's error, and more lines buy little (docs/maze.md).
constexpr std::size_t kFloorMaxMeasurements = 10;
/// --target's floor: the factors add no more to the unseen path's end than one tape
/// measurement's error (docs/calibration.md).
constexpr double kDefaultTargetMm = 2.0;
/// A default target relative to the robot's own random drift (this share of sigma_random) was
/// tried and is off (0): with half or a third of the drift, sessions stopped where their stated
/// precision was 2.9 times too good, or where the drift itself was estimated 2.5 times too high
/// (an unmodelled arc wheelbase), and ended 1.8-2.0 times the oracle (docs/calibration.md).
constexpr double kTargetDriftShare = 0.0;

/// Calibration runs before a drift-relative target may count as met: the first round's six runs
/// give the fit's covariance and the drift estimate about one degree of freedom per parameter
/// (the runs' Bell-McCaffrey figure), too few to trust (a generated robot stopped there with 5.6
/// times the systematic error it stated). A 2 mm target needs no such floor.
constexpr std::size_t kDriftTargetMinRuns = 10;

/// The one-sided bound a variance estimated with `dof` degrees of freedom has below it with the
/// probability of one sigma (84 %), as a factor on the estimated standard deviation:
/// sqrt(dof / chi2_0.16(dof)) (Wilson-Hilferty's chi-square quantile), 1 without an estimate
/// (dof <= 0). About 1.5 at 6 degrees of freedom, 1.2 at 20, 1.1 at 100.
double stop_factor_for(double dof);

/// stop_factor_for the runs' degrees of freedom `dof` and `more` runs to come (1e9 and more:
/// not estimated).
double widen_at(double dof, std::size_t more);

/// The target in force: `target` (the user's --target) when given, else the default above for a
/// robot whose drift is estimated as `sigma_random_mm` (0: not estimated yet).
double target_in_force(std::optional<double> target, double sigma_random_mm);

enum class Kind { line, spin_ccw, spin_cw, arc_left, arc_right };

/// The label of a run of `k` (`line`, `turns-ccw`, ...).
const char* kind_label(Kind k);
/// The kind a label names (nullopt: not a calibration run's label, e.g. `verify`).
std::optional<Kind> kind_of_label(const std::string& label);

/// What the runs are made of, from the robot's size and speeds.
struct Plan {
  double line_m = 2.0;
  double spin_radps = 2.0;
  double spin_turns = 5.0;
  double arc_radius_m = 0.4;
  double arc_rad = 1.5 * kPi;
  double arc_mps = 0.2;
  double cruise_mps = 0.3;
  /// Arcs among the runs (not in a maze: its corridors leave room for lines and turns in place).
  bool arcs = true;
  /// With the walls, in a maze whose start corridor cannot give the wheels' scale: the turns in
  /// place measured by the walls in the start cell, the lines (and every run after the first
  /// round) by a tape on an open floor.
  bool floor_lines = false;
};

/// The first round: every parameter seen from two sides. With the walls (no arcs in a maze's
/// corridors) lines out and back take the arcs' places: lines are what give the wheels' ratio.
constexpr std::size_t kFirstRound = 6;
constexpr Kind kTapeFirstRound[kFirstRound] = {Kind::line, Kind::spin_ccw, Kind::arc_left,
                                               Kind::line, Kind::spin_cw,  Kind::arc_right};
constexpr Kind kWallsFirstRound[kFirstRound] = {Kind::line,    Kind::spin_ccw, Kind::line,
                                                Kind::spin_cw, Kind::line,     Kind::line};
/// With the walls and a tape for the scale (Plan::floor_lines): the turns first, in the start
/// cell, for nothing (the walls measure them); then the two lines the scale and the wheels' ratio
/// need at least, each a tape reading.
constexpr std::size_t kFloorFirstTurns = 4;
constexpr Kind kFloorFirstRound[kFirstRound] = {Kind::spin_ccw, Kind::spin_cw, Kind::spin_ccw,
                                                Kind::spin_cw,  Kind::line,    Kind::line};
[[nodiscard]] constexpr const Kind* first_round_of(const Plan& p) {
  return p.arcs ? kTapeFirstRound : p.floor_lines ? kFloorFirstRound : kWallsFirstRound;
}

/// The drive command of a run of `k`, and its nominal duration (`expected_s`).
Motion motion_of(Kind k, const Plan& p, double& expected_s, Context& c);

/// What the user is to do and measure for a run of `k`.
std::string what_to_do(Kind k, const Plan& p);

/// The runs' sizes from the robot's wheelbase, speeds and --side-m.
Plan plan_for(Context& c, double wheelbase_mm);

/// What the runs so far leave on the unseen path, and the run to drive next.
struct Precision {
  double sigma_sys_mm = 0.0;
  double sigma_random_mm = 0.0;  ///< 0: not estimated
  double target_mm = 0.0;
  Kind next = Kind::line;
  std::size_t more = 0;      ///< runs expected before the target is met (capped)
  std::size_t min_runs = 0;  ///< calibration runs before the target may count as met
  /// What sigma_sys_mm is widened by before it is compared with the target: the runs' scatter
  /// is itself estimated from few degrees of freedom, and stopping at the first estimate below
  /// the target picks the estimates that came out low (stop_factor_for).
  double stop_factor = 1.0;
  /// The arcs look like another wheelbase the runs cannot pin yet: not done before more arcs.
  bool arc_unresolved = false;
  /// What the factors are expected to leave (1 sigma, mm) once the runs there is room for are
  /// driven, and whether the target is expected within them.
  double sigma_at_room_mm = 0.0;
  bool reached_in_room = true;
  nlohmann::json noise;  ///< `odocal fit`'s `noise` object, null when not estimated
};

/// The fit's comparison of model `kind` (nullptr when it was not among the candidates).
const FitCandidate* candidate_of(const FitResult& r, FitModelKind kind);

/// The precision the fit `r` of `logs` leaves, the next run, and how many more runs (at most
/// `room`) the target likely takes; `arc_count` the arcs driven so far.
Precision precision_of(const FitResult& r, const FitNominal& nominal,
                       const std::vector<TickLog>& logs, const Plan& plan,
                       std::optional<double> target, std::size_t room, std::size_t arc_count);

/// A run whose measured end the fitted geometry cannot explain as it explains the others: a
/// reading typed wrong (a heading's sign), or a run that went wrong (a wheel caught). Its end
/// residual, in mm with the heading weighed as the fit weighs it (kHeadingLengthMm per radian),
/// is more than kSuspectFactor times the runs' median and more than kSuspectFloorMm.
struct SuspectRun {
  std::size_t index = 0;     ///< into the logs
  double position_mm = 0.0;  ///< measured − predicted, position
  double heading_deg = 0.0;  ///< measured − predicted, heading (wrapped)
  double residual_mm = 0.0;  ///< the two together
  double typical_mm = 0.0;   ///< the runs' median residual
};
constexpr double kSuspectFactor = 6.0;
constexpr double kSuspectFloorMm = 5.0 * kMeasureSigmaMm;
std::vector<SuspectRun> suspect_runs(const std::vector<TickLog>& logs, const FitNominal& nominal,
                                     const FitGeometry& geometry);

/// `suspects` as `result.suspect_runs` (run, label, position_mm, heading_deg, typical_mm) and,
/// in `named`, as one line of text ("run 17 (turns-ccw: 2 mm and 40.8 deg off the fit, ...)");
/// log i is the session's run `first_run + i` (1-based), its label from `c.runs`.
nlohmann::json describe_suspects(const std::vector<SuspectRun>& suspects, const Context& c,
                                 std::size_t first_run, std::string& named);

/// What the target likely takes before anything was measured: the first round and then the
/// runs auto would choose, on the nominal geometry known to 3 % and a tape's noise (a robot that
/// scatters more than the tape needs more; the count is updated after every run).
struct Expectation {
  std::size_t runs = 0;       ///< calibration runs (at most `room`)
  double sigma_sys_mm = 0.0;  ///< what they leave on the unseen path
  bool reached = false;       ///< the target within `room`
};
Expectation expected_before_runs(const Plan& plan, const FitNominal& nominal, double target_mm,
                                 std::size_t first_round, std::size_t room);

}  // namespace odocal::host::session::auto_plan
