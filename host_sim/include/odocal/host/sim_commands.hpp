#pragma once
/// @file
/// The `odocal sim ...` subcommands, registered into the `odocal` program.

#include <CLI/CLI.hpp>

namespace odocal::host {

/// Adds `sim umbmark|validate|montecarlo` to `app`. The handlers run from `app`'s callbacks and
/// report their exit status through `exit_code` (0 ok; 2 for a bad robot file or picture path,
/// or a procedure that could not finish). Bad flags are CLI11 parse errors.
void register_sim_commands(CLI::App& app, int& exit_code);

}  // namespace odocal::host
