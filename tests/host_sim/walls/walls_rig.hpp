#pragma once
// The simulator's truth for the walls' tests: a maze, a SensorScene, four SimWallSensors read
// through hal::WallSensor::read_lit_counts at poses set by hand.

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <vector>

#include "odocal/host/walls.hpp"
#include "odocal/sim/maze.hpp"
#include "odocal/sim/wall_sensor_model.hpp"

namespace odocal::host::walls::rig {

inline constexpr double pi = std::numbers::pi;
inline constexpr double degrees = pi / 180.0;

/// The usual mouse with gains drawn in 1 ± 20 %, the default physics (σ = 6 counts per
/// conversion, reflectivity 1 ± 5 %), walls and noise from `seed`.
class Rig {
 public:
  Rig(const sim::Maze& maze, std::uint64_t seed, const sim::SensorPhysics& physics = {})
      : maze_(maze),
        scene_(maze_, physics, seed * 7919u + 13u),
        layout_(sim::with_random_gains(sim::WallSensorLayout{}, 0.2, seed)) {
    for (std::size_t i = 0u; i < sensor_count; ++i) {
      sensors_[i] = std::make_unique<sim::SimWallSensor>(scene_, pose_, layout_.sensors[i],
                                                         seed * 104729u + i);
    }
  }

  Rig(const Rig&) = delete;
  Rig& operator=(const Rig&) = delete;

  [[nodiscard]] const sim::SensorScene& scene() const { return scene_; }
  [[nodiscard]] const sim::WallSensorLayout& layout() const { return layout_; }

  /// The four lit readings (ambient taken away, noise σ√2) at `pose`.
  std::array<double, sensor_count> read(const sim::MazePose& pose) {
    pose_.set(pose);
    std::array<double, sensor_count> lit{};
    for (std::size_t i = 0u; i < sensor_count; ++i) {
      lit[i] = sensors_[i]->read_lit_counts();
    }
    return lit;
  }

 private:
  sim::Maze maze_;
  sim::SensorScene scene_;
  sim::WallSensorLayout layout_;
  sim::FixedPose pose_;
  std::array<std::unique_ptr<sim::SimWallSensor>, sensor_count> sensors_;
};

/// A turn in place: the true centre, start heading and radians per turn count.
struct TrueTurn {
  double centre_x_mm = 90.0;
  double centre_y_mm = 90.0;
  double start_heading_rad = pi / 2.0;
  double radians_per_count = 0.0025;
  double turned_rad = 450.0 * degrees;
  double step_rad = 0.5 * degrees;
};

/// Samples of `turn` counter-clockwise (turn counts exact: the wheels do not slip).
inline std::vector<TurnSample> sample_turn(Rig& rig, const TrueTurn& turn) {
  std::vector<TurnSample> samples;
  const auto steps = static_cast<std::size_t>(turn.turned_rad / turn.step_rad);
  for (std::size_t j = 0u; j <= steps; ++j) {
    const double turned = static_cast<double>(j) * turn.step_rad;
    const sim::MazePose pose{turn.centre_x_mm, turn.centre_y_mm, turn.start_heading_rad + turned};
    samples.push_back(TurnSample{turned / turn.radians_per_count, rig.read(pose)});
  }
  return samples;
}

/// A straight run north from (x, y0) with a constant small heading error, the encoders reading
/// `scale` mm per true mm; samples every `step_mm` of true travel. `true_y` gets each sample's
/// true y.
struct TrueRun {
  double x_mm = 90.0;
  double y_start_mm = 90.0;
  double heading_error_rad = 0.0;
  double length_mm = 1000.0;
  double scale = 1.0;
  double step_mm = 0.5;
};

inline std::vector<RunSample> sample_run(Rig& rig, const TrueRun& run,
                                         std::vector<double>& true_y) {
  std::vector<RunSample> samples;
  true_y.clear();
  const auto steps = static_cast<std::size_t>(run.length_mm / run.step_mm);
  for (std::size_t j = 0u; j <= steps; ++j) {
    const double s = static_cast<double>(j) * run.step_mm;
    const double heading = pi / 2.0 + run.heading_error_rad;
    const sim::MazePose pose{run.x_mm + s * std::cos(heading),
                             run.y_start_mm + s * std::sin(heading), heading};
    samples.push_back(RunSample{s * run.scale, rig.read(pose)});
    true_y.push_back(pose.y_mm);
  }
  return samples;
}

/// A 2x10 maze whose west column is a corridor: the perimeter on its west, on its east walls
/// with gaps (rows 2, 4, 5 and 8 open), so that the right diagonal sees walls end and begin.
inline sim::Maze gapped_corridor() {
  sim::Maze maze(2u, 10u);
  for (std::uint32_t row = 0u; row < 10u; ++row) {
    const bool open = row == 2u || row == 4u || row == 5u || row == 8u;
    maze.set_wall(0u, row, sim::Side::east, !open);
  }
  return maze;
}

}  // namespace odocal::host::walls::rig
