// Tick logs (DESIGN "Tick log"): reading and checking.

#include <cmath>
#include <cstdio>
#include <fstream>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include "odocal/host/csv.hpp"
#include "odocal/host/fit.hpp"

namespace odocal::host {
namespace {

const std::vector<std::string> counts_only = {"t_s", "count_l", "count_r"};
const std::vector<std::string> with_truth = {"t_s",  "count_l", "count_r",
                                             "x_mm", "y_mm",    "theta_deg"};

// Magnitudes beyond these are no real log: a clock past the year 5000 (UNIX time, as public
// data sets stamp their rows, is about 1.7e9 s; nanoseconds are not seconds), a log longer than a
// year, 2^50 counts, 1000 km, a million turns.
constexpr double max_clock_s = 1e11;
constexpr double max_span_s = 3.2e7;
constexpr double max_count = 1.1e15;
constexpr double max_position_mm = 1e9;
constexpr double max_heading_deg = 3.6e8;

std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) {
    return {};
  }
  return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
}

/// The header line's column names (the first line that is neither blank nor a '#' comment).
std::vector<std::string> header_of(const std::string& path, std::size_t& line_number) {
  std::ifstream in(path);
  if (!in) {
    throw InputError(path, 0, "", "cannot open file");
  }
  std::string line;
  line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    constexpr std::string_view bom = "\xEF\xBB\xBF";
    if (line_number == 1 && line.compare(0, bom.size(), bom) == 0) {
      line.erase(0, bom.size());
    }
    const std::string content = trim(line);
    if (content.empty() || content.front() == '#') {
      continue;
    }
    std::vector<std::string> names;
    std::size_t start = 0;
    while (true) {
      const auto comma = content.find(',', start);
      names.push_back(trim(content.substr(start, comma - start)));
      if (comma == std::string::npos) {
        return names;
      }
      start = comma + 1;
    }
  }
  throw InputError(path, line_number == 0 ? 1 : line_number, "t_s",
                   "missing header: expected 't_s,count_l,count_r' or "
                   "'t_s,count_l,count_r,x_mm,y_mm,theta_deg'");
}

[[noreturn]] void fail_row(const TickLog& log, const TickRow& row, const char* field,
                           const std::string& message) {
  throw InputError(log.source, row.line, field, message);
}

void check_magnitude(const TickLog& log, const TickRow& row, const char* field, double value,
                     double limit) {
  if (!std::isfinite(value)) {
    fail_row(log, row, field, "not a finite number");
  }
  if (std::fabs(value) > limit) {
    char text[96];
    std::snprintf(text, sizeof text, "absurd magnitude %g (at most %g)", value, limit);
    fail_row(log, row, field, text);
  }
}

}  // namespace

void check_tick_log(const TickLog& log) {
  if (log.rows.size() < 2) {
    throw InputError(log.source, log.rows.empty() ? 0 : log.rows.back().line, "t_s",
                     "too few rows: " + std::to_string(log.rows.size()) +
                         ", need at least 2 (counts at the start and at a measured instant)");
  }
  bool truth_after_start = false;
  for (std::size_t i = 0; i < log.rows.size(); ++i) {
    const TickRow& row = log.rows[i];
    if (std::isfinite(row.t_s) && std::fabs(row.t_s) > max_clock_s) {
      char text[160];
      std::snprintf(text, sizeof text,
                    "absurd magnitude %g (at most %g: t_s is in seconds, e.g. UNIX time; divide "
                    "nanosecond stamps by 1e9)",
                    row.t_s, max_clock_s);
      fail_row(log, row, "t_s", text);
    }
    check_magnitude(log, row, "t_s", row.t_s, max_clock_s);
    if (row.t_s - log.rows.front().t_s > max_span_s) {
      fail_row(log, row, "t_s", "absurd magnitude: the log spans more than a year");
    }
    check_magnitude(log, row, "count_l", row.count_l, max_count);
    check_magnitude(log, row, "count_r", row.count_r, max_count);
    if (row.has_xy) {
      check_magnitude(log, row, "x_mm", row.x_mm, max_position_mm);
      check_magnitude(log, row, "y_mm", row.y_mm, max_position_mm);
    }
    if (row.has_theta) {
      check_magnitude(log, row, "theta_deg", row.theta_deg, max_heading_deg);
    }
    // Time may repeat (loggers stamp at their own resolution) but never go back.
    if (i > 0 && row.t_s < log.rows[i - 1].t_s) {
      char text[128];
      std::snprintf(text, sizeof text,
                    "time goes backwards: %.9g after %.9g (rows must be in time order)", row.t_s,
                    log.rows[i - 1].t_s);
      fail_row(log, row, "t_s", text);
    }
    if (i > 0 && (row.has_xy || row.has_theta)) {
      truth_after_start = true;
    }
  }
  const TickRow& first = log.rows.front();
  if (first.has_xy != first.has_theta) {
    fail_row(log, first, first.has_xy ? "theta_deg" : "x_mm",
             "the first row's ground truth is the start pose: give x_mm, y_mm and theta_deg "
             "together, or leave all three empty (the run then starts at 0, 0, 0)");
  }
  if (!truth_after_start) {
    fail_row(log, log.rows.back(), "x_mm",
             "no ground truth after the first row: nothing to fit (a tape-measure run holds the "
             "measured stop point in its last row)");
  }
}

