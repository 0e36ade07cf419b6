#pragma once
// What the robot link's parts share (robot_link.cpp, serial_port.cpp, sim_process.cpp,
// robot_client.cpp): time left to a deadline, and an errno message. Not part of the library's
// interface.

#include <cerrno>
#include <chrono>
#include <cstring>
#include <string>

namespace odocal::host::link_detail {

using Clock = std::chrono::steady_clock;

/// Milliseconds left until `deadline`, 0 once it has passed.
inline int remaining_ms(Clock::time_point deadline) {
  const auto left =
      std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return left > 0 ? static_cast<int>(left) : 0;
}

/// "`what`: " and errno's message.
inline std::string system_error(const std::string& what) {
  return what + ": " + std::strerror(errno);
}

}  // namespace odocal::host::link_detail
