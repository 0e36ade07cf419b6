#include <stdexcept>

#include "session_internal.hpp"

namespace odocal::host::session {

Outcome run_fit(Context&) {
  throw std::runtime_error("--procedure fit: not implemented yet");
}

}  // namespace odocal::host::session
