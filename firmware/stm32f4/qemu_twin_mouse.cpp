// The QEMU mouse twin (odocal-fw-qemu-mouse): the usual mouse (sim/usual_mouse.hpp) standing in
// the practice maze's start cell, cell (0, 0) facing north, with the usual four wall sensors. The
// sensors are the simulator's own model (sim::SimWallSensor: odocal-sim's response, gain spread,
// ambient, noise and wall reflectivities), read by the console's `walls` through hal::WallSensor
// as a robot's ADC backend is. Tell the firmware the mouse's
// nominal size first (`set wheel_diameter_mm 32`, `set wheelbase_mm 76`): docs/maze.md.

#include <numbers>

#include "built_once.hpp"
#include "odocal/hal/critical_section.hpp"
#include "odocal/hal/stm32f4/interrupts.hpp"
#include "odocal/sim/maze.hpp"
#include "odocal/sim/usual_mouse.hpp"
#include "odocal/sim/wall_sensor_model.hpp"
#include "qemu_twin.hpp"

namespace odocal::firmware {
namespace {

/// Gains, wall reflectivities and each sensor's noise come from this seed (every boot the same).
constexpr std::uint64_t sensor_seed = 1u;

/// The plant's true pose in the maze: the plant advances in an interrupt (board_qemu.cpp) while
/// the console reads the sensors from the main loop, so its pose is copied with interrupts masked
/// (PRIMASK saved and restored: nesting inside the application's own critical sections is safe),
/// and put into the maze outside.
class GuardedPose final : public sim::PoseSource {
 public:
  GuardedPose(const sim::Plant& plant, const sim::MazePose& origin)
      : plant_(plant), origin_(origin) {}

 private:
  [[nodiscard]] sim::MazePose do_pose_in_maze() const override {
    sim::WorldPose world;
    {
      const hal::CriticalGuard guard(critical_);
      world = plant_.pose();
    }
    return sim::world_to_maze(world, origin_);
  }
  const sim::Plant& plant_;
  sim::MazePose origin_;
  mutable hal::stm32f4::InterruptCriticalSection critical_;
};

/// What the sensors look at, built once at start-up.
struct MazeWorld {
  MazeWorld(const sim::Plant& plant, const sim::MazePose& start)
      : scene(maze, sim::SensorPhysics{}, sensor_seed), pose(plant, start) {}
  sim::Maze maze = sim::practice_maze();
  sim::SensorScene scene;
  GuardedPose pose;
};

BuiltOnce<MazeWorld> world_storage;
BuiltOnce<std::array<sim::SimWallSensor, console::wall_sensor_slots>> sensor_storage;

}  // namespace

const bool twin_has_wall_sensors = true;
const char* const twin_name = "qemu-mouse";

sim::RobotModel twin_robot_model() {
  return sim::usual_mouse_model();
}

std::array<hal::WallSensor*, console::wall_sensor_slots> twin_wall_sensors(
    const sim::Plant& plant) {
  const MazeWorld& world =
      world_storage.make(plant, sim::Maze::cell_centre(0u, 0u, 0.5 * std::numbers::pi));
  const sim::WallSensorLayout layout = sim::with_random_gains(
      sim::WallSensorLayout{}, sim::usual_wall_sensor_gain_spread, sensor_seed);
  auto& sensors = sensor_storage.make(std::array<sim::SimWallSensor, console::wall_sensor_slots>{{
      {world.scene, world.pose, layout.sensors[0], sensor_seed + 1u},
      {world.scene, world.pose, layout.sensors[1], sensor_seed + 2u},
      {world.scene, world.pose, layout.sensors[2], sensor_seed + 3u},
      {world.scene, world.pose, layout.sensors[3], sensor_seed + 4u},
  }});
  return {&sensors[0], &sensors[1], &sensors[2], &sensors[3]};
}

}  // namespace odocal::firmware
