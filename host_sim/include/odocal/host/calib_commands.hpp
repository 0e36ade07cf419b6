#pragma once
/// @file
/// The calibration subcommands of `odocal`: umbmark, accuracy, lateral, bootstrap, ros2.

#include <CLI/CLI.hpp>

namespace odocal::host {

/// Adds `umbmark`, `accuracy`, `lateral`, `bootstrap` and `ros2` to `app`. The handlers run from
/// `app`'s callbacks and report their exit status through `exit_code` (0 ok, 2 bad input; the
/// message, naming file, line and field, goes to stderr).
void register_calib_commands(CLI::App& app, int& exit_code);

}  // namespace odocal::host
