#pragma once
// Internal to the ROSArduinoBridge robot's host-side console (bridge_console.cpp,
// bridge_commands.cpp): what both halves share.

#include <string>
#include <vector>

#include "odocal/drive/drive_config.hpp"
#include "odocal/host/bridge_console.hpp"

namespace odocal::host::bridge_detail {

/// One PID frame of ROSArduinoBridge, ms.
inline constexpr double kFrameMs = 1000.0 / BridgeConsole::frame_hz;

/// The words of a console line.
[[nodiscard]] std::vector<std::string> words_of(const std::string& line);
/// The parameter called `name`, nullptr when there is none.
[[nodiscard]] const drive::ConfigField* field_named(const std::string& name);
/// The provenance group a parameter belongs to ("wheel", "lateral"), nullptr for none.
[[nodiscard]] const char* group_of(const std::string& name);

}  // namespace odocal::host::bridge_detail
