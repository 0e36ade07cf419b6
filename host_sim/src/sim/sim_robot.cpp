// The simulated robot: the firmware's control loop on the hal/sim plant, run tick by tick.

#include "odocal/host/sim_robot.hpp"

#include <chrono>
#include <cmath>
#include <numbers>

namespace odocal::host {

namespace {
// Salts the robot's seed for the wall sensors' noise ("wallnois"): streams apart from the plant's.
constexpr std::uint64_t wall_noise_stream = 0x77616c6c6e6f6973u;
}  // namespace

sim::SimWallSensor SimulatedRobot::make_wall_sensor(std::uint32_t index, std::uint64_t seed) const {
  const std::uint64_t noise_seed = sim::Random::derive(seed ^ wall_noise_stream, index).next_u64();
  return sim::SimWallSensor(wall_scene_, plant_in_maze_, spec_.walls.sensors.sensors[index],
                            noise_seed);
}

SimulatedRobot::SimulatedRobot(const RobotSpec& spec, std::uint64_t seed)
    : spec_(spec),
      plant_(spec.truth, seed),
      reversed_direction_(spec.wiring == WiringFault::right_motor_reversed
                              ? plant_.right().forward()
                              : plant_.left().forward()),
      loop_(motor_connector(0), motor_connector(1), plant_.critical_section(), spec.nominal),
      left_wiring_(encoder_line(0, true), encoder_line(0, false), plant_.clock(),
                   loop_.left_decoder()),
      right_wiring_(encoder_line(1, true), encoder_line(1, false), plant_.clock(),
                    loop_.right_decoder()),
      wall_scene_(spec_.walls.maze, spec_.walls.physics, spec_.walls.seed),
      plant_in_maze_(plant_, spec_.walls.start_pose()),
      wall_sensors_{{make_wall_sensor(0u, seed), make_wall_sensor(1u, seed),
                     make_wall_sensor(2u, seed), make_wall_sensor(3u, seed)}} {
  left_wiring_.attach();
  right_wiring_.attach();
  fault_pending_ =
      spec.encoder_fault.wheel >= 0 && spec.encoder_fault.fault != sim::ChannelFault::none;
  const double hz = static_cast<double>(spec.nominal.control_hz);
  period_ns_ = static_cast<std::uint64_t>(std::llround(1e9 / hz));
  next_tick_ns_ = 0u;
}

drive::MotorChannel SimulatedRobot::motor_connector(int side) {
  const WiringFault wiring = spec_.wiring;
  const bool to_left = (side == 0) != (wiring == WiringFault::motors_swapped);
  sim::Wheel& wheel = to_left ? plant_.left() : plant_.right();
  const bool reversed =
      wiring == (side == 0 ? WiringFault::left_motor_reversed : WiringFault::right_motor_reversed);
  return drive::MotorChannel{
      wheel.pwm(),
      reversed ? static_cast<hal::DigitalOutput&>(reversed_direction_) : wheel.forward()};
}

sim::EncoderLine& SimulatedRobot::encoder_line(int side, bool a) {
  const WiringFault wiring = spec_.wiring;
  const bool from_left = (side == 0) != (wiring == WiringFault::encoders_swapped);
  sim::Wheel& wheel = from_left ? plant_.left() : plant_.right();
  // A reversed encoder has its A and B lines exchanged: it counts backwards.
  const bool reversed = wiring == (side == 0 ? WiringFault::left_encoder_reversed
                                             : WiringFault::right_encoder_reversed);
  return a != reversed ? wheel.channel_a() : wheel.channel_b();
}

SimulatedRobot::~SimulatedRobot() {
  left_wiring_.detach();
  right_wiring_.detach();
}

bool SimulatedRobot::configure(const drive::DriveConfig& config) {
  if (!loop_.configure(config)) {
    return false;
  }
  period_ns_ =
      static_cast<std::uint64_t>(std::llround(1e9 / static_cast<double>(config.control_hz)));
  return true;
}

void SimulatedRobot::follow_control_rate() {
  const double hz = static_cast<double>(loop_.config().control_hz);
  if (hz > 0.0) {
    period_ns_ = static_cast<std::uint64_t>(std::llround(1e9 / hz));
  }
}

void SimulatedRobot::tick_once() {
  plant_.advance_to_ns(next_tick_ns_);
  if (fault_pending_ && simulated_s() >= spec_.encoder_fault.after_s) {
    fault_pending_ = false;
    (spec_.encoder_fault.wheel == 0 ? left_wiring_ : right_wiring_)
        .set_fault(spec_.encoder_fault.fault);
  }
  if (measure_tick_time_) {
    const auto start = std::chrono::steady_clock::now();
    loop_.tick(plant_.clock().now_us());
    const std::chrono::duration<float, std::micro> took = std::chrono::steady_clock::now() - start;
    loop_.note_tick_duration_us(took.count());
  } else {
    loop_.tick(plant_.clock().now_us());
  }
  next_tick_ns_ += period_ns_;
}

void SimulatedRobot::follow_odometry_frame() {
  const std::uint32_t resets = loop_.status().pose_resets;
  if (resets != pose_resets_) {
    pose_resets_ = resets;
    frame_ = plant_.pose();
  }
}

sim::WorldPose SimulatedRobot::measure_in_odometry_frame() {
  const sim::WorldPose world = plant_.measure();
  const double dx = world.x_m - frame_.x_m;
  const double dy = world.y_m - frame_.y_m;
  const double c = std::cos(frame_.theta_rad);
  const double s = std::sin(frame_.theta_rad);
  sim::WorldPose local;
  local.x_m = c * dx + s * dy;
  local.y_m = -s * dx + c * dy;
  local.theta_rad = std::remainder(world.theta_rad - frame_.theta_rad, 2.0 * std::numbers::pi);
  return local;
}

void SimulatedRobot::run_until_ns(std::uint64_t t_ns) {
  while (next_tick_ns_ <= t_ns) {
    tick_once();
  }
  plant_.advance_to_ns(t_ns);
}

RunOutcome SimulatedRobot::run_path(const drive::Path& path, double timeout_s, const TraceFn& trace,
                                    std::uint32_t trace_period_ms) {
  RunOutcome out;
  // A new run: robot put down at the origin, faults acknowledged, odometry zeroed.
  loop_.stop();
  tick_once();
  plant_.place();
  loop_.reset_pose();
  const double rad_per_count = 2.0 * std::numbers::pi / spec_.nominal.counts_per_rev;
  const std::int64_t left0 = plant_.left().encoder_count();
  const std::int64_t right0 = plant_.right().encoder_count();
  if (!loop_.run(path)) {
    return out;
  }
  const std::uint64_t start_ns = next_tick_ns_;
  const auto limit_ns = start_ns + static_cast<std::uint64_t>(timeout_s * 1e9);
  const std::uint64_t trace_ns = static_cast<std::uint64_t>(trace_period_ms) * 1000000u;
  std::uint64_t next_trace_ns = start_ns;
  tick_once();
  bool completed = false;
  while (next_tick_ns_ < limit_ns) {
    if (trace && next_tick_ns_ >= next_trace_ns) {
      trace(plant_.pose());
      next_trace_ns += trace_ns;
    }
    // The procedure runs the ticks: between two of them the loop's state is settled, and the
    // mode needs no copy of the whole status under the critical section.
    const drive::Mode mode = loop_.mode_after_tick();
    if (mode != drive::Mode::path) {
      completed = mode == drive::Mode::idle && loop_.faults_after_tick() == drive::fault_none;
      break;
    }
    tick_once();
  }
  out.duration_s = static_cast<double>(next_tick_ns_ - start_ns) * 1e-9;
  // Let the wheels come to rest before the measurement (at most 2 s).
  const std::uint64_t rest_limit = next_tick_ns_ + 2'000'000'000u;
  while (!plant_.at_rest() && next_tick_ns_ < rest_limit) {
    tick_once();
  }
  if (trace) {
    trace(plant_.pose());
  }
  out.completed = completed;
  out.truth = plant_.pose();
  out.measured = plant_.measure();
  out.odometry = loop_.pose();
  out.left_wheel_rad = static_cast<double>(plant_.left().encoder_count() - left0) * rad_per_count;
  out.right_wheel_rad =
      static_cast<double>(plant_.right().encoder_count() - right0) * rad_per_count;
  return out;
}

}  // namespace odocal::host
