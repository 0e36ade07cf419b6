#pragma once
/// @file
/// Strict reading of the numbers `odocal sim` and `odocal-sim` take on their command lines: the
/// whole text must be one plain decimal number (no hex, no trailing junk, finite), inside a
/// closed range. The CLI11 validators built on it name the flag, the range and the unit.

#include <CLI/CLI.hpp>
#include <cstdint>
#include <optional>
#include <string>

namespace odocal::host {

/// A decimal real ("4000", "-2.5", "1e3"): nullopt for anything else (empty, "abc", "4000x",
/// "0x10", "nan", "inf", overflow such as "1e400").
[[nodiscard]] std::optional<double> parse_real(const std::string& text);

/// A non-negative decimal integer made of digits only ("42"): nullopt for a sign, a fraction, an
/// exponent, hex, trailing junk, or a value above 2^64 − 1.
[[nodiscard]] std::optional<std::uint64_t> parse_whole(const std::string& text);

/// A CLI11 check: a real in [lo, hi] `unit` (CLI11 prefixes the flag to the message).
/// With `zero_allowed`, 0 is accepted besides the range (e.g. `--speed 0`, as fast as possible).
[[nodiscard]] CLI::Validator real_in(double lo, double hi, const std::string& unit,
                                     bool zero_allowed = false);

/// A CLI11 check: a whole number in [lo, hi].
[[nodiscard]] CLI::Validator whole_in(std::uint64_t lo, std::uint64_t hi);

}  // namespace odocal::host
