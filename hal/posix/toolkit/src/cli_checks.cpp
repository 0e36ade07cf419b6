#include "odocal/toolkit/cli_checks.hpp"

#include "odocal/toolkit/numbers.hpp"

namespace odocal::toolkit {

CLI::Validator number_check(const std::string& allowed, const std::function<bool(double)>& ok) {
  return CLI::Validator(
      [allowed, ok](std::string& text) {
        const std::optional<double> value = parse_real(text);
        if (value && ok(*value)) {
          return std::string{};
        }
        return "must be " + allowed + ", got '" + text + "'";
      },
      "NUMBER");
}

std::string range_text(double low, double high, const std::string& unit, LowBound low_bound) {
  const bool open = low_bound == LowBound::open;
  return "a finite number " + std::string(open ? "> " : "from ") + bound_text(low) +
         (open ? " and at most " : " to ") + bound_text(high) + (unit.empty() ? "" : " " + unit);
}

CLI::Validator range_check(double low, double high, const std::string& unit, LowBound low_bound) {
  const bool open = low_bound == LowBound::open;
  return number_check(range_text(low, high, unit, low_bound), [low, high, open](double v) {
    return (open ? v > low : v >= low) && v <= high;
  });
}

CLI::Validator zero_or_range_check(double low, double high, const std::string& unit) {
  return number_check("0 or " + range_text(low, high, unit),
                      [low, high](double v) { return v == 0.0 || (v >= low && v <= high); });
}

CLI::Validator whole_check(std::uint64_t low, std::uint64_t high, const std::string& what) {
  const std::string allowed = "a whole number " + what + (what.empty() ? "" : " ") + "from " +
                              std::to_string(low) + " to " + std::to_string(high);
  return CLI::Validator(
      [allowed, low, high](std::string& text) {
        if (parse_whole_in(text, low, high)) {
          return std::string{};
        }
        return "must be " + allowed + ", got '" + text + "'";
      },
      "UINT");
}

}  // namespace odocal::toolkit
