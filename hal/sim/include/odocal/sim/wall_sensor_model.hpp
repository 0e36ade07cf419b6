#pragma once
/// @file
/// The simulated wall sensors: where a maze robot's reflective sensors sit, how much light comes
/// back from a wall (falling with the square of the distance and with the angle of incidence,
/// scaled by the sensor's gain and the wall's reflectivity), ambient light, noise and the 12-bit
/// ADC's limits; and the `sim` backend of hal::WallSensor that reads them.
///
/// Fixed-size, no heap, no exceptions, no I/O (like the plant). Deterministic per seed.

#include <array>
#include <cstdint>
#include <numbers>

#include "odocal/hal/wall_sensor.hpp"
#include "odocal/sim/maze.hpp"
#include "odocal/sim/plant.hpp"
#include "odocal/sim/random.hpp"

namespace odocal::sim {

/// Where a sensor sits on the robot and where it looks, in the robot's frame (origin between the
/// wheels' contact points, x forward, y left): mm, and rad counter-clockwise from forward.
struct SensorMount {
  double x_mm = 0.0;
  double y_mm = 0.0;
  double yaw_rad = 0.0;
};

/// One sensor: its mount and its own gain (emitter power times receiver sensitivity; real sensors
/// of one robot differ by about ±20 %).
struct WallSensorSpec {
  SensorMount mount{};
  double gain = 1.0;
};

/// The response every sensor of a robot shares. Above ambient, a sensor whose axis meets a face at
/// distance d (mm) and incidence φ reads
///   lit = gain · reflectivity · k / d² · cos(φ)^p
/// (a diffuse wall lit by a small emitter: intensity falling with the square of the distance, and
/// with the cosine of the angle between the beam and the face's normal). The ADC converts
/// ambient + (emitter on: lit) + N(0, σ), rounded, clamped to [0, 4095]. Beyond `range_mm` (or
/// with no face ahead) the sensor sees no reflection: ambient + noise.
struct SensorPhysics {
  /// k, counts·mm²: a sensor of gain 1 reads about 3000 counts above ambient 45 mm from a wall.
  double k_counts_mm2 = 6.0e6;
  double incidence_power = 1.0;       ///< p
  double ambient_counts = 100.0;      ///< the receiver's reading with the emitter off
  double noise_sigma_counts = 6.0;    ///< σ of each conversion
  double range_mm = 400.0;            ///< no reflection seen beyond
  double reflectivity_spread = 0.05;  ///< each wall's or post's factor is uniform in 1 ± this
};

/// What is wrong with a physics or a spec, if anything (the first problem found).
enum class SensorModelError : std::uint8_t {
  none,
  k,             ///< not finite or not > 0
  incidence,     ///< power not finite or < 0
  ambient,       ///< not finite, < 0 or above full scale
  noise,         ///< not finite or < 0
  range,         ///< not finite or not > 0
  reflectivity,  ///< spread not in [0, 0.5]
  gain,          ///< a sensor's gain not finite or not > 0
  mount,         ///< a mount coordinate not finite
};

[[nodiscard]] SensorModelError check(const SensorPhysics& physics);
[[nodiscard]] SensorModelError check(const WallSensorSpec& spec);

/// The usual mouse's diagonal sensors look 50° off its heading (builders use 45° to 60°).
inline constexpr double usual_diagonal_yaw_rad = 50.0 * std::numbers::pi / 180.0;

/// The usual maze robot's four sensors, by place.
enum class SensorPlace : std::uint8_t { left_front, left_diagonal, right_diagonal, right_front };

/// The sensors a robot carries: by default the usual mouse, two looking ahead from near the front
/// corners and two diagonals at ±50°, all of gain 1.
struct WallSensorLayout {
  static constexpr std::uint32_t count = 4u;
  std::array<WallSensorSpec, count> sensors{{
      {{40.0, 30.0, 0.0}, 1.0},                       // left front: looks ahead
      {{35.0, 20.0, usual_diagonal_yaw_rad}, 1.0},    // left diagonal: 50° to the left
      {{35.0, -20.0, -usual_diagonal_yaw_rad}, 1.0},  // right diagonal
      {{40.0, -30.0, 0.0}, 1.0},                      // right front
  }};
  [[nodiscard]] const WallSensorSpec& at(SensorPlace place) const {
    return sensors[static_cast<std::uint32_t>(place)];
  }
};

/// Draws each sensor's gain uniformly in 1 ± `spread` (e.g. 0.2) from `seed`, keeping the mounts.
[[nodiscard]] WallSensorLayout with_random_gains(const WallSensorLayout& layout, double spread,
                                                 std::uint64_t seed);

/// The sensors' world: one maze, one physics, and the walls' reflectivities drawn from a seed.
class SensorScene {
 public:
  /// @param maze kept by reference: it must outlive the scene; @param wall_seed draws every wall's
  ///        and post's reflectivity (the same surface always reflects the same).
  SensorScene(const Maze& maze, const SensorPhysics& physics, std::uint64_t wall_seed)
      : maze_(maze), physics_(physics), wall_seed_(wall_seed) {}

