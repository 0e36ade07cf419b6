// `odocal ros2`: see docs/calibration.md.

#include "calib_cli.hpp"
#include "odocal/host/fit_noise.hpp"
#include "odocal/host/ros2_yaml.hpp"

namespace odocal::host::calib_cli {
namespace {

/// `prefix` + `key`: where a key of the calibration object is in the file, for messages.
std::string field_name(const std::string& prefix, const char* key) {
  return prefix + key;
}

double multiplier_key(const json& object, const std::string& file, const std::string& prefix,
                      const char* key) {
  if (!object.contains(key)) {
    throw InputError(file, 0, field_name(prefix, key),
                     "missing key (expected the JSON of `odocal umbmark --json` or `odocal fit "
                     "--json`, or a session.json whose result is one)");
  }
  const json& value = object.at(key);
  if (!value.is_number() || !std::isfinite(value.get<double>()) || !(value.get<double>() > 0.0) ||
      value.get<double>() > ros2_max_multiplier) {
    throw InputError(file, 0, field_name(prefix, key),
                     "must be " + multiplier_allowed() + ", got " +
                         value.dump(-1, ' ', false, json::error_handler_t::replace));
  }
  return value.get<double>();
}

/// The calibration in a `--from` file: the file itself (the JSON of `odocal umbmark` or `odocal
/// fit`), or, in a session.json (`procedure` and `result`), its `result` (`--procedure fit`,
/// `umbmark`) or the fit inside it (`result.fit`, `--procedure auto`). `prefix` says where.
const json& calibration_of(const json& doc, std::string& prefix) {
  if (!doc.contains("procedure") || !doc.contains("result") || !doc["result"].is_object()) {
    prefix.clear();
    return doc;
  }
  const json& result = doc["result"];
  if (result.contains("fit") && result["fit"].is_object() && !result.contains("c_l")) {
    prefix = "result.fit.";
    return result["fit"];
  }
  prefix = "result.";
  return result;
}

/// A ROS 2 node / controller name: a letter or '_', then letters, digits or '_'
/// (rmw_validate_node_name), at most 255 characters.
bool ros2_name(const std::string& name) {
  static const std::regex pattern("[A-Za-z_][A-Za-z0-9_]*");
  return name.size() <= 255 && std::regex_match(name, pattern);
}

/// Text from a JSON file that goes into a YAML comment: printable ASCII only, so that a newline
/// in it cannot start a YAML line of its own.
std::string comment_text(const json& value) {
  std::string text = value.is_string() ? value.get<std::string>()
                                       : value.dump(-1, ' ', false, json::error_handler_t::replace);
  for (char& c : text) {
    if (c < 0x20 || c > 0x7e) {
      c = '?';
    }
  }
  return text;
}

/// A number of `odocal fit`'s noise object: finite and >= 0.
double noise_key(const json& noise, const std::string& file, const std::string& prefix,
                 const char* key) {
  const std::string field = prefix + "noise." + key;
  if (!noise.contains(key)) {
    throw InputError(file, 0, field, "missing key (expected the JSON of `odocal fit --json`)");
  }
  const json& value = noise.at(key);
  if (!value.is_number() || !std::isfinite(value.get<double>()) || value.get<double>() < 0.0 ||
      value.get<double>() > 1e6) {
    throw InputError(file, 0, field,
                     "must be a number from 0 to 1e6 (mm^2/mm), got " +
                         value.dump(-1, ' ', false, json::error_handler_t::replace));
  }
  return value.get<double>();
}

}  // namespace

void run_ros2(const Ros2Options& o) {
  if (!ros2_name(o.controller)) {
    throw InputError("(command line)", 0, "--controller",
                     "must be a ROS 2 controller name: a letter or '_', then letters, digits or "
                     "'_' (at most 255), got '" +
                         comment_text(json(o.controller)) + "'");
  }
  double c_l = 0.0, c_r = 0.0, e_b = 0.0;
  std::string source;
  std::optional<Ros2Covariance> covariance;
  std::string covariance_note;
  if (!o.from_file.empty()) {
    const std::string text = read_text_file(o.from_file);
    json doc;
    JsonProblem problem;
    if (!parse_json_strict(text, doc, problem)) {
      throw InputError(o.from_file, problem.line, problem.key, problem.message);
    }
    if (!doc.is_object()) {
      throw InputError(o.from_file, 1, "", "expected a JSON object");
    }
    std::string at;  // where the calibration is in the file: "", "result." or "result.fit."
    const json& cal = calibration_of(doc, at);
    c_l = multiplier_key(cal, o.from_file, at, "c_l");
    c_r = multiplier_key(cal, o.from_file, at, "c_r");
    e_b = multiplier_key(cal, o.from_file, at, "e_b");
    source = comment_text(json(o.from_file));
    if (!at.empty()) {
      source += " (session, procedure " + comment_text(doc["procedure"]) + ")";
    }
    // The JSON of `odocal fit` carries the random error growth: the covariances follow from it.
    if (cal.contains("noise") && cal["noise"].is_object() && !cal["noise"].contains("error")) {
      const WheelNoise noise{noise_key(cal["noise"], o.from_file, at, "k_l"),
                             noise_key(cal["noise"], o.from_file, at, "k_r")};
      if (!cal.contains("wheelbase_mm") || !cal["wheelbase_mm"].is_number() ||
          !(cal["wheelbase_mm"].get<double>() > 0.0) ||
          !std::isfinite(cal["wheelbase_mm"].get<double>())) {
        throw InputError(o.from_file, 0, at + "wheelbase_mm",
                         "missing or not a positive number (the covariance needs the wheelbase)");
      }
      covariance = ros2_covariance(noise, cal["wheelbase_mm"].get<double>(), o.speed_mps,
                                   o.velocity, o.pose_distance_m);
      covariance_note = ros2_covariance_note(noise, o.pose_distance_m, o.speed_mps, o.velocity);
    } else if (cal.contains("noise") && cal["noise"].is_object()) {
      covariance_note = "# no covariances: " + comment_text(cal["noise"]["error"]) + "\n";
    }
    if (doc.contains("provenance") && doc["provenance"].is_object()) {
      const auto& p = doc["provenance"];
      const auto field = [&p](const char* key) {
        return p.contains(key) ? comment_text(p[key]) : std::string("?");
      };
      source += " (" + field("method") + ", " + field("runs") + " runs, " + field("date") + ")";
    }
  } else {
    if (!o.c_l || !o.c_r || !o.e_b) {
      throw InputError("(command line)", 0,
                       !o.c_l   ? "--c-l"
                       : !o.c_r ? "--c-r"
                                : "--e-b",
                       "give --from FILE, or all of --c-l, --c-r and --e-b");
    }
    c_l = *o.c_l;
    c_r = *o.c_r;
    e_b = *o.e_b;
    source = "command line";
  }
  // diff_drive_controller multiplies the wheel separation and each wheel radius it is given:
  // E_b scales the wheelbase, c_L and c_R scale each wheel's distance per radian. ROS 2 declares
  // them as doubles and refuses an integer, so each value is written as a float literal.
  std::printf("# ROS 2 diff_drive_controller parameters from odocal (%s)\n", source.c_str());
  std::printf("%s", covariance_note.c_str());
  std::printf("%s:\n  ros__parameters:\n", o.controller.c_str());
  std::printf("    wheel_separation_multiplier: %s\n", yaml_double(e_b).c_str());
  std::printf("    left_wheel_radius_multiplier: %s\n", yaml_double(c_l).c_str());
  std::printf("    right_wheel_radius_multiplier: %s\n", yaml_double(c_r).c_str());
  if (covariance) {
    std::printf("    pose_covariance_diagonal: %s\n", yaml_list(covariance->pose).c_str());
    std::printf("    twist_covariance_diagonal: %s\n", yaml_list(covariance->twist).c_str());
  }
}

}  // namespace odocal::host::calib_cli
