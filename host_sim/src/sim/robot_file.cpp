// The robot file (`--robot FILE`): parsing, the ranges it must keep, and the default robot.

#include "odocal/host/robot_file.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "odocal/host/calib_json.hpp"
#include "odocal/host/csv.hpp"
#include "odocal/params/param_table.hpp"
#include "robot_file_walls.hpp"

namespace odocal::host {

const char* to_string(WiringFault fault) {
  switch (fault) {
    case WiringFault::left_motor_reversed:
      return "left_motor_reversed";
    case WiringFault::right_motor_reversed:
      return "right_motor_reversed";
    case WiringFault::left_encoder_reversed:
      return "left_encoder_reversed";
    case WiringFault::right_encoder_reversed:
      return "right_encoder_reversed";
    case WiringFault::encoders_swapped:
      return "encoders_swapped";
    case WiringFault::motors_swapped:
      return "motors_swapped";
    case WiringFault::ok:
      break;
  }
  return "ok";
}

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
  } else if (key == "true_wheelbase_arc_mm") {
    spec.truth.wheelbase_arc_m = value * 1e-3;
  } else if (key == "slip_sigma") {
    spec.truth.slip_sigma = value;
  } else if (key == "bump_height_mm") {
    spec.truth.bump_height_m = value * 1e-3;
  } else if (key == "bump_spacing_mm") {
    spec.truth.bump_spacing_m = value * 1e-3;
  } else if (key == "measure_sigma_mm") {
    spec.truth.measure_sigma_m = value * 1e-3;
    // The sonar calibrator's ±0.4° goes with its ±2 mm: scale the heading noise alike.
    spec.truth.measure_heading_sigma_rad = 0.4 * std::numbers::pi / 180.0 * value / 2.0;
  } else {
    return false;
  }
  return true;
}

// "left_dead" -> the left wheel's channel A dead; "none" -> no fault.
bool parse_encoder_fault(const std::string& text, RobotSpec& spec) {
  const struct {
    const char* name;
    int wheel;
    sim::ChannelFault fault;
  } kinds[] = {{"none", -1, sim::ChannelFault::none},
               {"left_dead", 0, sim::ChannelFault::dead},
               {"right_dead", 1, sim::ChannelFault::dead},
               {"left_noisy", 0, sim::ChannelFault::noisy},
               {"right_noisy", 1, sim::ChannelFault::noisy}};
  for (const auto& kind : kinds) {
    if (text == kind.name) {
      spec.encoder_fault.wheel = kind.wheel;
      spec.encoder_fault.fault = kind.fault;
      return true;
    }
  }
  return false;
}

constexpr WiringFault kWiringFaults[] = {
    WiringFault::ok,
    WiringFault::left_motor_reversed,
    WiringFault::right_motor_reversed,
    WiringFault::left_encoder_reversed,
    WiringFault::right_encoder_reversed,
    WiringFault::encoders_swapped,
    WiringFault::motors_swapped,
};

bool fail(std::string& error, const std::string& source, const std::string& key,
          const std::string& why) {
  error = source + ": " + key + ": " + why;
  return false;
}

/// Every key a robot file may hold (the numeric ones set_key takes, and the named ones; the maze
/// and wall-sensor keys are robot_file_walls::keys).
constexpr const char* robot_file_keys[] = {"wheel_diameter_mm",      "wheelbase_mm",
                                           "counts_per_rev",         "true_left_diameter_mm",
                                           "true_right_diameter_mm", "true_wheelbase_mm",
                                           "true_wheelbase_arc_mm",  "slip_sigma",
                                           "bump_height_mm",         "bump_spacing_mm",
                                           "measure_sigma_mm",       "encoder_fault",
                                           "encoder_fault_after_s",  "wiring"};

/// Edit distance (insertions, deletions, substitutions) between two short keys.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) {
    row[j] = j;
  }
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

