#pragma once
// Internal to the session: the verification step every procedure that verifies uses (verify's
// before and after, auto's check of what it applied): Maddahi's unseen path driven and measured.

#include <cstddef>
#include <string>
#include <vector>

#include "odocal/calib/accuracy.hpp"
#include "odocal/drive/motion_executor.hpp"
#include "odocal/host/path_geometry.hpp"
#include "session_internal.hpp"

namespace odocal::host::session {

/// The unseen path (100 cm square, 100 cm triangle, 80 cm semicircle), where it ends if driven
/// exactly, and how long a run of it takes on this robot.
struct UnseenPath {
  drive::Path path;
  PathEnd goal;
  double expected_s = 0.0;
};

/// The path, its goal, and its nominal duration at the robot's speeds.
UnseenPath unseen_path(Context& c);

/// One stop of the unseen path: where it was measured, and its error (measured − goal), mm.
struct UnseenStop {
  double x_mm = 0.0;
  double y_mm = 0.0;
  calib::EndError error{};
};

/// Drives the unseen path `n` times (runs labelled `label`), each measured as any run
/// (Context::run: Enter, `Run N/M`, the journal); `log_ticks`: each run logged (its counts replay
/// it through another geometry).
std::vector<UnseenStop> drive_unseen(Context& c, const UnseenPath& unseen, const std::string& label,
                                     std::size_t n, bool log_ticks = false);

}  // namespace odocal::host::session
