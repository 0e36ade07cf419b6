#pragma once
/// @file
/// Outcome of a start-up step of the Linux backend (opening a chip, requesting a line, ...).

#include <cstdint>
#include <string>
#include <utility>

namespace odocal::hal::linux_gpiod {

/// What went wrong while setting a peripheral up.
enum class SetupCode : std::uint8_t {
  ok,
  not_found,          ///< the GPIO chip, line or PWM chip/channel does not exist
  busy,               ///< the line or PWM channel is already used by someone else
  permission_denied,  ///< the device exists but this user may not open it
  bad_argument,       ///< a value the caller gave is out of range
  system_error,       ///< any other failing system call
};

/// A code and a message that names the thing that failed (chip, line, role, file).
/// Set-up only: building the message may allocate, so never use it from the tick.
struct [[nodiscard]] SetupResult {
  SetupCode code = SetupCode::ok;
  std::string message;

  /// True when the step succeeded.
  bool ok() const { return code == SetupCode::ok; }

  static SetupResult success() { return SetupResult{}; }
  static SetupResult failure(SetupCode code, std::string message) {
    return SetupResult{code, std::move(message)};
  }
};

/// Maps an errno value from a failed open or request to a code.
SetupCode code_of_errno(int error_number);

}  // namespace odocal::hal::linux_gpiod
