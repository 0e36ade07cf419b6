#pragma once
/// @file
/// Where the paths the robot drives go, for the simulator and the session alike: a point of a
/// drawn path, and the end of a path driven exactly (the one model's exact arcs,
/// drive::model::advance_arc). The paths themselves (the UMBmark square, Maddahi's line and
/// unseen path) are the firmware's (drive/motion_executor.hpp); the extended UMBmark's cable
/// layout is `extended_bump_layout` (extended_figure.hpp).

#include "odocal/drive/motion_executor.hpp"

namespace odocal::host {

/// A point of a driven path, m (world frame = start frame).
struct PathPoint {
  double x_m = 0.0;
  double y_m = 0.0;
};

/// A pose in the start frame: x along the start heading, y to the left, m; θ CCW, rad.
struct PathEnd {
  double x_m = 0.0;
  double y_m = 0.0;
  double theta_rad = 0.0;
};

/// Where a path ends if driven exactly (the desired END point), start frame.
[[nodiscard]] PathEnd path_end(const drive::Path& path);

}  // namespace odocal::host
