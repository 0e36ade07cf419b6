#pragma once
/// @file
/// The extended UMBmark's figure and floor (Borenstein & Feng's report, section 3.4; their 1996
/// paper, section V; the project's reading in docs/architecture.md), for the simulator
/// (`odocal sim extended`) and the session (`--procedure extended`) alike.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace odocal::host {

/// One run of the extended UMBmark: its return errors, measured minus odometry (as UMBmark).
struct ExtendedRun {
  bool clockwise = true;
  double theta_error_deg = 0.0;  ///< measured heading minus odometry heading, wrapped to ±180°
  double x_mm = 0.0;
  double y_mm = 0.0;
  std::uint32_t bumps_crossed = 0;  ///< cables the robot's wheels actually rolled over
};

/// The figure of the extended UMBmark from its runs (docs/architecture.md): per direction, the
/// average of |θ_i − θ̄_ref| over the bump runs i, θ̄_ref the bump-free runs' average orientation
/// error in that direction; e_nonsys_deg = the sum of the two directions' averages.
struct ExtendedFigure {
  double reference_cw_deg = 0.0;
  double reference_ccw_deg = 0.0;
  double e_cw_deg = 0.0;
  double e_ccw_deg = 0.0;
  double e_nonsys_deg = 0.0;
  double sd_deg = 0.0;     ///< approximate standard error of e_nonsys_deg (run-to-run scatter)
  double ci_lo_deg = 0.0;  ///< approximate 95 % interval (Student t)
  double ci_hi_deg = 0.0;
};

/// Computes the figure; false (and `figure` untouched) unless every list has at least 2 runs.
[[nodiscard]] bool extended_figure(const std::vector<ExtendedRun>& reference_cw,
                                   const std::vector<ExtendedRun>& reference_ccw,
                                   const std::vector<ExtendedRun>& bumps_cw,
                                   const std::vector<ExtendedRun>& bumps_ccw,
                                   ExtendedFigure& figure);

/// Where the cables go: `count` evenly spaced along a leg of `side_m`, half a spacing from each
/// end (first = side/(2·count), spacing = side/count).
void extended_bump_layout(double side_m, std::size_t count, double& first_m, double& spacing_m);

}  // namespace odocal::host
