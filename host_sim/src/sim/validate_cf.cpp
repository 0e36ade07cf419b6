// Logged runs on the simulated robot: tick logs (DESIGN "Tick log") recorded while a path runs,
// for the CF calibration of `odocal sim validate` and for tests of `odocal fit`.

#include <cmath>
#include <numbers>

#include "odocal/host/sim_procedures.hpp"

namespace odocal::host {

RunOutcome run_path_logged(SimulatedRobot& robot, const drive::Path& path, TickLog& log,
                           LogTruth truth, std::uint32_t period_ms, double timeout_s) {
  constexpr double rad_to_deg = 180.0 / std::numbers::pi;
  log.rows.clear();
  const TraceFn record = [&](const sim::WorldPose& pose) {
    TickRow row;
    row.t_s = robot.simulated_s();
    row.count_l = static_cast<double>(robot.plant().left().encoder_count());
    row.count_r = static_cast<double>(robot.plant().right().encoder_count());
    if (truth == LogTruth::path) {
      row.has_xy = true;
      row.has_theta = true;
      row.x_mm = pose.x_m * 1e3;
      row.y_mm = pose.y_m * 1e3;
      row.theta_deg = pose.theta_rad * rad_to_deg;
    }
    // The final record (after the rest) can fall on the instant of the last periodic one.
    if (!log.rows.empty() && !(row.t_s > log.rows.back().t_s)) {
      log.rows.back() = row;
    } else {
      log.rows.push_back(row);
    }
  };
  const RunOutcome out = robot.run_path(path, timeout_s, record, period_ms);
  if (truth == LogTruth::end_only && !log.rows.empty()) {
    TickRow& last = log.rows.back();
    last.has_xy = true;
    last.has_theta = true;
    last.x_mm = out.measured.x_m * 1e3;
    last.y_mm = out.measured.y_m * 1e3;
    last.theta_deg = out.measured.theta_rad * rad_to_deg;
  }
  return out;
}

}  // namespace odocal::host
