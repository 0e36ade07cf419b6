#include "odocal/host/sim_commands.hpp"

#include <iostream>

namespace odocal::host {

void register_sim_commands(CLI::App& app, int& exit_code) {
  auto* sim = app.add_subcommand("sim", "Simulated calibration procedures");
  sim->require_subcommand(1);
  for (const char* name : {"umbmark", "validate", "montecarlo"}) {
    auto* sub = sim->add_subcommand(name, "not built yet");
    sub->allow_extras();
    sub->callback([&exit_code, name] {
      std::cerr << "odocal sim " << name << ": not built yet\n";
      exit_code = 2;
    });
  }
}

}  // namespace odocal::host
