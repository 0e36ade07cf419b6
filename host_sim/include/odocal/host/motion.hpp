#pragma once
/// @file
/// What one run tells the robot to do, as a value: one of the robot's paths (`run ...`), a timed
/// drive (`drive v w ms`) or the self-test's wheel drives. The session builds runs as Motions,
/// compares them as values (a repeat of a run, a run taken over on --resume) and turns one into a
/// console line in one place (`command`); a line is read back into a Motion as the robot reads it
/// (its command list, its number parser, its argument ranges: console/commands.hpp).

#include <cstdint>
#include <optional>
#include <string>

#include "odocal/drive/motion_executor.hpp"

namespace odocal::host {

struct Motion {
  enum class Kind : std::uint8_t {
    square_cw,   ///< `run umbmark-cw <side_m>`
    square_ccw,  ///< `run umbmark-ccw <side_m>`
    line,        ///< `run line <m>`
    unseen,      ///< `run unseen` (its shape is the robot's)
    timed,       ///< `drive <v_mps> <w_radps> <ms>`
    selftest,    ///< `selftest [left|right]`
  };
  enum class Wheels : std::uint8_t { both, left, right };

  Kind kind = Kind::unseen;
  float length_m = 0.0f;         ///< square side or line length, as the robot reads it
  float v_mps = 0.0f;            ///< timed drive: forward speed
  float w_radps = 0.0f;          ///< timed drive: turn rate, counter-clockwise positive
  std::uint32_t ms = 0u;         ///< timed drive: how long
  Wheels wheels = Wheels::both;  ///< self-test: the wheels it turns

  /// The motions, their numbers as the console line carries them (a length to the millimetre, a
  /// speed and a turn rate to 4 decimals, whole milliseconds): what the robot will drive.
  [[nodiscard]] static Motion square(bool clockwise, double side_m);
  [[nodiscard]] static Motion line(double length_m);
  [[nodiscard]] static Motion unseen();
  [[nodiscard]] static Motion timed(double v_mps, double w_radps, double ms);
  [[nodiscard]] static Motion selftest(Wheels wheels);

  /// The console line that starts it: the one place a motion becomes text.
  [[nodiscard]] std::string command() const;
  /// The motion a console line starts, read as the robot reads it; nullopt for any other line
  /// and for arguments the robot would refuse.
  [[nodiscard]] static std::optional<Motion> of_command(const std::string& line);
  /// The path the robot is told to drive: its own for `run`, one segment (v·t, w·t) for a timed
  /// drive; nullopt for the self-test.
  [[nodiscard]] std::optional<drive::Path> path() const;

  friend bool operator==(const Motion& a, const Motion& b) = default;
};

}  // namespace odocal::host
