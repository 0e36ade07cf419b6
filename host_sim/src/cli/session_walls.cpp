// `odocal session --truth walls`: its flags checked, the robot file a usual mouse's when it says
// nothing of the robot's size, and what the session knows of the maze (session_flags.hpp).

#include <fstream>
#include <string>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "odocal/host/csv.hpp"
#include "odocal/host/robot_file.hpp"
#include "odocal/sim/usual_mouse.hpp"
#include "session_flags.hpp"

namespace odocal::host {
namespace {

/// `{}` under --truth walls (DESIGN: "a usual mouse in a practice maze"): a robot file that says
/// nothing of the robot's size is given a micromouse's (docs/simulation.md, "--truth walls").
const nlohmann::json kUsualMouse = {
    {"wheel_diameter_mm", sim::usual_mouse_wheel_diameter_mm},
    {"wheelbase_mm", sim::usual_mouse_wheelbase_mm},
    {"true_left_diameter_mm", sim::usual_mouse_true_left_diameter_mm},
    {"true_right_diameter_mm", sim::usual_mouse_true_right_diameter_mm},
    {"true_wheelbase_mm", sim::usual_mouse_true_wheelbase_mm}};

}  // namespace

std::string walls_robot_file(const std::string& path, const std::string& out_dir) {
  nlohmann::json doc = nlohmann::json::parse(read_text_file(path), nullptr, false);
  if (!doc.is_object()) {
    return path;  // odocal-sim names what is wrong with it
  }
  for (const auto& [key, value] : kUsualMouse.items()) {
    if (doc.contains(key)) {
      return path;
    }
  }
  doc.update(kUsualMouse);
  const std::string derived = out_dir + "/robot.json";
  std::ofstream out(derived, std::ios::trunc);
  out << doc.dump(2) << "\n";
  if (!out.flush()) {
    throw InputError(derived, 0, "", "cannot write the robot file for odocal-sim");
  }
  return derived;
}

MazeKnowledge maze_knowledge(const WallsFlags& f, const std::string& sim_file) {
  MazeKnowledge k;
  sim::WallSensorLayout layout;
  if (!f.sim_robot.empty()) {
    RobotSpec spec;
    std::string error;
    if (!load_robot_file(sim_file, spec, error)) {
      throw InputError(f.sim_robot, 0, "", error);
    }
    if (!spec.walls.present()) {
      throw InputError(f.sim_robot, 0, "",
                       "--truth walls: this robot stands in no maze (its wheelbase and wheel "
                       "diameter come to more than a corridor's 168 mm, or the file says \"maze\": "
                       "\"none\"); docs/simulation.md");
    }
    k.maze = spec.walls.maze;
    k.start_column = spec.walls.start_column;
    k.start_row = spec.walls.start_row;
    k.start_heading_rad = spec.walls.start_pose().theta_rad;
    layout = spec.walls.sensors;
    k.name = spec.walls.source == MazeSource::file ? spec.walls.maze_file : "the practice maze";
    k.simulator = true;
  } else if (f.maze.empty() || f.maze == "practice") {
    k.maze = sim::practice_maze();
  } else {
    const std::string text = read_text_file(f.maze);
    sim::Maze maze(16u, 16u);
    const sim::MazeTextStatus status = sim::parse_maze_text(text, maze);
    if (!status.ok()) {
      char why[160];
      static_cast<void>(sim::describe(status, why, sizeof why));
      throw InputError(f.maze, 0, "", std::string("--maze: ") + why);
    }
    k.maze = maze;
    k.name = f.maze;
  }
  for (std::size_t i = 0; i < k.mounts.size(); ++i) {
    k.mounts[i] = layout.sensors[i].mount;
  }
  return k;
}

bool check_walls_flags(const WallsFlags& f, Procedure procedure, bool measurements, bool bridge) {
  if (f.truth != "walls") {
    if (!f.maze.empty()) {
      throw InputError("--maze", 0, "", "only with --truth walls");
    }
    return false;
  }
  if (procedure != Procedure::automatic) {
    throw InputError("--truth", 0, "", "walls: only with --procedure auto");
  }
  if (measurements) {
    throw InputError("--measurements", 0, "",
                     "--truth walls takes no tape reading from a file (where its maze cannot give "
                     "the scale it asks for the lines' readings as it drives them); leave "
                     "--measurements out");
  }
  if (bridge) {
    throw InputError("--truth", 0, "",
                     "walls: the robot reads its wall sensors through odocal's console "
                     "(`walls`); ROSArduinoBridge has no such command");
  }
  return true;
}

void add_walls_flags(CLI::App& cmd, std::string& truth, std::string& maze, CLI::Option* port) {
  cmd.add_option("--truth", truth,
                 "what measures the runs: tape (default: you, --measurements, or odocal-sim's "
                 "measure) or walls (auto only: a maze robot measured by its wall sensors in "
                 "its maze, no tape reading; docs/maze.md)")
      ->check(CLI::IsMember({"tape", "walls"}));
  cmd.add_option("--maze", maze,
                 "--truth walls with --port: the maze the robot stands in, `practice` (the "
                 "default) or a maze text file (docs/maze.md); with --sim the robot file's")
      ->needs(port);
}

}  // namespace odocal::host
