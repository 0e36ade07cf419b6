#pragma once
/// @file
/// The simulated calibration procedures behind `odocal sim umbmark|validate|montecarlo`:
/// UMBmark (Borenstein & Feng, section 6) and the Maddahi & Zareinia protocol, run on the
/// simulated robot with the real firmware control loop. Deterministic for a seed.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "odocal/calib/accuracy.hpp"
#include "odocal/calib/bootstrap.hpp"
#include "odocal/calib/lateral.hpp"
#include "odocal/calib/umbmark.hpp"
#include "odocal/drive/motion_executor.hpp"
#include "odocal/host/calib_json.hpp"
#include "odocal/host/extended_figure.hpp"
#include "odocal/host/fit.hpp"
#include "odocal/host/path_geometry.hpp"
#include "odocal/host/sim_robot.hpp"

namespace odocal::host {

/// Receives a one-line progress message ("umbmark: pass 1, run 3/10") while a procedure runs.
using ProgressFn = std::function<void(const std::string&)>;

/// What ground truth a logged run records.
enum class LogTruth {
  end_only,  ///< the tape measure: the measured stop pose (with the robot's noise) in the last row
  path,      ///< motion capture: the exact true pose in every row
};

/// Drives `path` like SimulatedRobot::run_path and records its tick log (DESIGN "Tick log"):
/// cumulative encoder counts every `period_ms` of robot time and at the end (after the wheels
/// came to rest), with the ground truth `truth` asks for. The run starts at the origin, so an
/// end-only log starts at (0, 0, 0). `log.rows` is replaced.
RunOutcome run_path_logged(SimulatedRobot& robot, const drive::Path& path, TickLog& log,
                           LogTruth truth = LogTruth::end_only, std::uint32_t period_ms = 10u,
                           double timeout_s = 600.0);

// ---------------------------------------------------------------------------------------------
// UMBmark

struct UmbmarkOptions {
  double side_m = 4.0;         ///< side L of the square
  std::size_t runs = 5;        ///< runs per direction per pass
  std::size_t max_passes = 2;  ///< corrections applied at most (a second one if 3·SEM says so)
  bool exact = false;          ///< solve without the small-angle approximations
  bool record_paths = false;   ///< keep the true paths (for --svg)
  double v_max_mps = 0.2;      ///< cruise speed on the legs (UMBmark used 0.2 m/s)
  float control_hz = 0.0f;     ///< firmware tick rate; 0 keeps the robot's (1 kHz)
};

/// One set of cw + ccw runs with the factors then in the firmware, and what it solves to.
struct UmbmarkPass {
  calib::WheelFactors factors{};  ///< in the firmware during these runs
  std::vector<calib::ReturnError> cw;
  std::vector<calib::ReturnError> ccw;
  calib::UmbmarkResult result{};
  std::vector<std::vector<PathPoint>> cw_paths;
  std::vector<std::vector<PathPoint>> ccw_paths;
};

struct UmbmarkReport {
  bool ok = false;
  std::string error;                ///< why not ok
  std::vector<UmbmarkPass> passes;  ///< [0] before any correction; back() = after
  calib::WheelFactors applied{};    ///< the final factors
  TrueErrors truth{};
  double recovered_e_d = 1.0;     ///< c_R/c_L applied
  double recovered_e_b = 1.0;     ///< wheelbase applied / nominal
  double improvement_fold = 0.0;  ///< E_max,syst before / after
  double simulated_s = 0.0;       ///< robot time simulated, also when the procedure failed
  std::uint64_t seed = 0;
  UmbmarkOptions options{};
};

/// Runs UMBmark on a robot: 5 cw + 5 ccw before, solve, apply (compose), 5 + 5 after; a second
/// correction when the after-pass's E_max,syst >= 3·SEM.
[[nodiscard]] UmbmarkReport run_umbmark(const RobotSpec& robot, std::uint64_t seed,
                                        const UmbmarkOptions& options,
                                        const ProgressFn& progress = {});

[[nodiscard]] nlohmann::json umbmark_report_json(const UmbmarkReport& report);
[[nodiscard]] std::string umbmark_report_text(const UmbmarkReport& report);
[[nodiscard]] std::string umbmark_report_svg(const UmbmarkReport& report);

// ---------------------------------------------------------------------------------------------
// Maddahi validation

struct ValidateOptions {
  std::size_t trials = 20;        ///< straight calibration trials per floor (the paper: 20)
  double line_m = 1.5;            ///< their length on the smooth floor (the paper: 1.5 m)
  double line_bumps_m = 2.0;      ///< their length over the bumps (the paper: 2 m)
  double trial_v_min_mps = 0.10;  ///< trial cruise speeds spread over [min, max]
  double trial_v_max_mps = 0.30;
  double trial_lateral_spread = 0.01;  ///< trial F_lat spread over 1 ± this (excites eq. 10)
  std::size_t runs = 5;                ///< runs of the unseen path per scenario (the paper: 5)
  std::uint32_t replicates = 1000;     ///< bootstrap B
  double bump_height_m = 0.010;        ///< used when the robot file gives no bumps (Maddahi)
  double bump_spacing_m = 0.200;
  bool record_paths = false;
  /// CF, the recommended calibration (docs/calibration.md section 4): the straight trials above,
  /// `cf_squares` cw + `cf_squares` ccw squares of `cf_side_m`, and `cf_spins` cw + `cf_spins`
  /// ccw turns in place of `cf_spin_turns` turns, all with the nominal geometry and each
  /// measured only where it stopped (x, y, heading, with the robot's measurement noise), fitted
  /// by `odocal fit`.
  std::size_t cf_squares = 2;
  double cf_side_m = 1.0;
  std::size_t cf_spins = 4;
  double cf_spin_turns = 5.0;
};

/// One scenario (NC, CL, CB, OR or CF) on the unseen path.
struct ValidateScenario {
  std::string name;
  double c_l = 1.0;  ///< wheel factors and wheelbase in the firmware (OR, CF; 1, 1, told else)
  double c_r = 1.0;
  double wheelbase_mm = 0.0;
  calib::LateralResult factors{};       ///< F_lat, F_lon in the firmware
  std::vector<calib::EndError> errors;  ///< reached minus desired END point, mm
  std::vector<std::vector<PathPoint>> paths;
};

/// One floor (smooth: "systematic"; with bumps: "bumps").
struct ValidateFloor {
  std::string name;
  double bump_height_m = 0.0;
  double bump_spacing_m = 0.0;
  double line_m = 0.0;
  std::vector<calib::TrainingRow> training;
  std::vector<calib::StopPoint> stops;  ///< where each straight trial stopped, mm
  calib::LateralResult eq45{};          ///< eq. 4/5 from the stop points (for reference)
  calib::BootstrapEstimate estimate{};  ///< wheel rates for the straight unknown
  calib::UnknownRow unknown{};
  std::vector<TickLog> cf_logs;             ///< the CF trial runs (straight trials, squares)
  std::optional<FitResult> cf_fit;          ///< what `odocal fit` made of them
  std::vector<ValidateScenario> scenarios;  ///< NC, CL, CB, OR, CF
  std::vector<ScenarioAccuracy> accuracy;   ///< RMS and improvement against NC
};

struct ValidateReport {
  bool ok = false;
  std::string error;
  std::vector<ValidateFloor> floors;
  double wheelbase_told_mm = 0.0;  ///< the actual wheelbase l̂ the paper's eq. 7 assumes known
  double simulated_s = 0.0;        ///< robot time simulated, also when the procedure failed
  std::uint64_t seed = 0;
  ValidateOptions options{};
};

/// The Maddahi protocol on both floors.
[[nodiscard]] ValidateReport run_validate(const RobotSpec& robot, std::uint64_t seed,
                                          const ValidateOptions& options,
                                          const ProgressFn& progress = {});

[[nodiscard]] nlohmann::json validate_report_json(const ValidateReport& report);
[[nodiscard]] std::string validate_report_text(const ValidateReport& report);
[[nodiscard]] std::string validate_report_svg(const ValidateReport& report);

// ---------------------------------------------------------------------------------------------
// Extended UMBmark (non-systematic errors)

struct ExtendedOptions {
  double side_m = 4.0;         ///< side L of the UMBmark square
  std::size_t runs = 5;        ///< runs per direction, on each floor (the published test: 5)
  std::size_t bumps = 10;      ///< cables laid along the first leg (the published test: 10)
  double bump_height_m = 0.0;  ///< 0: the robot file's bump_height_mm, else 10 mm (published)
  bool right_wheel = true;     ///< the wheel that rolls over the cables
  double v_max_mps = 0.2;      ///< cruise speed on the legs
  bool record_paths = false;   ///< keep the true paths (for --svg)
};

struct ExtendedReport {
  bool ok = false;
  std::string error;
  std::vector<ExtendedRun> reference;  ///< bump-free runs, cw then ccw
  std::vector<ExtendedRun> bump_runs;  ///< runs over the cables, cw then ccw
  ExtendedFigure figure{};
  double bump_height_m = 0.0;
  double bump_first_m = 0.0;    ///< floor distance from the start mark to the first cable
  double bump_spacing_m = 0.0;  ///< between two cables
  std::vector<std::vector<PathPoint>> reference_paths;
  std::vector<std::vector<PathPoint>> bump_paths;
  double simulated_s = 0.0;
  std::uint64_t seed = 0;
  ExtendedOptions options{};
};

/// The extended UMBmark on a robot (its nominal geometry in the firmware): `runs` cw + `runs` ccw
/// squares on a smooth floor, then the same over `bumps` cables laid under one wheel along the
/// first leg.
[[nodiscard]] ExtendedReport run_extended(const RobotSpec& robot, std::uint64_t seed,
                                          const ExtendedOptions& options,
                                          const ProgressFn& progress = {});

[[nodiscard]] nlohmann::json extended_report_json(const ExtendedReport& report);
[[nodiscard]] std::string extended_report_text(const ExtendedReport& report);
[[nodiscard]] std::string extended_report_svg(const ExtendedReport& report);

// ---------------------------------------------------------------------------------------------
// Monte Carlo

struct MonteCarloOptions {
  std::size_t robots = 100;
  unsigned threads = 2;
  double diameter_spread = 0.005;  ///< each true diameter: nominal·(1 ± U), relative
  double wheelbase_spread = 0.02;  ///< true wheelbase: nominal·(1 ± U), relative
  UmbmarkOptions umbmark{};        ///< the procedure each robot goes through
  std::uint32_t physics_step_ns = 2000000u;
};

/// One robot's outcome.
struct MonteCarloRobot {
  bool ok = false;
  std::string error;  ///< why not ok (the UMBmark report's error)
  TrueErrors truth{};
  double recovered_e_d = 1.0;
  double recovered_e_b = 1.0;
  double e_max_before_mm = 0.0;
  double e_max_after_mm = 0.0;
  double improvement_fold = 0.0;
  std::size_t passes = 0;
  double simulated_s = 0.0;
};

struct MonteCarloReport {
  std::vector<MonteCarloRobot> robots;
  double simulated_s = 0.0;
  std::uint64_t seed = 0;
  MonteCarloOptions options{};
};

/// Random robots around `robot`'s nominal geometry (its noise and floor kept), each calibrated
/// by UMBmark, on `options.threads` threads. Same seed, same report, whatever the thread count.
[[nodiscard]] MonteCarloReport run_montecarlo(const RobotSpec& robot, std::uint64_t seed,
                                              const MonteCarloOptions& options,
                                              const ProgressFn& progress = {});

[[nodiscard]] nlohmann::json montecarlo_report_json(const MonteCarloReport& report);
[[nodiscard]] std::string montecarlo_report_text(const MonteCarloReport& report);
[[nodiscard]] std::string montecarlo_report_svg(const MonteCarloReport& report);

}  // namespace odocal::host
