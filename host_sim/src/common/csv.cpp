#include "odocal/host/csv.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string_view>

#include "odocal/toolkit/numbers.hpp"

namespace odocal::host {
namespace {

std::string describe(const std::string& file, std::size_t line, const std::string& field,
                     const std::string& message) {
  std::ostringstream out;
  out << file;
  if (line > 0) {
    out << ':' << line;
  }
  out << ": ";
  if (!field.empty()) {
    out << "field '" << field << "': ";
  }
  out << message;
  // A control byte from the input (a NUL would end the message when printed, a CR would move the
  // cursor back over it) is shown as \xNN.
  std::string shown;
  for (const char c : out.str()) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20u || byte == 0x7Fu) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02X", static_cast<unsigned>(byte));
      shown += escaped;
    } else {
      shown += c;
    }
  }
  return shown;
}

std::string trim(const std::string& text) {
  return std::string(toolkit::trim(text));
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma - start)));
    if (comma == std::string::npos) {
      return fields;
    }
    start = comma + 1;
  }
}

std::string join(const std::vector<std::string>& parts) {
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    out += (i == 0 ? "" : ",") + parts[i];
  }
  return out;
}

}  // namespace

InputError::InputError(std::string file, std::size_t line, std::string field,
                       const std::string& message)
    : std::runtime_error(describe(file, line, field, message)),
      file_(std::move(file)),
      line_(line),
      field_(std::move(field)) {}

std::string read_text_file(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    throw InputError(path, 0, "", "is a directory, not a file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError(path, 0, "", "cannot open file");
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) {
    throw InputError(path, 0, "", "cannot read file");
  }
  return text.str();
}

const std::string& CsvTable::text(std::size_t row, std::size_t column) const {
  return rows.at(row).fields.at(column);
}

double CsvTable::number(std::size_t row, std::size_t column) const {
  const std::string& field = text(row, column);
  using toolkit::NumberText;
  double value = 0.0;
  const NumberText kind = toolkit::read_number(field, value);
  if (kind == NumberText::out_of_range) {
    fail(row, column, "number out of range (beyond +-1.8e308): '" + field + "'");
  }
  if (kind != NumberText::ok) {
    const std::string lower = [&] {
      std::string s;
      for (const char c : field) {
        s += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      }
      return s;
    }();
    const bool non_finite =
        lower.find("nan") != std::string::npos || lower.find("inf") != std::string::npos;
    if (field.empty()) {
      fail(row, column, "empty, expected a number");
    }
    fail(row, column, (non_finite ? "not a finite number: '" : "not a number: '") + field + "'");
  }
  return value;
}

void CsvTable::fail(std::size_t row, std::size_t column, const std::string& message) const {
  throw InputError(file, rows.at(row).line, columns.at(column), message);
}

CsvTable read_csv(const std::string& path, const std::vector<std::string>& columns) {
  const std::string text = read_text_file(path);
  CsvTable table;
  table.file = path;
  table.columns = columns;
  std::string line;
  std::size_t number = 0;
  bool have_header = false;
  std::size_t start = 0;
  while (start < text.size()) {
    // A line ends with LF, CRLF or a lone CR (old Mac exports), as on the robot's console.
    const std::size_t end = text.find_first_of("\r\n", start);
    line = text.substr(start, end == std::string::npos ? std::string::npos : end - start);
    start = end == std::string::npos                                              ? text.size()
            : text[end] == '\r' && end + 1 < text.size() && text[end + 1] == '\n' ? end + 2
                                                                                  : end + 1;
    ++number;
    const std::size_t nul = line.find('\0');
    if (nul != std::string::npos) {
      // Name the column the byte is in: commas before it count the fields.
      const auto commas = static_cast<std::size_t>(
          std::count(line.begin(), line.begin() + static_cast<std::ptrdiff_t>(nul), ','));
      throw InputError(path, number, commas < columns.size() ? columns[commas] : columns.back(),
                       "contains a NUL byte (a binary file, or a text file in UTF-16?)");
    }
    // A UTF-8 byte order mark (spreadsheet exports) is not part of the first header name.
    constexpr std::string_view bom = "\xEF\xBB\xBF";
    if (number == 1 && line.compare(0, bom.size(), bom) == 0) {
      line.erase(0, bom.size());
    }
    const std::string content = trim(line);
    if (content.empty() || content.front() == '#') {
      continue;
    }
    std::vector<std::string> fields = split(content);
    if (!have_header) {
      if (fields != columns) {
        // Name the first column that differs, so the message points at the mistake.
        std::size_t i = 0;
        while (i < fields.size() && i < columns.size() && fields[i] == columns[i]) {
          ++i;
        }
        const std::string expected = i < columns.size() ? columns[i] : "(end of header)";
        throw InputError(
            path, number, expected,
            "missing or wrong header: expected '" + join(columns) + "', got '" + content + "'");
      }
      have_header = true;
      continue;
    }
    if (fields.size() != columns.size()) {
      const std::size_t column = fields.size() < columns.size() ? fields.size() : columns.size();
      throw InputError(path, number, column < columns.size() ? columns[column] : columns.back(),
                       "expected " + std::to_string(columns.size()) + " fields, got " +
                           std::to_string(fields.size()));
    }
    table.rows.push_back(CsvRow{number, std::move(fields)});
  }
  if (!have_header) {
    throw InputError(path, number == 0 ? 1 : number, columns.empty() ? "" : columns.front(),
                     "missing header: expected '" + join(columns) + "'");
  }
  return table;
}

std::vector<std::vector<double>> read_numeric_csv(const std::string& path,
                                                  const std::vector<std::string>& columns) {
  const CsvTable table = read_csv(path, columns);
  std::vector<std::vector<double>> rows;
  rows.reserve(table.rows.size());
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    std::vector<double> values(columns.size());
    for (std::size_t c = 0; c < columns.size(); ++c) {
      values[c] = table.number(r, c);
    }
    rows.push_back(std::move(values));
  }
  return rows;
}

}  // namespace odocal::host
