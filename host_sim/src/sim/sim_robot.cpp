#include "odocal/host/sim_robot.hpp"

#include <chrono>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace odocal::host {

RobotSpec default_robot() {
  RobotSpec spec;
  spec.truth.left_diameter_m = 0.05991;
  spec.truth.right_diameter_m = 0.06003;
  spec.truth.wheelbase_m = 0.1515;
  spec.truth.counts_per_rev = 1440u;
  return spec;
}

namespace {

/// What a robot-file key sets, and the number it holds.
bool set_key(const std::string& key, double value, RobotSpec& spec) {
  if (key == "wheel_diameter_mm") {
    spec.nominal.wheel_diameter_mm = static_cast<float>(value);
  } else if (key == "wheelbase_mm") {
    spec.nominal.wheelbase_mm = static_cast<float>(value);
  } else if (key == "counts_per_rev") {
    spec.nominal.counts_per_rev = static_cast<float>(value);
    spec.truth.counts_per_rev =
        value >= 0.0 && value < 4.0e9 ? static_cast<std::uint32_t>(value) : 0u;
  } else if (key == "true_left_diameter_mm") {
    spec.truth.left_diameter_m = value * 1e-3;
  } else if (key == "true_right_diameter_mm") {
    spec.truth.right_diameter_m = value * 1e-3;
  } else if (key == "true_wheelbase_mm") {
    spec.truth.wheelbase_m = value * 1e-3;
  } else if (key == "slip_sigma") {
    spec.truth.slip_sigma = value;
  } else if (key == "bump_height_mm") {
    spec.truth.bump_height_m = value * 1e-3;
  } else if (key == "bump_spacing_mm") {
    spec.truth.bump_spacing_m = value * 1e-3;
  } else if (key == "measure_sigma_mm") {
    spec.truth.measure_sigma_m = value * 1e-3;
    // The sonar calibrator's ±0.4° goes with its ±2 mm: scale the heading noise alike.
    spec.truth.measure_heading_sigma_rad = 0.4 * 3.14159265358979323846 / 180.0 * value / 2.0;
  } else {
    return false;
  }
  return true;
}

bool fail(std::string& error, const std::string& source, const std::string& key,
          const std::string& why) {
  error = source + ": " + key + ": " + why;
  return false;
}

}  // namespace

bool parse_robot(const std::string& text, const std::string& source, RobotSpec& spec,
                 std::string& error) {
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    error = source + ": not valid JSON (" + e.what() + ")";
    return false;
  }
  if (!doc.is_object()) {
    error = source + ": the robot file must be one flat JSON object";
    return false;
  }
  RobotSpec out = default_robot();
  for (auto it = doc.begin(); it != doc.end(); ++it) {
    const std::string& key = it.key();
    if (!it.value().is_number()) {
      RobotSpec probe;
      if (!set_key(key, 1.0, probe)) {
        return fail(error, source, key, "unknown key");
      }
      return fail(error, source, key, "must be a number");
    }
    const double value = it.value().get<double>();
    if (!std::isfinite(value)) {
      return fail(error, source, key, "must be finite");
    }
    if (!set_key(key, value, out)) {
      return fail(error, source, key, "unknown key");
    }
  }
  // Geometry the firmware is told.
  const drive::DriveConfig& n = out.nominal;
  if (!(n.wheel_diameter_mm > 0.0f)) {
    return fail(error, source, "wheel_diameter_mm", "must be > 0");
  }
  if (!(n.wheelbase_mm > n.wheel_diameter_mm)) {
    return fail(error, source, "wheelbase_mm", "must be larger than the wheel diameter");
  }
  if (!(n.counts_per_rev >= 4.0f) || std::floor(n.counts_per_rev) != n.counts_per_rev ||
      out.truth.counts_per_rev % 4u != 0u) {
    return fail(error, source, "counts_per_rev", "must be a positive whole multiple of 4");
  }
  if (!drive::valid(n)) {
    return fail(error, source, "wheel_diameter_mm",
                "outside the firmware's range (5-1000 mm, wheelbase 10-5000 mm)");
  }
  // The real robot.
  const sim::RobotModel& t = out.truth;
  if (!(t.left_diameter_m > 0.0)) {
    return fail(error, source, "true_left_diameter_mm", "must be > 0");
  }
  if (!(t.right_diameter_m > 0.0)) {
    return fail(error, source, "true_right_diameter_mm", "must be > 0");
  }
  if (!(t.wheelbase_m > std::fmax(t.left_diameter_m, t.right_diameter_m))) {
    return fail(error, source, "true_wheelbase_mm", "must be larger than a wheel's diameter");
  }
  if (!(t.slip_sigma >= 0.0 && t.slip_sigma < 0.5)) {
    return fail(error, source, "slip_sigma", "must be in [0, 0.5)");
  }
  if (!(t.bump_height_m >= 0.0) ||
      t.bump_height_m >= 0.5 * std::fmin(t.left_diameter_m, t.right_diameter_m)) {
    return fail(error, source, "bump_height_mm", "must be >= 0 and below the wheel radius");
  }
  if (!(t.bump_spacing_m > 0.0)) {
    return fail(error, source, "bump_spacing_mm", "must be > 0");
  }
  if (!(t.measure_sigma_m >= 0.0)) {
    return fail(error, source, "measure_sigma_mm", "must be >= 0");
  }
  if (sim::check(t) != sim::ModelError::none) {
    return fail(error, source, "robot", sim::to_string(sim::check(t)));
  }
  spec = out;
  return true;
}

bool load_robot_file(const std::string& path, RobotSpec& spec, std::string& error) {
  std::ifstream in(path);
  if (!in) {
    error = path + ": cannot read";
    return false;
  }
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_robot(buffer.str(), path, spec, error);
}

TrueErrors true_errors(const RobotSpec& spec) {
  TrueErrors e;
  const sim::RobotModel& t = spec.truth;
  e.e_d = t.right_diameter_m / t.left_diameter_m;
  const double mean_d_mm = 0.5 * (t.left_diameter_m + t.right_diameter_m) * 1e3;
  e.e_b = t.wheelbase_m * 1e3 / static_cast<double>(spec.nominal.wheelbase_mm) *
          static_cast<double>(spec.nominal.wheel_diameter_mm) / mean_d_mm;
  return e;
}

SimulatedRobot::SimulatedRobot(const RobotSpec& spec, std::uint64_t seed)
    : spec_(spec),
      plant_(spec.truth, seed),
      loop_(drive::MotorChannel{plant_.left().pwm(), plant_.left().forward()},
            drive::MotorChannel{plant_.right().pwm(), plant_.right().forward()},
            plant_.critical_section(), spec.nominal),
      left_wiring_(plant_.left().channel_a(), plant_.left().channel_b(), plant_.clock(),
                   loop_.left_decoder()),
      right_wiring_(plant_.right().channel_a(), plant_.right().channel_b(), plant_.clock(),
                    loop_.right_decoder()) {
  left_wiring_.attach();
  right_wiring_.attach();
  const double hz = static_cast<double>(spec.nominal.control_hz);
  period_ns_ = static_cast<std::uint64_t>(std::llround(1e9 / hz));
  next_tick_ns_ = 0u;
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
  const double rad_per_count = 6.283185307179586476925 / spec_.nominal.counts_per_rev;
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
    const drive::LoopStatus status = loop_.status();
    if (status.mode != drive::Mode::path) {
      completed = status.mode == drive::Mode::idle && status.faults == drive::fault_none;
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
