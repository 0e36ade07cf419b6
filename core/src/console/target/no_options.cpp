// The console without its target options (ConsoleOptions: a target's own command, its status
// pairs, its defaults), for the images that use none (the STM32F4 ones; core/CMakeLists.txt): no
// target command, no pairs of its own, the built-in defaults. The code that would serve them is
// not linked (226 B of the robot's flash). Each image chooses its wall sensors' code apart
// (walls_read.cpp or walls_none.cpp).

#include "odocal/console/console.hpp"
#include "odocal/console/settings.hpp"

namespace odocal::console {

bool Console::run_target_command(const Token* /*words*/, std::size_t /*count*/) {
  return false;
}

const char* Console::target_usage() const {
  return nullptr;
}

void Console::append_target_status(Reply& /*reply*/) {}

const params::ParamSet* Settings::usable_defaults(const params::ParamSet* /*defaults*/) {
  return nullptr;
}

params::ParamSet Settings::defaults() const {
  return params::default_params();
}

float Settings::default_value(params::ParamId id) const {
  return params::default_params().get(id);
}

}  // namespace odocal::console
