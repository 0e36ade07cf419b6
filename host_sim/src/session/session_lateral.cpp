#include <stdexcept>

#include "session_internal.hpp"

namespace odocal::host::session {

Outcome run_lateral(Context&) {
  throw std::runtime_error("--procedure lateral: not implemented yet");
}

}  // namespace odocal::host::session