/// "unknown key", with the closest known key when the typo is small.
std::string unknown_key(const std::string& key) {
  const char* best = nullptr;
  std::size_t best_distance = 0;
  const auto consider = [&](const char* known) {
    const std::size_t d = edit_distance(key, known);
    if (best == nullptr || d < best_distance) {
      best = known;
      best_distance = d;
    }
  };
  for (const char* known : robot_file_keys) {
    consider(known);
  }
  for (const char* known : robot_file_walls::keys) {
    consider(known);
  }
  if (best != nullptr && best_distance <= std::max<std::size_t>(2, key.size() / 4)) {
    return std::string("unknown key (did you mean \"") + best + "\"?)";
  }
  return "unknown key";
}

std::string mm(double value) {
  return fmt::format("{:.6g} mm", value);
}

// Ranges a robot file must keep so that the simulated firmware can run every procedure on it.
// The wheel diameter's is the firmware's own (its parameter table); the wheelbase range is
// narrower than the firmware's 10-5000 mm so that a calibrated wheelbase (E_b·b, E_b up to
// 1.1/0.95) stays inside it.
constexpr const drive::ConfigField& firmware_field(params::ParamId id) {
  return drive::config_fields[static_cast<std::size_t>(id)];
}
constexpr double wheel_diameter_min_mm =
    static_cast<double>(firmware_field(params::ParamId::wheel_diameter_mm).min);
constexpr double wheel_diameter_max_mm =
    static_cast<double>(firmware_field(params::ParamId::wheel_diameter_mm).max);
constexpr double wheelbase_min_mm = 12.0;
constexpr double wheelbase_max_mm = 4000.0;
static_assert(wheelbase_min_mm * 0.95 / 1.1 >= firmware_field(params::ParamId::wheelbase_mm).min &&
                  wheelbase_max_mm * 1.1 / 0.95 <=
                      firmware_field(params::ParamId::wheelbase_mm).max,
              "a calibrated wheelbase stays within the firmware's range");
// Fewer than 100 counts per turn (under 2 mm of wheel travel per count on the default wheel) is
// too coarse for return errors of a few millimetres to mean anything.
constexpr double counts_per_rev_min = 100.0;
constexpr double counts_per_rev_max =
    static_cast<double>(firmware_field(params::ParamId::counts_per_rev).max);
// The procedures correct errors of a few percent (UMBmark's formulas are small-angle ones, and
// Maddahi's factors must stay in the firmware's 0.5-2): the real wheels within 5 % of what the
// firmware is told, the real wheelbase within 10 %.
constexpr double true_diameter_tolerance = 0.05;
constexpr double true_wheelbase_tolerance = 0.10;
// UMBmark's sonar calibrator measured to ±2 mm; beyond this the noise swamps the return errors.
constexpr double measure_sigma_max_mm = 100.0;

/// Checks a real geometry value against the nominal one it must stay near.
bool near_nominal(double true_mm, double nominal_mm, double tolerance) {
  return true_mm >= nominal_mm * (1.0 - tolerance) && true_mm <= nominal_mm * (1.0 + tolerance);
}

/// Reads one key of the robot file into `out`. @return false with `error` set when the key is
/// unknown or its value is out of its form (the ranges that involve other keys come after).
bool read_key(const std::string& key, const nlohmann::json& value, const std::string& source,
              RobotSpec& out, std::string& error) {
  if (robot_file_walls::is_key(key)) {
    return true;  // read once the robot's geometry is known (robot_file_walls::read)
  }
  if (key == "encoder_fault") {
    if (!value.is_string() || !parse_encoder_fault(value.get<std::string>(), out)) {
      return fail(error, source, key,
                  "must be one of \"none\", \"left_dead\", \"right_dead\", \"left_noisy\", "
                  "\"right_noisy\"");
    }
    return true;
  }
  if (key == "wiring") {
    bool known = false;
    for (const WiringFault fault : kWiringFaults) {
      if (value.is_string() && value.get<std::string>() == to_string(fault)) {
        out.wiring = fault;
        known = true;
      }
    }
    if (!known) {
      std::string allowed;
      for (const WiringFault fault : kWiringFaults) {
        allowed += std::string(allowed.empty() ? "\"" : ", \"") + to_string(fault) + "\"";
      }
      return fail(error, source, key, "must be one of " + allowed);
    }
    return true;
  }
  if (key == "encoder_fault_after_s") {
    if (!value.is_number() || !(value.get<double>() >= 0.0) || !(value.get<double>() <= 1.0e6)) {
      return fail(error, source, key, "must be a number of seconds from 0 to 1000000");
    }
    out.encoder_fault.after_s = value.get<double>();
    return true;
  }
  RobotSpec probe;
  if (!set_key(key, 1.0, probe)) {
    return fail(error, source, key, unknown_key(key));
  }
  if (!value.is_number()) {
    return fail(error, source, key, "must be a number");
  }
  const double number = value.get<double>();
  if (!std::isfinite(number)) {
    return fail(error, source, key, "must be finite");
  }
  if (key == "counts_per_rev" && !(number >= counts_per_rev_min && number <= counts_per_rev_max &&
                                   std::floor(number) == number && std::fmod(number, 4.0) == 0.0)) {
    return fail(error, source, key,
                "must be a whole multiple of 4 from 100 to 1000000 (x4 counts per wheel turn)");
  }
  static_cast<void>(set_key(key, number, out));
  return true;
}

