#include <CLI/CLI.hpp>

#include "odocal/host/calib_commands.hpp"
#include "odocal/host/fit_command.hpp"
#include "odocal/host/session_command.hpp"
#include "odocal/host/sim_commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"odocal: odometry calibration tools"};
  app.require_subcommand(1);
  int exit_code = 0;
  odocal::host::register_calib_commands(app, exit_code);
  odocal::host::register_sim_commands(app, exit_code);
  odocal::host::register_fit_command(app, exit_code);
  odocal::host::register_session_command(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int status = app.exit(e);
    return status == 0 ? 0 : 2;
  }
  return exit_code;
}
