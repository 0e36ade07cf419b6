#pragma once
/// @file
/// The `odocal fit` subcommand (DESIGN "Host program: sessions and fits").

#include <CLI/CLI.hpp>

namespace odocal::host {

/// Adds `fit` to `app`. Its handler reports its exit status through `exit_code` (0 ok; 2 bad
/// input or data that cannot determine a parameter, with one line on stderr naming the file,
/// line and field, or the parameter).
void register_fit_command(CLI::App& app, int& exit_code);

}  // namespace odocal::host