/// A real robot not described in the file keeps the default robot's errors (E_d, E_b) around
/// whatever nominal geometry the file gives: `{"wheel_diameter_mm": 80}` is an 80 mm robot
/// with the default's 0.2 % wheel mismatch, not a 60 mm robot told it has 80 mm wheels.
void scale_untold_truth(const nlohmann::json& doc, RobotSpec& out) {
  const RobotSpec base = default_robot();
  const double d_scale = static_cast<double>(out.nominal.wheel_diameter_mm) /
                         static_cast<double>(base.nominal.wheel_diameter_mm);
  const double b_scale = static_cast<double>(out.nominal.wheelbase_mm) /
                         static_cast<double>(base.nominal.wheelbase_mm);
  if (!doc.contains("true_left_diameter_mm")) {
    out.truth.left_diameter_m = base.truth.left_diameter_m * d_scale;
  }
  if (!doc.contains("true_right_diameter_mm")) {
    out.truth.right_diameter_m = base.truth.right_diameter_m * d_scale;
  }
  if (!doc.contains("true_wheelbase_mm")) {
    out.truth.wheelbase_m = base.truth.wheelbase_m * b_scale;
  }
}

/// Checks the geometry the firmware is told (wheel diameter, wheelbase) against the ranges the
/// simulated firmware takes.
bool check_nominal_geometry(const RobotSpec& out, const std::string& source, std::string& error) {
  const double wheel_mm = static_cast<double>(out.nominal.wheel_diameter_mm);
  const double wheelbase_mm = static_cast<double>(out.nominal.wheelbase_mm);
  if (!(wheel_mm >= wheel_diameter_min_mm && wheel_mm <= wheel_diameter_max_mm)) {
    return fail(error, source, "wheel_diameter_mm",
                fmt::format("must be from {:g} to {:g} mm (the firmware's range), not {}",
                            wheel_diameter_min_mm, wheel_diameter_max_mm, mm(wheel_mm)));
  }
  if (!(wheelbase_mm > wheel_mm)) {
    return fail(
        error, source, "wheelbase_mm",
        "must be larger than the wheel diameter (" + mm(wheel_mm) + "), not " + mm(wheelbase_mm));
  }
  if (!(wheelbase_mm >= wheelbase_min_mm && wheelbase_mm <= wheelbase_max_mm)) {
    return fail(error, source, "wheelbase_mm",
                "must be from 12 to 4000 mm (the firmware takes 10-5000 mm, and a calibrated "
                "wheelbase must still fit), not " +
                    mm(wheelbase_mm));
  }
  if (!drive::valid(out.nominal)) {
    return fail(error, source, "robot", "the firmware refuses this geometry");
  }
  return true;
}

