// `odocal session --procedure selftest` (DESIGN "Wiring self-test"): the robot's `selftest`,
// then, for what the encoders alone cannot tell apart (a motor or an encoder turned the wrong
// way; motors or encoders swapped), one wheel driven alone and measured: which way the robot
// turned says which wheel moved and which way. Names each fault, proposes the `wiring_fix` that
// fixes it, applies it with --yes or the user's consent, and tests again.

#include <cstdint>
#include <optional>
#include <sstream>
#include <stdexcept>
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
  // The user's moment: the wheels turn, so nothing is sent before Enter (with --port).
  c.wait_for_enter(
      "Self-test: put the robot on the floor with room to turn about its middle (each wheel "
      "turns alone, slowly, for a moment); hands off;",
      "the self-test");
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

/// The self-test of one wheel ("left" or "right").
Motion wheel_motion(const std::string& side) {
  return Motion::selftest(side == "right" ? Motion::Wheels::right : Motion::Wheels::left);
}

/// Tells the two faults behind a console fault apart by the heading the robot turned to while
/// `selftest <side>` drove one wheel: a left wheel turning forward (or a right wheel turning
/// backwards) turns the robot clockwise.
Diagnosis diagnose(Context& c, const std::string& seen) {
  const bool right = seen == "right_reversed";
  const std::string side = right ? "right" : "left";
  c.robot.drain(300);  // the `# done` of the self-test's own drives
  const RunRecord r = c.run("selftest " + side, wheel_motion(side), 1.2);
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

/// The fix checked by a motion it predicts: each side's wheel driven alone again, forward as the
/// fixed wiring now drives it, must turn the robot as a wheel going forward does (the left one
/// clockwise, the right one counter-clockwise). A heading typed with the wrong sign in the
/// diagnosis proposes the wrong fix, and this motion then turns the other way.
void check_fix(Context& c, const std::vector<std::string>& sides) {
  for (const std::string& side : sides) {
    c.robot.drain(300);
    const RunRecord r = c.run("selftest check " + side, wheel_motion(side), 1.2);
    const bool counter_clockwise = r.measured.theta_deg.value_or(0.0) > 0.0;
    const bool as_predicted = side == "right" ? counter_clockwise : !counter_clockwise;
    if (!as_predicted) {
      throw std::runtime_error(fmt::format(
          "the fix does not hold: with it the {} wheel should turn the robot {} (heading {} 0), "
          "but the heading measured was {:.1f} deg. A heading typed with the wrong sign in the "
          "self-test proposes the wrong fix: the fix is taken back; run the self-test again and "
          "read each heading counter-clockwise positive",
          side, side == "right" ? "counter-clockwise" : "clockwise", side == "right" ? ">" : "<",
          r.measured.theta_deg.value_or(0.0)));
    }
  }
}

/// The self-test's outcome and its measured runs in the partial result, for --resume.
void record(Context& c, const Outcome& out, std::size_t runs_before) {
  c.partial["selftest"] = out.result;
  c.partial["selftest_runs"] = c.runs.size() - runs_before;
  c.partial["selftest_text"] = out.text;
}

/// --resume: the self-test the interrupted session finished is not driven again. Its measured
/// runs are taken over and its fix (put back by the interruption) is applied again.
std::optional<Outcome> replayed(Context& c) {
  const nlohmann::json& before = c.options.resumed_result;
  if (!before.is_object() || !before.contains("selftest") || !before["selftest"].is_object() ||
      !before.contains("selftest_runs") || !before["selftest_runs"].is_number_unsigned()) {
    return std::nullopt;
  }
  const auto measured = before["selftest_runs"].get<std::size_t>();
  if (c.runs.size() + measured > c.options.replay.size()) {
    return std::nullopt;  // its runs are not all there: test again
  }
  c.initial_wiring_fix = c.get(ParamId::wiring_fix);  // what an interruption puts back
  Outcome out;
  out.result = before["selftest"];
  out.text = before.value("selftest_text", std::string());
  const std::size_t runs_before = c.runs.size();
  for (std::size_t i = 0; i < measured; ++i) {
    const RunRecord& r = c.options.replay[c.runs.size()];
    static_cast<void>(c.run(r.label, r.motion, 1.2));
  }
  std::string again;
  if (out.result.contains("fixed") && out.result["fixed"].contains("wiring_fix")) {
    const double value = out.result["fixed"]["wiring_fix"].get<double>();
    static_cast<void>(c.set(ParamId::wiring_fix, value));
    out.applied = true;
    again = fmt::format("; its fix applied again (wiring_fix {:.0f})", value);
  }
  c.log << "Self-test: done before the interruption (" << out.result["faults"].size()
        << " fault(s)), not driven again" << again << ".\n";
  // Kept for the next --resume too: a session interrupted again takes it over once more.
  record(c, out, runs_before);
  return out;
}

}  // namespace

Outcome run_selftest(Context& c) {
  if (std::optional<Outcome> done = replayed(c)) {
    return *done;
  }
  const std::size_t runs_before = c.runs.size();
  Outcome out;
  const double wiring_fix = c.get(ParamId::wiring_fix);
  if (!c.initial_wiring_fix) {
    c.initial_wiring_fix = wiring_fix;  // what an interruption puts back
  }
  const auto before = static_cast<std::uint32_t>(wiring_fix);
  const Reply first = selftest(c, "selftest");
  nlohmann::json faults = nlohmann::json::array();
  std::uint32_t bits = 0u;
  std::vector<std::string> fixes;
  std::vector<std::string> sides;  // the wheels whose fix a motion checks
  std::ostringstream text;
  for (const std::string& seen : fault_list(first)) {
    if (seen == "left_reversed" || seen == "right_reversed" || seen == "crossed") {
      const Diagnosis d = diagnose(c, seen);
      sides.push_back(seen == "right_reversed" ? "right" : "left");
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
    c.log << "Wired right: no fault.\n";  // said as it is found (the result text may not be)
  }
  if (bits != 0u) {
    const std::uint32_t proposed = before ^ bits;
    std::string names;
    for (const std::string& f : fixes) {
      names += (names.empty() ? "" : ", ") + f;
    }
    c.log << text.str();
    if (ask_yes_no(c, fmt::format("Apply the fix ({}): set wiring_fix {}?", names, proposed))) {
      const auto value = static_cast<std::uint32_t>(c.set(ParamId::wiring_fix, proposed));
      out.result["fixed"]["wiring_fix"] = value;
      out.result["wiring_fix"] = value;
      out.applied = true;
      const std::vector<std::string> after = fault_list(selftest(c, "selftest"));
      out.result["after"] = after;
      check_fix(c, sides);
      out.result["checked_by_motion"] = sides;
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
  record(c, out, runs_before);
  return out;
}

}  // namespace odocal::host::session
