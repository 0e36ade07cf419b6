// The robot file's maze and wall sensors (issue 48): which maze, where the robot starts in it, and
// the sensors' mounts, gains and response. Read after the robot's geometry, which decides whether
// the robot fits a maze at all.

#include "robot_file_walls.hpp"

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include <fmt/format.h>

namespace odocal::host {

sim::MazePose WallsSpec::start_pose() const {
  double heading_rad = 0.0;
  switch (start_heading) {
    case sim::Side::north:
      heading_rad = 0.5 * std::numbers::pi;
      break;
    case sim::Side::east:
      heading_rad = 0.0;
      break;
    case sim::Side::south:
      heading_rad = -0.5 * std::numbers::pi;
      break;
    case sim::Side::west:
      heading_rad = std::numbers::pi;
      break;
  }
  return sim::Maze::cell_centre(start_column, start_row, heading_rad);
}

bool fits_maze(const drive::DriveConfig& nominal) {
  return static_cast<double>(nominal.wheelbase_mm) +
             static_cast<double>(nominal.wheel_diameter_mm) <=
         maze_clear_width_mm;
}

WallsSpec usual_mouse_in_practice_maze(std::uint64_t seed) {
  WallsSpec walls;
  walls.source = MazeSource::practice;
  walls.maze = sim::practice_maze();
  walls.start_column = 0u;
  walls.start_row = 0u;
  walls.start_heading = sim::Side::north;
  walls.seed = seed;
  walls.sensors =
      sim::with_random_gains(sim::WallSensorLayout{}, default_wall_sensor_gain_spread, seed);
  return walls;
}

namespace robot_file_walls {

bool is_key(std::string_view key) {
  for (const char* known : keys) {
    if (key == known) {
      return true;
    }
  }
  return false;
}

namespace {

bool walls_fail(std::string& error, const std::string& source, const std::string& key,
                const std::string& why) {
  error = source + ": " + key + ": " + why;
  return false;
}

// A maze text of 32x32 cells is 65 lines of 129 characters (8.4 kB): more is not a maze.
constexpr std::uintmax_t maze_file_max_bytes = 65536u;

/// Reads a maze text file (its path relative to the robot file's folder) into `walls`.
bool read_maze_file(const std::string& given, const std::string& source, WallsSpec& walls,
                    std::string& error) {
  const std::filesystem::path path = std::filesystem::path(source).parent_path() / given;
  const std::string shown = path.string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    return walls_fail(error, source, "maze",
                      shown +
                          ": no such maze file (a path is taken from the robot file's folder; "
                          "or \"practice\", \"none\")");
  }
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec || size > maze_file_max_bytes) {
    return walls_fail(error, source, "maze", shown + ": larger than a 32x32 maze's text (64 kB)");
  }
  std::ifstream in(path, std::ios::binary);
  std::string text(static_cast<std::size_t>(size), '\0');
  if (!in || !in.read(text.data(), static_cast<std::streamsize>(size))) {
    return walls_fail(error, source, "maze", shown + ": cannot read");
  }
  sim::Maze maze;
  const sim::MazeTextStatus status = sim::parse_maze_text(text, maze);
  if (!status.ok()) {
    std::array<char, 160> why{};
    static_cast<void>(sim::describe(status, why.data(), why.size()));
    return walls_fail(error, source, "maze", shown + ": " + why.data());
  }
  walls.source = MazeSource::file;
  walls.maze_file = shown;
  walls.maze = maze;
  return true;
}

/// `maze`: "practice" (the default for a robot that fits), "none" (the default otherwise), or a
/// maze text file.
bool read_maze(const nlohmann::json& doc, const std::string& source, const RobotSpec& robot,
               WallsSpec& walls, std::string& error) {
  const bool fits = fits_maze(robot.nominal);
  const auto it = doc.find("maze");
  if (it == doc.end()) {
    walls.source = fits ? MazeSource::practice : MazeSource::none;
  } else if (!it->is_string() || it->get<std::string>().empty()) {
    return walls_fail(error, source, "maze",
                      "must be \"practice\", \"none\" or the path of a maze text file");
  } else if (it->get<std::string>() == "none") {
    walls.source = MazeSource::none;
  } else if (it->get<std::string>() == "practice") {
    walls.source = MazeSource::practice;
  } else if (!read_maze_file(it->get<std::string>(), source, walls, error)) {
    return false;
  }
  if (walls.source == MazeSource::practice) {
    walls.maze = sim::practice_maze();
  }
  if (walls.present() && !fits) {
    return walls_fail(
        error, source, "maze",
        fmt::format("the robot does not fit a maze: wheelbase_mm + wheel_diameter_mm = {:g} mm is "
                    "wider than a corridor's {:g} mm (give a mouse's geometry, or \"none\")",
                    static_cast<double>(robot.nominal.wheelbase_mm) +
                        static_cast<double>(robot.nominal.wheel_diameter_mm),
                    maze_clear_width_mm));
  }
  return true;
}

/// A whole number from 0 to `max` (JSON integer or a double holding one).
bool whole_number(const nlohmann::json& value, double max, double& out) {
  if (!value.is_number()) {
    return false;
  }
  out = value.get<double>();
  return std::isfinite(out) && out >= 0.0 && out <= max && std::floor(out) == out;
}

/// `maze_start_cell` [column, row] and `maze_start_heading`.
bool read_start(const nlohmann::json& doc, const std::string& source, WallsSpec& walls,
                std::string& error) {
  const sim::Maze& maze = walls.maze;
  if (const auto it = doc.find("maze_start_cell"); it != doc.end()) {
    double column = 0.0;
    double row = 0.0;
    if (!it->is_array() || it->size() != 2u ||
        !whole_number((*it)[0], maze.width() - 1.0, column) ||
        !whole_number((*it)[1], maze.height() - 1.0, row)) {
      return walls_fail(
          error, source, "maze_start_cell",
          fmt::format("must be [column, row], whole numbers inside the {}x{} maze "
                      "(column 0 to {}, row 0 to {}; row 0 is the south row)",
                      maze.width(), maze.height(), maze.width() - 1u, maze.height() - 1u));
    }
    walls.start_column = static_cast<std::uint32_t>(column);
    walls.start_row = static_cast<std::uint32_t>(row);
  }
  const struct {
    const char* name;
    sim::Side side;
  } sides[] = {{"north", sim::Side::north},
               {"east", sim::Side::east},
               {"south", sim::Side::south},
               {"west", sim::Side::west}};
  const auto it = doc.find("maze_start_heading");
  const std::string heading =
      it == doc.end() ? "out" : (it->is_string() ? it->get<std::string>() : "");
  for (const auto& side : sides) {
    if (heading == side.name) {
      walls.start_heading = side.side;
      return true;
    }
  }
  if (heading != "out") {
    return walls_fail(error, source, "maze_start_heading",
                      "must be \"north\", \"east\", \"south\", \"west\" or \"out\" (the start "
                      "cell's first open side in that order)");
  }
  for (const auto& side : sides) {
    if (!maze.has_wall(walls.start_column, walls.start_row, side.side)) {
      walls.start_heading = side.side;
      return true;
    }
  }
  return walls_fail(error, source, "maze_start_cell",
                    fmt::format("cell ({}, {}) is walled on all four sides: no way out to face "
                                "(give maze_start_heading)",
                                walls.start_column, walls.start_row));
}

// A mount further from the robot's centre than a cell's wall faces would start inside a wall.
constexpr double mount_max_radius_mm = 0.5 * sim::cell_pitch_mm - 0.5 * sim::wall_thickness_mm;
constexpr double gain_min = 0.1;
constexpr double gain_max = 10.0;

/// `wall_sensor_layout`: four [x_mm, y_mm, yaw_deg], in the order left front, left diagonal,
/// right diagonal, right front.
bool read_layout(const nlohmann::json& value, const std::string& source, WallsSpec& walls,
                 std::string& error) {
  const std::string why = fmt::format(
      "must be four [x_mm, y_mm, yaw_deg] (left front, left diagonal, right diagonal, right "
      "front; x forward, y left, yaw counter-clockwise from forward, -180 to 180), each mount "
      "within {:g} mm of the robot's centre",
      mount_max_radius_mm);
  if (!value.is_array() || value.size() != sim::WallSensorLayout::count) {
    return walls_fail(error, source, "wall_sensor_layout", why);
  }
  for (std::uint32_t i = 0; i < sim::WallSensorLayout::count; ++i) {
    const nlohmann::json& mount = value[i];
    if (!mount.is_array() || mount.size() != 3u || !mount[0].is_number() || !mount[1].is_number() ||
        !mount[2].is_number()) {
      return walls_fail(error, source, "wall_sensor_layout", why);
    }
    const double x_mm = mount[0].get<double>();
    const double y_mm = mount[1].get<double>();
    const double yaw_deg = mount[2].get<double>();
    if (!(std::hypot(x_mm, y_mm) <= mount_max_radius_mm) || !(std::fabs(yaw_deg) <= 180.0)) {
      return walls_fail(error, source, "wall_sensor_layout",
                        fmt::format("sensor {}: ", i + 1u) + why);
    }
    walls.sensors.sensors[i].mount = {x_mm, y_mm, yaw_deg * std::numbers::pi / 180.0};
  }
  return true;
}

/// `wall_sensor_gains`: four numbers, in the layout's order.
bool read_gains(const nlohmann::json& value, const std::string& source, WallsSpec& walls,
                std::string& error) {
  bool ok = value.is_array() && value.size() == sim::WallSensorLayout::count;
  for (std::uint32_t i = 0; ok && i < sim::WallSensorLayout::count; ++i) {
    ok = value[i].is_number() && value[i].get<double>() >= gain_min &&
         value[i].get<double>() <= gain_max;
    if (ok) {
      walls.sensors.sensors[i].gain = value[i].get<double>();
    }
  }
  if (!ok) {
    return walls_fail(error, source, "wall_sensor_gains",
                      fmt::format("must be four numbers from {:g} to {:g} (left front, left "
                                  "diagonal, right diagonal, right front)",
                                  gain_min, gain_max));
  }
  return true;
}

/// The response keys: each a number, then the physics checked as a whole (sim::check).
bool read_physics(const nlohmann::json& doc, const std::string& source, WallsSpec& walls,
                  std::string& error) {
  sim::SensorPhysics& p = walls.physics;
  const struct {
    const char* key;
    double* value;
    sim::SensorModelError when;
    const char* why;
  } fields[] = {
      {"wall_sensor_k_counts_mm2", &p.k_counts_mm2, sim::SensorModelError::k,
       "must be a number > 0 (counts·mm²: a sensor of gain 1 reads k/d² above ambient)"},
      {"wall_sensor_incidence_power", &p.incidence_power, sim::SensorModelError::incidence,
       "must be a number >= 0 (the power of cos(incidence))"},
      {"wall_sensor_ambient_counts", &p.ambient_counts, sim::SensorModelError::ambient,
       "must be a number of counts from 0 to 4095 (the 12-bit ADC)"},
      {"wall_sensor_noise_counts", &p.noise_sigma_counts, sim::SensorModelError::noise,
       "must be a number >= 0 (σ of each conversion, counts)"},
      {"wall_sensor_range_mm", &p.range_mm, sim::SensorModelError::range,
       "must be a number > 0 (mm; no reflection is seen beyond)"},
      {"wall_reflectivity_spread", &p.reflectivity_spread, sim::SensorModelError::reflectivity,
       "must be a number from 0 to 0.5 (each wall's reflectivity is uniform in 1 ± this)"},
  };
  for (const auto& field : fields) {
    const auto it = doc.find(field.key);
    if (it == doc.end()) {
      continue;
    }
    if (!it->is_number()) {
      return walls_fail(error, source, field.key, field.why);
    }
    *field.value = it->get<double>();
    if (sim::check(p) == field.when) {
      return walls_fail(error, source, field.key, field.why);
    }
  }
  return true;
}

}  // namespace

