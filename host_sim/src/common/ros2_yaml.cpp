// YAML values for ROS 2 parameter files (ros2_yaml.hpp).

#include "odocal/host/ros2_yaml.hpp"

#include <charconv>
#include <system_error>

namespace odocal::host {

std::string yaml_double(double value) {
  char text[64];
  const auto [end, error] = std::to_chars(text, text + sizeof text, value);
  std::string out = error == std::errc{} ? std::string(text, end) : std::string("0");
  if (out.find('.') == std::string::npos) {
    const auto exponent = out.find_first_of("eE");
    out.insert(exponent == std::string::npos ? out.size() : exponent, ".0");
  }
  return out;
}

std::string yaml_list(const double (&values)[6]) {
  std::string out = "[";
  for (int i = 0; i < 6; ++i) {
    if (i > 0) {
      out += ", ";
    }
    out += yaml_double(values[i]);
  }
  return out + "]";
}

}  // namespace odocal::host