  [[nodiscard]] const Maze& maze() const { return maze_; }
  [[nodiscard]] const SensorPhysics& physics() const { return physics_; }

  /// The reflectivity factor of surface `surface` (RayHit::surface): in 1 ± the spread.
  [[nodiscard]] double reflectivity(std::uint32_t surface) const;

  /// Where the sensor's axis meets the maze from `robot`'s pose (mm, maze frame), up to the range.
  [[nodiscard]] RayHit look(const SensorMount& mount, const MazePose& robot) const;

  /// The noiseless light above ambient, counts (not rounded, not clamped): 0 with nothing in range.
  [[nodiscard]] double lit_counts(const WallSensorSpec& spec, const MazePose& robot) const;

  /// One conversion: ambient + (emitter on: lit) + N(0, σ) drawn from `noise`, rounded and clamped
  /// to [0, hal::WallSensor::full_scale_counts].
  [[nodiscard]] std::uint16_t convert(const WallSensorSpec& spec, const MazePose& robot,
                                      bool emitter_on, Random& noise) const;

 private:
  const Maze& maze_;
  SensorPhysics physics_;
  std::uint64_t wall_seed_;
};

/// Where the robot is in the maze, for the simulated sensors.
class PoseSource {
 public:
  /// The true pose in the maze frame, mm and rad.
  [[nodiscard]] MazePose pose_in_maze() const { return do_pose_in_maze(); }

 protected:
  ~PoseSource() = default;

 private:
  [[nodiscard]] virtual MazePose do_pose_in_maze() const = 0;
};

/// A pose in the plant's world (m, rad) put into the maze (mm, rad), the world's origin lying at
/// `origin` in the maze frame.
[[nodiscard]] MazePose world_to_maze(const WorldPose& world, const MazePose& origin);

/// The plant's true pose put into the maze: the plant's world origin (where `Plant::place` put it
/// down with the default pose) lies at `origin` in the maze frame.
class PlantInMaze final : public PoseSource {
 public:
  PlantInMaze(const Plant& plant, const MazePose& origin) : plant_(plant), origin_(origin) {}

 private:
  [[nodiscard]] MazePose do_pose_in_maze() const override;
  const Plant& plant_;
  MazePose origin_;
};

/// A pose set by hand (tests, a robot standing still).
class FixedPose final : public PoseSource {
 public:
  explicit FixedPose(const MazePose& pose = MazePose{}) : pose_(pose) {}
  void set(const MazePose& pose) { pose_ = pose; }

 private:
  [[nodiscard]] MazePose do_pose_in_maze() const override { return pose_; }
  MazePose pose_;
};

/// The `sim` backend of one wall sensor: each conversion looks from the pose source's current
/// pose, with the emitter as the firmware left it. The settle wait returns at once (the
/// simulator's time stands still inside a tick).
class SimWallSensor final : public hal::WallSensor {
 public:
  /// @param scene and @param pose are kept by reference and must outlive the sensor;
  /// @param noise_seed seeds this sensor's own noise stream.
  SimWallSensor(const SensorScene& scene, const PoseSource& pose, const WallSensorSpec& spec,
                std::uint64_t noise_seed)
      : scene_(scene), pose_(pose), spec_(spec), noise_(noise_seed) {}

  [[nodiscard]] bool emitter_on() const { return emitter_on_; }
  [[nodiscard]] const WallSensorSpec& spec() const { return spec_; }
  /// How many settle waits the firmware asked for.
  [[nodiscard]] std::uint32_t settles() const { return settles_; }

  /// The settle time the backend reports, µs (a typical infrared phototransistor's).
  static constexpr std::uint32_t default_settle_us = 20u;

 private:
  void do_set_emitter(bool on) override { emitter_on_ = on; }
  std::uint16_t do_read_counts() override {
    return scene_.convert(spec_, pose_.pose_in_maze(), emitter_on_, noise_);
  }
  std::uint32_t do_settle_us() const override { return default_settle_us; }
  void do_wait_settle() override { ++settles_; }

  const SensorScene& scene_;
  const PoseSource& pose_;
  WallSensorSpec spec_;
  Random noise_;
  bool emitter_on_ = false;
  std::uint32_t settles_ = 0u;
};

}  // namespace odocal::sim
