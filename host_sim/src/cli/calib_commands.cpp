#include "odocal/host/calib_commands.hpp"

#include <memory>

#include "calib_cli.hpp"

namespace odocal::host {

using namespace calib_cli;

// Command-line bounds: wide enough for any robot, narrow enough that no result overflows.
constexpr double min_length_mm = 1.0;
constexpr double max_path_length_mm = 1e6;  // 1 km: side of the square, length of a trial
constexpr double max_robot_size_mm = 1e4;   // 10 m: wheelbase, wheel diameter

CLI::Validator path_length_check() {
  return range_check(min_length_mm, max_path_length_mm, "mm");
}
CLI::Validator robot_size_check() {
  return range_check(min_length_mm, max_robot_size_mm, "mm");
}

namespace {

/// `odocal umbmark`: UMBmark from the return errors of the cw and ccw squares.
void add_umbmark_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<UmbmarkOptions>();
  auto* cmd = app.add_subcommand("umbmark", "UMBmark: E_d, E_b, c_L, c_R from cw/ccw runs");
  cmd->add_option("--side-mm", o->side_mm, "side L of the square, mm")
      ->required()
      ->check(path_length_check());
  cmd->add_option("--wheelbase-mm", o->wheelbase_mm, "wheelbase b used during the runs, mm")
      ->required()
      ->check(robot_size_check());
  cmd->add_option("--cw", o->cw_file, "CSV x_mm,y_mm of the clockwise return errors")->required();
  cmd->add_option("--ccw", o->ccw_file, "CSV x_mm,y_mm of the counter-clockwise return errors")
      ->required();
  cmd->add_flag("--json", o->json, "print one JSON object");
  cmd->add_flag("--exact", o->exact, "solve the square geometry without small angles");
  add_date_option(cmd, o->date);
  cmd->callback([o, &exit_code] { guarded("umbmark", exit_code, [o] { run_umbmark(*o); }); });
}

/// `odocal accuracy`: RMS radial error per scenario and the improvement over a baseline.
void add_accuracy_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<AccuracyOptions>();
  auto* cmd = app.add_subcommand("accuracy", "RMS radial error per scenario, improvement");
  cmd->add_option("file", o->file, "CSV scenario,trial,x_mm,y_mm")->required();
  cmd->add_option("--baseline", o->baseline, "scenario to compare with (default: the first)");
  cmd->add_flag("--json", o->json, "print one JSON object");
  add_date_option(cmd, o->date);
  cmd->callback([o, &exit_code] { guarded("accuracy", exit_code, [o] { run_accuracy(*o); }); });
}

/// `odocal lateral`: Maddahi's F_lat and F_lon from straight-line stop points.
void add_lateral_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<LateralOptions>();
  auto* cmd = app.add_subcommand("lateral", "Maddahi F_lat (eq. 4), F_lon (eq. 5)");
  cmd->add_option("--trials", o->file, "CSV x_mm,y_mm of the stop points")->required();
  cmd->add_option("--length-mm", o->length_mm, "commanded length L, mm")
      ->required()
      ->check(path_length_check());
  cmd->add_option("--wheelbase-mm", o->wheelbase_mm, "wheelbase l, mm")
      ->required()
      ->check(robot_size_check());
  cmd->add_option("--dl-mm", o->dl_mm, "left wheel diameter D_L, mm")
      ->required()
      ->check(robot_size_check());
  cmd->add_option("--dr-mm", o->dr_mm, "right wheel diameter D_R, mm")
      ->required()
      ->check(robot_size_check());
  cmd->add_option("--theta-l-rad", o->theta_l_rad,
                  "left wheel rotation per trial, rad (default 2L/D_L; within a factor of 2 "
                  "of it)")
      ->check(number_check("a finite number of rad > 0", [](double v) { return v > 0.0; }));
  cmd->add_flag("--json", o->json, "print one JSON object");
  add_date_option(cmd, o->date);
  cmd->callback([o, &exit_code] { guarded("lateral", exit_code, [o] { run_lateral(*o); }); });
}

