#pragma once
/// @file
/// A serial port as the robot link's channel: plain termios, 8N1, raw, exclusive.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "odocal/host/robot_link.hpp"

namespace odocal::host {

/// Opens a serial port: must exist, be a tty and not be held by another program (flock and
/// TIOCEXCL); then 8N1, raw, no flow control, at `baud`. Throws LinkError naming the port and why.
[[nodiscard]] std::unique_ptr<FdChannel> open_serial_port(const std::string& path,
                                                          std::uint32_t baud);

/// The baud rates open_serial_port takes.
[[nodiscard]] std::vector<std::uint32_t> supported_bauds();

}  // namespace odocal::host
