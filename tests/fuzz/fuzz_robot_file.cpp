// libFuzzer target: arbitrary bytes as a robot file (`--robot FILE`, `--sim ROBOT.json`). Besides
// the sanitizers, it checks parse_robot's contract (host_sim/include/odocal/host/robot_file.hpp):
// no exception, false with an error "<source>: ..." and the spec untouched, or true with a robot
// inside the ranges the simulated firmware runs (the firmware accepts the told geometry, the
// model checks out, the true errors are finite and near 1); and load_robot_file on the same bytes
// in a file says the same (unless the bytes may name a maze file, found from each one's folder).

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "fuzz_scratch.hpp"
#include "odocal/host/robot_file.hpp"

namespace {

const odocal::fuzz::ScratchDir scratch("robot_file");

// A spec no robot file yields (a 1234.5 mm wheel is outside the firmware's range).
odocal::host::RobotSpec sentinel() {
  odocal::host::RobotSpec spec = odocal::host::default_robot();
  spec.nominal.wheel_diameter_mm = 1234.5f;
  spec.encoder_fault.after_s = -7.0;
  return spec;
}

bool untouched(const odocal::host::RobotSpec& spec) {
  return spec.nominal.wheel_diameter_mm == 1234.5f && spec.encoder_fault.after_s == -7.0;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace odocal;
  const std::string text(reinterpret_cast<const char*>(data), size);
  host::RobotSpec spec = sentinel();
  std::string error;
  const bool ok = host::parse_robot(text, "robot.json", spec, error);
  if (!ok) {
    if (!untouched(spec) || error.rfind("robot.json: ", 0) != 0)
      __builtin_trap();
  } else {
    const double wheel = static_cast<double>(spec.nominal.wheel_diameter_mm);
    const double wheelbase = static_cast<double>(spec.nominal.wheelbase_mm);
    if (!error.empty() || !drive::valid(spec.nominal) || !(wheelbase > wheel) ||
        sim::check(spec.truth) != sim::ModelError::none)
      __builtin_trap();
    // The true wheels within 5 % of the told one, the true wheelbase within 10 %.
    if (!(std::fabs(spec.truth.left_diameter_m * 1e3 / wheel - 1.0) <= 0.0501) ||
        !(std::fabs(spec.truth.right_diameter_m * 1e3 / wheel - 1.0) <= 0.0501) ||
        !(std::fabs(spec.truth.wheelbase_m * 1e3 / wheelbase - 1.0) <= 0.1001))
      __builtin_trap();
    const host::TrueErrors e = host::true_errors(spec);
    if (!std::isfinite(e.e_d) || !std::isfinite(e.e_b) || !(e.e_d > 0.8 && e.e_d < 1.2) ||
        !(e.e_b > 0.7 && e.e_b < 1.3))
      __builtin_trap();
    if (!(spec.encoder_fault.after_s >= 0.0) ||
        (spec.encoder_fault.wheel != -1) != (spec.encoder_fault.fault != sim::ChannelFault::none))
      __builtin_trap();
  }

  // The same bytes as a file: the same verdict, and the same message but for the source. Not when
  // the bytes may name a maze file: it is found from each robot file's own folder (the working
  // directory for the text, the scratch folder for the file), which may hold different files.
  if (text.find("maze") != std::string::npos || text.find("\\u") != std::string::npos) {
    return 0;
  }
  const std::string path = scratch.write("robot.json", data, size);
  host::RobotSpec from_file = sentinel();
  std::string file_error;
  const bool file_ok = host::load_robot_file(path, from_file, file_error);
  if (file_ok != ok || (!ok && file_error != path + error.substr(std::strlen("robot.json"))))
    __builtin_trap();
  if (ok &&
      (from_file.nominal.wheel_diameter_mm != spec.nominal.wheel_diameter_mm ||
       from_file.truth.wheelbase_m != spec.truth.wheelbase_m || from_file.wiring != spec.wiring))
    __builtin_trap();
  return 0;
}
