#pragma once
/// @file
/// The CLI11 checks of every host command line (odocal, odocal-sim, odocal-linux), built on
/// numbers.hpp. A refused argument reads "--FLAG: must be ALLOWED, got 'TEXT'" (CLI11 puts the
/// flag in front) and the program exits with status 2.

#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <string>

namespace odocal::toolkit {

/// A finite plain decimal real (parse_real) for which `ok` holds; `allowed` says which, e.g.
/// "a finite number strictly between 0 and 1".
[[nodiscard]] CLI::Validator number_check(const std::string& allowed,
                                          const std::function<bool(double)>& ok);

/// Whether a range takes its lower bound.
enum class LowBound { closed, open };

/// "a finite number from LOW to HIGH UNIT" (closed) or "a finite number > LOW and at most HIGH
/// UNIT" (open); no unit when `unit` is empty.
[[nodiscard]] std::string range_text(double low, double high, const std::string& unit,
                                     LowBound low_bound = LowBound::closed);

/// A finite real in [low, high] (or (low, high]), with its unit in the message.
[[nodiscard]] CLI::Validator range_check(double low, double high, const std::string& unit,
                                         LowBound low_bound = LowBound::closed);

/// 0, or a finite real in [low, high] (e.g. `--speed 0`, as fast as possible).
[[nodiscard]] CLI::Validator zero_or_range_check(double low, double high, const std::string& unit);

/// A whole number in [low, high], digits only (parse_whole); `what` names it in the message
/// ("a whole number of replicates from 100 to 1000000").
[[nodiscard]] CLI::Validator whole_check(std::uint64_t low, std::uint64_t high,
                                         const std::string& what = "");

}  // namespace odocal::toolkit