/// Checks the real robot's wheels and wheelbase against what the firmware is told: near enough
/// for the calibrations, which correct errors of a few percent.
bool check_true_geometry(const RobotSpec& out, const std::string& source, std::string& error) {
  const double wheel_mm = static_cast<double>(out.nominal.wheel_diameter_mm);
  const double wheelbase_mm = static_cast<double>(out.nominal.wheelbase_mm);
  const sim::RobotModel& t = out.truth;
  const std::pair<const char*, double> wheels[] = {
      {"true_left_diameter_mm", t.left_diameter_m * 1e3},
      {"true_right_diameter_mm", t.right_diameter_m * 1e3}};
  for (const auto& [key, true_mm] : wheels) {
    if (!(true_mm > 0.0)) {
      return fail(error, source, key, "must be > 0");
    }
    if (!near_nominal(true_mm, wheel_mm, true_diameter_tolerance)) {
      return fail(error, source, key,
                  mm(true_mm) + " is not within 5 % of wheel_diameter_mm (" + mm(wheel_mm) +
                      "): the calibrations correct errors of a few percent (give the real "
                      "wheels' diameters when the firmware is told another size)");
    }
  }
  const double true_wheelbase_mm = t.wheelbase_m * 1e3;
  if (!(true_wheelbase_mm > std::fmax(t.left_diameter_m, t.right_diameter_m) * 1e3)) {
    return fail(error, source, "true_wheelbase_mm", "must be larger than a wheel's diameter");
  }
  if (!near_nominal(true_wheelbase_mm, wheelbase_mm, true_wheelbase_tolerance)) {
    return fail(error, source, "true_wheelbase_mm",
                mm(true_wheelbase_mm) + " is not within 10 % of wheelbase_mm (" + mm(wheelbase_mm) +
                    "): the calibrations correct errors of a few percent (give the real "
                    "wheelbase when the firmware is told another one)");
  }
  // The arc wheelbase (0 = none), near the turn one: the firmware's wheelbase_arc_mm is within
  // 20 % of wheelbase_mm, and a real robot's differ by a few millimetres.
  const double true_arc_mm = t.wheelbase_arc_m * 1e3;
  if (true_arc_mm != 0.0 && !(std::fabs(true_arc_mm - true_wheelbase_mm) <=
                              drive::wheelbase_arc_tolerance * true_wheelbase_mm)) {
    return fail(error, source, "true_wheelbase_arc_mm",
                mm(true_arc_mm) +
                    " is neither 0 (one wheelbase) nor within 20 % of the true "
                    "wheelbase (" +
                    mm(true_wheelbase_mm) + ")");
  }
  return true;
}

/// Checks the real robot's noise and floor (slip, bumps, the calibrator's noise) and the model
/// as a whole.
bool check_true_noise(const sim::RobotModel& t, const std::string& source, std::string& error) {
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
  if (!(t.measure_sigma_m >= 0.0 && t.measure_sigma_m * 1e3 <= measure_sigma_max_mm)) {
    return fail(error, source, "measure_sigma_mm",
                "must be from 0 to 100 mm (UMBmark's calibrator: 2 mm; more swamps the errors "
                "being measured)");
  }
  if (sim::check(t) != sim::ModelError::none) {
    return fail(error, source, "robot", sim::to_string(sim::check(t)));
  }
  return true;
}

}  // namespace

bool parse_robot(const std::string& text, const std::string& source, RobotSpec& spec,
                 std::string& error) {
  nlohmann::json doc;
  JsonProblem problem;
  if (!parse_json_strict(text, doc, problem)) {
    if (problem.key.empty()) {
      error = source + ": " + problem.message;
      return false;
    }
    return fail(error, source, problem.key, problem.message);
  }
  if (!doc.is_object()) {
    error = source + ": the robot file must be one flat JSON object";
    return false;
  }
  RobotSpec out = default_robot();
  for (auto it = doc.begin(); it != doc.end(); ++it) {
    if (!read_key(it.key(), it.value(), source, out, error)) {
      return false;
    }
  }
  scale_untold_truth(doc, out);
  if (!check_nominal_geometry(out, source, error) || !check_true_geometry(out, source, error) ||
      !check_true_noise(out.truth, source, error) ||
      !robot_file_walls::read(doc, source, out, error)) {
    return false;
  }
  spec = out;
  return true;
}

bool load_robot_file(const std::string& path, RobotSpec& spec, std::string& error) {
  std::string text;
  try {
    text = read_text_file(path);  // a directory or an unreadable file is refused by name
  } catch (const InputError& e) {
    error = e.what();
    return false;
  }
  return parse_robot(text, path, spec, error);
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

}  // namespace odocal::host