void write_tick_log(const TickLog& log, std::ostream& out) {
  const auto number = [](double value) {
    char text[40];
    std::snprintf(text, sizeof text, "%.17g", value);
    return std::string(text);
  };
  out << "t_s,count_l,count_r,x_mm,y_mm,theta_deg\n";
  for (const TickRow& row : log.rows) {
    out << number(row.t_s) << ',' << number(row.count_l) << ',' << number(row.count_r) << ','
        << (row.has_xy ? number(row.x_mm) : "") << ',' << (row.has_xy ? number(row.y_mm) : "")
        << ',' << (row.has_theta ? number(row.theta_deg) : "") << '\n';
  }
}

TickLog read_tick_log(const std::string& path) {
  std::size_t header_line = 0;
  const std::vector<std::string> names = header_of(path, header_line);
  const bool truth = names.size() > counts_only.size();
  const std::vector<std::string>& expected = truth ? with_truth : counts_only;
  for (std::size_t i = 0; i < names.size() || i < expected.size(); ++i) {
    if (i >= names.size() || i >= expected.size() || names[i] != expected[i]) {
      const std::string got = i < names.size() ? "'" + names[i] + "'" : "nothing";
      const std::string want = i < expected.size() ? "'" + expected[i] + "'" : "no more columns";
      throw InputError(path, header_line, i < names.size() ? names[i] : expected[i],
                       "unknown or misplaced column " + got + ": expected " + want +
                           " (header 't_s,count_l,count_r' with optional "
                           "',x_mm,y_mm,theta_deg')");
    }
  }
  const CsvTable table = read_csv(path, expected);
  TickLog log;
  log.source = path;
  log.rows.reserve(table.rows.size());
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    TickRow row;
    row.line = table.rows[r].line;
    row.t_s = table.number(r, 0);
    row.count_l = table.number(r, 1);
    row.count_r = table.number(r, 2);
    if (truth) {
      const bool x = !table.text(r, 3).empty();
      const bool y = !table.text(r, 4).empty();
      if (x != y) {
        table.fail(r, x ? 4 : 3, "x_mm and y_mm are measured together: both or neither empty");
      }
      if (x) {
        row.has_xy = true;
        row.x_mm = table.number(r, 3);
        row.y_mm = table.number(r, 4);
      }
      if (!table.text(r, 5).empty()) {
        row.has_theta = true;
        row.theta_deg = table.number(r, 5);
      }
    }
    log.rows.push_back(row);
  }
  if (log.rows.size() < 2) {
    throw InputError(path, log.rows.empty() ? header_line : log.rows.back().line, "t_s",
                     "too few rows: " + std::to_string(log.rows.size()) + ", need at least 2");
  }
  check_tick_log(log);
  return log;
}

}  // namespace odocal::host
