#pragma once
// The calibration subcommands of `odocal` share these: error handling, number checks for
// CLI11, JSON and CSV helpers, and each command's options. Internal to host_sim/src/cli.

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "odocal/calib/accuracy.hpp"
#include "odocal/calib/bootstrap.hpp"
#include "odocal/calib/lateral.hpp"
#include "odocal/calib/umbmark.hpp"
#include "odocal/host/calib_json.hpp"
#include "odocal/host/csv.hpp"
#include "odocal/host/fit_noise.hpp"
#include "odocal/toolkit/cli_checks.hpp"
#include "odocal/toolkit/numbers.hpp"

namespace odocal::host::calib_cli {

using nlohmann::json;
using toolkit::bound_text;
using toolkit::number_check;
using toolkit::range_check;
using toolkit::whole_check;

/// Runs a handler; bad input (any exception) becomes exit status 2 and one line on stderr.
inline void guarded(const char* command, int& exit_code, const std::function<void()>& body) {
  try {
    body();
    exit_code = 0;
  } catch (const std::exception& e) {
    std::cerr << "odocal " << command << ": " << e.what() << '\n';
    exit_code = 2;
  }
}

inline std::string date_or_today(const std::string& date) {
  return date.empty() ? today_utc() : date;
}

inline bool leap_year(int year) {
  return (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
}

inline void add_date_option(CLI::App* cmd, std::string& date) {
  cmd->add_option("--date", date, "date recorded in the provenance (YYYY-MM-DD; default today)")
      ->check(CLI::Validator(
          [](std::string& value) {
            static const std::regex iso(R"(\d{4}-\d{2}-\d{2})");
            const std::string error =
                "must be a real date YYYY-MM-DD from 1970-01-01 to "
                "9999-12-31, got '" +
                value + "'";
            if (!std::regex_match(value, iso)) {
              return error;
            }
            // Digits only (the pattern above): parse_whole cannot fail here.
            const auto part = [&value](std::size_t at, std::size_t size) {
              return static_cast<int>(toolkit::parse_whole(value.substr(at, size)).value_or(0));
            };
            const int year = part(0, 4);
            const int month = part(5, 2);
            const int day = part(8, 2);
            const int days[12] = {31, leap_year(year) ? 29 : 28, 31, 30, 31, 30, 31, 31, 30, 31, 30,
                                  31};
            if (year < 1970 || month < 1 || month > 12 || day < 1 || day > days[month - 1]) {
              return error;
            }
            return std::string{};
          },
          "DATE"));
}

/// One JSON object on stdout. Strings that are not UTF-8 (e.g. a file name) come out with
/// U+FFFD instead of throwing.
inline void print_json(const json& object) {
  std::cout << object.dump(2, ' ', false, json::error_handler_t::replace) << '\n';
}

/// The path of the first number in `value` that is not finite, or "" if there is none.
inline std::string non_finite_at(const json& value, const std::string& path) {
  if (value.is_number_float() && !std::isfinite(value.get<double>())) {
    return path;
  }
  if (value.is_object()) {
    for (const auto& [key, item] : value.items()) {
      const std::string at = non_finite_at(item, path.empty() ? key : path + "." + key);
      if (!at.empty()) {
        return at;
      }
    }
  } else if (value.is_array()) {
    for (std::size_t i = 0; i < value.size(); ++i) {
      const std::string at = non_finite_at(value[i], path + "[" + std::to_string(i) + "]");
      if (!at.empty()) {
        return at;
      }
    }
  }
  return {};
}

/// Refuses a result with a NaN or infinity in it: nothing is printed that is not a number.
inline void require_finite(const json& result, const std::string& inputs) {
  const std::string at = non_finite_at(result, "");
  if (!at.empty()) {
    throw InputError(inputs, 0, at,
                     "the result is not a finite number: the inputs are too extreme to use");
  }
}

/// Reads a number and refuses it when its size is beyond anything the quantity can be.
inline double bounded_number(const CsvTable& table, std::size_t row, std::size_t column,
                             double limit, const char* unit) {
  const double value = table.number(row, column);
  if (std::fabs(value) > limit) {
    table.fail(row, column,
               fmt::format("absurd magnitude {:g}: must be at most {} {} in size", value,
                           bound_text(limit), unit));
  }
  return value;
}

inline std::string line_span(const CsvTable& table) {
  if (table.rows.empty()) {
    return table.file;
  }
  return table.file + ":" + std::to_string(table.rows.front().line) + "-" +
         std::to_string(table.rows.back().line);
}

/// Too few data rows: the error points at the line after the header / last row.
[[noreturn]] inline void too_few(const CsvTable& table, std::size_t need, const std::string& what) {
  const std::size_t line = table.rows.empty() ? 1 : table.rows.back().line;
  throw InputError(table.file, line, table.columns.front(),
                   "too few " + what + ": " + std::to_string(table.rows.size()) +
                       ", need at least " + std::to_string(need));
}

inline void print_number(const char* name, double value, const char* unit = "") {
  const double shown = value == 0.0 ? 0.0 : value;  // never "-0"
  std::printf("%-26s %.6g%s%s\n", name, shown, *unit != '\0' ? " " : "", unit);
}

// ---------------------------------------------------------------- umbmark

struct UmbmarkOptions {
  double side_mm = 0.0;
  double wheelbase_mm = 0.0;
  std::string cw_file, ccw_file, date;
  bool json = false;
  bool exact = false;
};

struct AccuracyOptions {
  std::string file, baseline, date;
  bool json = false;
};

struct LateralOptions {
  std::string file, date;
  double length_mm = 0.0, wheelbase_mm = 0.0, dl_mm = 0.0, dr_mm = 0.0, theta_l_rad = 0.0;
  bool json = false;
};

struct BootstrapOptions {
  std::string training_file, unknowns_file, date, interval = "percentile";
  std::uint32_t replicates = 2000;
  std::uint64_t seed = 1;
  double level = 0.95;
  double wheelbase_mm = 0.0, dl_mm = 0.0, dr_mm = 0.0;
  bool json = false;
};

struct Ros2Options {
  std::string from_file, controller = "diff_drive_controller";
  std::optional<double> c_l, c_r, e_b;
  // Covariances from `odocal fit`'s noise (see fit_noise.hpp, ros2_covariance).
  double speed_mps = 0.2;
  RosVelocityEstimate velocity;  ///< the controller's velocity estimate (its defaults)
  double pose_distance_m = 1.0;
};

/// Largest multiplier `odocal ros2` writes: a factor of 10 corrects no real robot.
constexpr double ros2_max_multiplier = 10.0;
/// What `odocal ros2` accepts as a multiplier, for messages.
inline std::string multiplier_allowed() {
  return toolkit::range_text(0.0, ros2_max_multiplier, "", toolkit::LowBound::open);
}

// One file per command (host_sim/src/cli/<name>_command.cpp).
void run_umbmark(const UmbmarkOptions& o);
void run_accuracy(const AccuracyOptions& o);
void run_lateral(const LateralOptions& o);
void run_bootstrap(const BootstrapOptions& o);
void run_ros2(const Ros2Options& o);

}  // namespace odocal::host::calib_cli