bool read(const nlohmann::json& doc, const std::string& source, RobotSpec& out,
          std::string& error) {
  WallsSpec walls;
  if (!read_maze(doc, source, out, walls, error)) {
    return false;
  }
  if (!walls.present()) {
    for (const char* key : keys) {
      if (std::string_view(key) != "maze" && doc.contains(key)) {
        return walls_fail(error, source, key,
                          doc.contains("maze")
                              ? "needs a maze (\"maze\" is \"none\")"
                              : "needs a maze, and this robot has none: it does not fit one "
                                "(wheelbase_mm + wheel_diameter_mm above " +
                                    fmt::format("{:g}", maze_clear_width_mm) + " mm)");
      }
    }
    out.walls = walls;
    return true;
  }
  if (const auto it = doc.find("wall_sensor_seed"); it != doc.end()) {
    double seed = 0.0;
    if (!whole_number(*it, 9007199254740992.0, seed)) {
      return walls_fail(error, source, "wall_sensor_seed", "must be a whole number from 0 to 2^53");
    }
    walls.seed = static_cast<std::uint64_t>(seed);
  }
  if (!read_start(doc, source, walls, error) || !read_physics(doc, source, walls, error)) {
    return false;
  }
  if (const auto it = doc.find("wall_sensor_layout");
      it != doc.end() && !read_layout(*it, source, walls, error)) {
    return false;
  }
  if (const auto it = doc.find("wall_sensor_gains"); it == doc.end()) {
    walls.sensors =
        sim::with_random_gains(walls.sensors, default_wall_sensor_gain_spread, walls.seed);
  } else if (!read_gains(*it, source, walls, error)) {
    return false;
  }
  out.walls = walls;
  return true;
}

}  // namespace robot_file_walls

}  // namespace odocal::host
