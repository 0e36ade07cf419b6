#pragma once
/// @file
/// The GPIO chips a process uses, opened once each, and the lines requested on them.

#include <array>
#include <cstddef>
#include <string>

#include "odocal/hal/linux_gpiod/setup_result.hpp"

struct gpiod_chip;
struct gpiod_line;

namespace odocal::hal::linux_gpiod {

/// One GPIO line named by its chip and offset, with the role it plays (used in messages).
struct LinePin {
  std::string chip;          ///< "gpiochip0", "/dev/gpiochip0", a chip label or a number
  unsigned int offset = 0u;  ///< line offset within the chip
  std::string role;          ///< e.g. "left_a": what the configuration calls this line
};

/// Opens GPIO chips on demand (each at most once) and hands out their lines. Every line it
/// handed out is released when the set is destroyed. Set-up only: not thread-safe.
class ChipSet {
 public:
  static constexpr std::size_t max_chips = 8u;

  ChipSet() = default;
  ~ChipSet();
  ChipSet(const ChipSet&) = delete;
  ChipSet& operator=(const ChipSet&) = delete;

  /// Finds `pin` and checks it is free. On success `*line` is the (not yet requested) line.
  /// Fails with `not_found` (no such chip or offset), `busy` (a consumer holds the line, named in
  /// the message) or `permission_denied`.
  SetupResult find(const LinePin& pin, gpiod_line** line);

  /// Opens `chip` without taking a line: checks that it exists.
  SetupResult open(const std::string& chip, gpiod_chip** handle);

 private:
  struct Entry {
    std::string name;
    gpiod_chip* chip = nullptr;
  };
  std::array<Entry, max_chips> chips_{};
};

/// "gpiochip0 line 17 (left_a)": how messages name a line.
std::string describe(const LinePin& pin);

/// Explains a failed line request (`errno` after gpiod_line_request_*), naming the line.
SetupResult request_failure(const LinePin& pin, gpiod_line* line, int error_number);

}  // namespace odocal::hal::linux_gpiod
