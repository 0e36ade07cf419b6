#pragma once
/// @file
/// `odocal session`: a whole calibration through the robot's console (see session.hpp).

#include <CLI/CLI.hpp>

namespace odocal::host {

/// Adds `session` to `app`; its handler reports through `exit_code` (0 ok, 2 bad input or a
/// failed link, with one message on stderr).
void register_session_command(CLI::App& app, int& exit_code);

}  // namespace odocal::host