/// `odocal bootstrap`: Maddahi's residual bootstrap of the wheel velocities.
void add_bootstrap_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<BootstrapOptions>();
  auto* cmd = app.add_subcommand("bootstrap", "Maddahi residual bootstrap of wheel velocities");
  cmd->add_option("--training", o->training_file,
                  "CSV xdot,ydot,thetadot,omega_l,omega_r (m/s, rad/s)")
      ->required();
  cmd->add_option("--unknowns", o->unknowns_file, "CSV xdot,ydot,thetadot")->required();
  cmd->add_option("--b", o->replicates, "bootstrap replicates B")
      ->check(whole_check(calib::bootstrap_min_replicates, calib::bootstrap_max_replicates,
                          "of replicates"))
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "random seed")
      ->check(whole_check(0, UINT64_MAX, ""))
      ->capture_default_str();
  cmd->add_option("--level", o->level, "interval level")
      ->check(number_check("a finite number strictly between 0 and 1 (e.g. 0.95)",
                           [](double v) { return v > 0.0 && v < 1.0; }))
      ->capture_default_str();
  cmd->add_option("--interval", o->interval,
                  "percentile (the paper's, default) or calibrated (t-widened percentile)")
      ->check(CLI::IsMember({"percentile", "calibrated"}))
      ->capture_default_str();
  cmd->add_option("--wheelbase-mm", o->wheelbase_mm,
                  "with --dl-mm and --dr-mm: also F_lat, F_lon per unknown (eq. 7)")
      ->check(robot_size_check());
  cmd->add_option("--dl-mm", o->dl_mm, "left wheel diameter, mm")->check(robot_size_check());
  cmd->add_option("--dr-mm", o->dr_mm, "right wheel diameter, mm")->check(robot_size_check());
  cmd->add_flag("--json", o->json, "print one JSON object");
  add_date_option(cmd, o->date);
  cmd->callback([o, &exit_code] { guarded("bootstrap", exit_code, [o] { run_bootstrap(*o); }); });
}

/// `odocal ros2`: a diff_drive_controller parameter file from calibrated factors.
void add_ros2_command(CLI::App& app, int& exit_code) {
  auto o = std::make_shared<Ros2Options>();
  auto* cmd = app.add_subcommand("ros2", "ROS 2 diff_drive_controller parameter file");
  auto* from = cmd->add_option("--from", o->from_file, "JSON of `odocal umbmark --json`");
  const auto multiplier = [] {
    return range_check(0.0, ros2_max_multiplier, "", toolkit::LowBound::open);
  };
  auto* c_l = cmd->add_option("--c-l", o->c_l, "left wheel factor c_L")->check(multiplier());
  auto* c_r = cmd->add_option("--c-r", o->c_r, "right wheel factor c_R")->check(multiplier());
  auto* e_b = cmd->add_option("--e-b", o->e_b, "wheelbase factor E_b")->check(multiplier());
  from->excludes(c_l)->excludes(c_r)->excludes(e_b);
  cmd->add_option("--controller", o->controller, "controller name ([A-Za-z_][A-Za-z0-9_]*)")
      ->capture_default_str();
  cmd->add_option("--speed-mps", o->speed_mps,
                  "typical speed for the twist covariance (FIT.json with noise), m/s")
      ->check(range_check(0.0, 20.0, "m/s", toolkit::LowBound::open))
      ->capture_default_str();
  cmd->add_option("--update-rate-hz", o->velocity.update_rate_hz,
                  "the controller manager's update_rate, Hz: diff_drive_controller estimates the "
                  "velocity at every update (docs/ros.md)")
      ->check(range_check(0.0, 10000.0, "Hz", toolkit::LowBound::open))
      ->capture_default_str();
  cmd->add_option("--velocity-window", o->velocity.window,
                  "diff_drive_controller's velocity_rolling_window_size: updates averaged")
      ->check(toolkit::whole_check(1u, 100000u))
      ->capture_default_str();
  cmd->add_option("--pose-distance-m", o->pose_distance_m,
                  "straight distance whose drift the pose covariance gives, m")
      ->check(range_check(0.0, 10000.0, "m", toolkit::LowBound::open))
      ->capture_default_str();
  cmd->callback([o, &exit_code] { guarded("ros2", exit_code, [o] { run_ros2(*o); }); });
}

}  // namespace

void register_calib_commands(CLI::App& app, int& exit_code) {
  add_umbmark_command(app, exit_code);
  add_accuracy_command(app, exit_code);
  add_lateral_command(app, exit_code);
  add_bootstrap_command(app, exit_code);
  add_ros2_command(app, exit_code);
}

}  // namespace odocal::host