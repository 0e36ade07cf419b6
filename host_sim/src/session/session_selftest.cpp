// `odocal session --procedure selftest` (DESIGN "Wiring self-test"): the robot's `selftest`,
// then, for what the encoders alone cannot tell apart (a motor or an encoder turned the wrong
// way; motors or encoders swapped), one wheel driven alone and measured: which way the robot
// turned says which wheel moved and which way. Names each fault, proposes the `wiring_fix` that
// fixes it, applies it with --yes or the user's consent, and tests again.

#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "odocal/drive/drive_config.hpp"
#include "odocal/host/csv.hpp"
#include "session_internal.hpp"

namespace odocal::host::session {
namespace {

/// The console's `faults=` list ("none" or names joined by commas).
std::vector<std::string> fault_list(const Reply& reply) {
  std::vector<std::string> out;
  std::stringstream list(reply.text("faults"));
  for (std::string name; std::getline(list, name, ',');) {
    if (!name.empty() && name != "none") {
      out.push_back(name);
    }
  }
  return out;
}

Reply selftest(Context& c, const std::string& line) {
  c.log << "Self-test: each wheel turns alone, slowly, for a moment (" << line << ")\n";
  // Two wheels, each 0.3 s of driving and 0.8 s to come to rest: seconds on a real robot.
  return c.robot.expect_ok(line, 20000);
}

/// What one wheel driven alone shows: the fault it is (DESIGN name) and its wiring_fix bit.
struct Diagnosis {
  std::string fault;
  std::uint32_t bit = 0u;
  std::string fix;
};

/// Tells the two faults behind a console fault apart by the heading the robot turned to while
/// `selftest <side>` drove one wheel: a left wheel turning forward (or a right wheel turning
/// backwards) turns the robot clockwise.
Diagnosis diagnose(Context& c, const std::string& seen) {
  const bool right = seen == "right_reversed";
  const std::string side = right ? "right" : "left";
  c.robot.drain(300);  // the `# done` of the self-test's own drives
  const RunRecord r = c.run("selftest " + side, "selftest " + side, 1.2);
  if (!r.measured.theta_deg) {
    throw InputError("measurement", 0, "theta_deg",
                     "the self-test needs the robot's heading after the run (x y theta): it "
                     "tells which wheel turned which way");
  }
  const bool counter_clockwise = *r.measured.theta_deg > 0.0;
  if (seen == "crossed") {
    // Driving the left output: the left wheel turned (clockwise) when the encoders are swapped,
    // the right wheel (counter-clockwise) when the motors are.
    return counter_clockwise ? Diagnosis{"motors_swapped", drive::swap_motors, "swap_motors"}
                             : Diagnosis{"encoders_swapped", drive::swap_encoders, "swap_encoders"};
  }
  // The wheel's encoder counted backwards: the wheel really went backwards (the motor is
  // reversed) or forward (the encoder is).
  const bool wheel_backwards = right ? !counter_clockwise : counter_clockwise;
  if (right) {
    return wheel_backwards
               ? Diagnosis{"right_motor_reversed", drive::invert_right_motor, "invert_right_motor"}
               : Diagnosis{"right_encoder_reversed", drive::invert_right_encoder,
                           "invert_right_encoder"};
  }
  return wheel_backwards
             ? Diagnosis{"left_motor_reversed", drive::invert_left_motor, "invert_left_motor"}
             : Diagnosis{"left_encoder_reversed", drive::invert_left_encoder,
                         "invert_left_encoder"};
}

/// --yes, or "y" typed at the terminal; false without a terminal.
bool consent(Context& c, const std::string& question) {
  if (c.options.yes) {
    return true;
  }
  if (c.options.confirm_in == nullptr) {
    return false;
  }
  for (;;) {
    c.log << question << " [y/n]: " << std::flush;
    std::string answer;
    if (!std::getline(*c.options.confirm_in, answer)) {
      throw InputError("standard input", 0, "", "end of input at the question '" + question + "'");
    }
    while (!answer.empty() && (answer.back() == '\r' || answer.back() == ' ')) {
      answer.pop_back();
    }
    if (answer == "y" || answer == "yes") {
      return true;
    }
    if (answer == "n" || answer == "no") {
      return false;
    }
  }
}

}  // namespace

Outcome run_selftest(Context& c) {
  Outcome out;
  const auto before = static_cast<std::uint32_t>(c.get("wiring_fix"));
  const Reply first = selftest(c, "selftest");
  nlohmann::json faults = nlohmann::json::array();
  std::uint32_t bits = 0u;
  std::vector<std::string> fixes;
  std::ostringstream text;
  for (const std::string& seen : fault_list(first)) {
    if (seen == "left_reversed" || seen == "right_reversed" || seen == "crossed") {
      const Diagnosis d = diagnose(c, seen);
      faults.push_back(d.fault);
      bits |= d.bit;
      fixes.push_back(d.fix);
      text << fmt::format("Fault: {} (fix: {})\n", d.fault, d.fix);
    } else {
      // A wheel that did not turn (dead band, a dead motor or encoder), illegal transitions:
      // wiring no parameter fixes.
      faults.push_back(seen);
      text << fmt::format("Fault: {} (no parameter fixes it: see docs/wiring.md)\n", seen);
    }
  }
  out.result["faults"] = faults;
  out.result["fixed"] = nlohmann::json::object();
  out.result["wiring_fix"] = before;
  if (faults.empty()) {
    text << "Wired right: no fault.\n";
  }
  if (bits != 0u) {
    const std::uint32_t proposed = before ^ bits;
    std::string names;
    for (const std::string& f : fixes) {
      names += (names.empty() ? "" : ", ") + f;
    }
    c.log << text.str();
    if (consent(c, fmt::format("Apply the fix ({}): set wiring_fix {}?", names, proposed))) {
      const auto value = static_cast<std::uint32_t>(c.set("wiring_fix", proposed));
      out.result["fixed"]["wiring_fix"] = value;
      out.result["wiring_fix"] = value;
      out.applied = true;
      const std::vector<std::string> after = fault_list(selftest(c, "selftest"));
      out.result["after"] = after;
      text << fmt::format("Applied wiring_fix {} ({}); the self-test again: {}\n", value, names,
                          after.empty() ? std::string("no fault")
                                        : fmt::format("{}", after.size()) + " fault(s) left");
    } else {
      const std::string not_applied = fmt::format(
          "Not applied: type 'set wiring_fix {}' on the console (then 'save').\n", proposed);
      c.log << not_applied;
      text << not_applied;
    }
  }
  out.text = text.str();
  return out;
}

}  // namespace odocal::host::session
