#include "odocal/sim/wall_sensor_model.hpp"

#include <cmath>

namespace odocal::sim {

namespace {

// The reflectivities' own derivation index space, apart from any sensor's noise stream.
constexpr std::uint64_t reflectivity_stream = 0x5245464Cu;  // "REFL"

bool finite_positive(double value) {
  return std::isfinite(value) && value > 0.0;
}

}  // namespace

SensorModelError check(const SensorPhysics& physics) {
  if (!finite_positive(physics.k_counts_mm2)) {
    return SensorModelError::k;
  }
  if (!std::isfinite(physics.incidence_power) || physics.incidence_power < 0.0) {
    return SensorModelError::incidence;
  }
  if (!std::isfinite(physics.ambient_counts) || physics.ambient_counts < 0.0 ||
      physics.ambient_counts > hal::WallSensor::full_scale_counts) {
    return SensorModelError::ambient;
  }
  if (!std::isfinite(physics.noise_sigma_counts) || physics.noise_sigma_counts < 0.0) {
    return SensorModelError::noise;
  }
  if (!finite_positive(physics.range_mm)) {
    return SensorModelError::range;
  }
  if (!(physics.reflectivity_spread >= 0.0 && physics.reflectivity_spread <= 0.5)) {
    return SensorModelError::reflectivity;
  }
  return SensorModelError::none;
}

SensorModelError check(const WallSensorSpec& spec) {
  if (!finite_positive(spec.gain)) {
    return SensorModelError::gain;
  }
  if (!std::isfinite(spec.mount.x_mm) || !std::isfinite(spec.mount.y_mm) ||
      !std::isfinite(spec.mount.yaw_rad)) {
    return SensorModelError::mount;
  }
  return SensorModelError::none;
}

WallSensorLayout with_random_gains(const WallSensorLayout& layout, double spread,
                                   std::uint64_t seed) {
  WallSensorLayout out = layout;
  Random random(seed);
  for (WallSensorSpec& spec : out.sensors) {
    spec.gain = random.uniform(1.0 - spread, 1.0 + spread);
  }
  return out;
}

double SensorScene::reflectivity(std::uint32_t surface) const {
  // One draw per surface from a generator derived from (seed, surface): no table, and the same
  // surface reflects the same whichever sensor sees it first.
  Random draw = Random::derive(wall_seed_ ^ reflectivity_stream, surface);
  const double spread = physics_.reflectivity_spread;
  return draw.uniform(1.0 - spread, 1.0 + spread);
}

RayHit SensorScene::look(const SensorMount& mount, const MazePose& robot) const {
  const double c = std::cos(robot.theta_rad);
  const double s = std::sin(robot.theta_rad);
  const double x = robot.x_mm + c * mount.x_mm - s * mount.y_mm;
  const double y = robot.y_mm + s * mount.x_mm + c * mount.y_mm;
  return maze_.cast(x, y, robot.theta_rad + mount.yaw_rad, physics_.range_mm);
}

double SensorScene::lit_counts(const WallSensorSpec& spec, const MazePose& robot) const {
  const RayHit hit = look(spec.mount, robot);
  if (hit.kind == SurfaceKind::none) {
    return 0.0;
  }
  // A sensor against the wall sees more than the ADC can hold: stand it off by a tenth of a mm.
  const double d = hit.distance_mm > 0.1 ? hit.distance_mm : 0.1;
  const double falloff = physics_.k_counts_mm2 / (d * d);
  const double tilt = std::pow(std::cos(hit.incidence_rad), physics_.incidence_power);
  return spec.gain * reflectivity(hit.surface) * falloff * tilt;
}

std::uint16_t SensorScene::convert(const WallSensorSpec& spec, const MazePose& robot,
                                   bool emitter_on, Random& noise) const {
  double counts = physics_.ambient_counts + noise.normal(physics_.noise_sigma_counts);
  if (emitter_on) {
    counts += lit_counts(spec, robot);
  }
  constexpr double full_scale = hal::WallSensor::full_scale_counts;
  if (!(counts > 0.0)) {
    return 0u;
  }
  if (counts >= full_scale) {
    return hal::WallSensor::full_scale_counts;
  }
  return static_cast<std::uint16_t>(std::lround(counts));
}

MazePose world_to_maze(const WorldPose& world, const MazePose& origin) {
  const double c = std::cos(origin.theta_rad);
  const double s = std::sin(origin.theta_rad);
  const double x_mm = world.x_m * 1000.0;
  const double y_mm = world.y_m * 1000.0;
  return MazePose{origin.x_mm + c * x_mm - s * y_mm, origin.y_mm + s * x_mm + c * y_mm,
                  origin.theta_rad + world.theta_rad};
}

MazePose PlantInMaze::do_pose_in_maze() const {
  return world_to_maze(plant_.pose(), origin_);
}

}  // namespace odocal::sim
