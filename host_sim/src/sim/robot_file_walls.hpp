#pragma once
// The robot file's maze and wall-sensor keys (issue 48), read after the robot's geometry.

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "odocal/host/robot_file.hpp"

namespace odocal::host::robot_file_walls {

/// The maze and wall-sensor keys a robot file may hold (for "did you mean").
inline constexpr const char* keys[] = {"maze",
                                       "maze_start_cell",
                                       "maze_start_heading",
                                       "wall_sensor_seed",
                                       "wall_sensor_gains",
                                       "wall_sensor_layout",
                                       "wall_sensor_k_counts_mm2",
                                       "wall_sensor_incidence_power",
                                       "wall_sensor_ambient_counts",
                                       "wall_sensor_noise_counts",
                                       "wall_sensor_range_mm",
                                       "wall_reflectivity_spread"};

[[nodiscard]] bool is_key(std::string_view key);

/// Sets `out.walls` from the document's maze and wall-sensor keys, given the robot's checked
/// geometry (`out.nominal`). False with "<source>: <key>: <why>" in `error` on a bad value.
[[nodiscard]] bool read(const nlohmann::json& doc, const std::string& source, RobotSpec& out,
                        std::string& error);

}  // namespace odocal::host::robot_file_walls
