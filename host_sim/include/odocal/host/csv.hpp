#pragma once
/// @file
/// Strict CSV input for the host programs: a fixed header, comma-separated fields, numbers parsed
/// whole and finite. Every error names the file, the line and the field.

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace odocal::host {

/// Bad input: thrown by the readers, caught by `odocal` (exit status 2).
/// what() reads "FILE:LINE: field 'NAME': MESSAGE" (line 0 and no field when the whole file is
/// at fault, e.g. it cannot be opened).
class InputError : public std::runtime_error {
 public:
  InputError(std::string file, std::size_t line, std::string field, const std::string& message);
  [[nodiscard]] const std::string& file() const { return file_; }
  [[nodiscard]] std::size_t line() const { return line_; }
  [[nodiscard]] const std::string& field() const { return field_; }

 private:
  std::string file_;
  std::size_t line_;
  std::string field_;
};

/// One data row: its 1-based line number in the file and its fields (trimmed of spaces).
struct CsvRow {
  std::size_t line = 0;
  std::vector<std::string> fields;
};

/// A read CSV file. Blank lines and lines starting with '#' are skipped; a UTF-8 byte order mark
/// at the start of the file and LF, CRLF or CR line ends are accepted; a NUL byte is refused.
struct CsvTable {
  std::string file;
  std::vector<std::string> columns;
  std::vector<CsvRow> rows;

  /// The field as text.
  [[nodiscard]] const std::string& text(std::size_t row, std::size_t column) const;
  /// The field as a finite number (toolkit::read_number: whole field, plain decimal); throws
  /// InputError.
  [[nodiscard]] double number(std::size_t row, std::size_t column) const;
  /// Throws InputError naming this row's line and the column's name.
  [[noreturn]] void fail(std::size_t row, std::size_t column, const std::string& message) const;
};

/// Reads `path`; its first non-blank line must be exactly `columns` (in order) and every row
/// must have that many fields. Throws InputError (cannot open, missing or wrong header, wrong
/// field count).
[[nodiscard]] CsvTable read_csv(const std::string& path, const std::vector<std::string>& columns);

/// Reads a CSV whose columns are all numbers; rows of doubles in column order.
[[nodiscard]] std::vector<std::vector<double>> read_numeric_csv(
    const std::string& path, const std::vector<std::string>& columns);

/// The whole contents of `path`. Throws InputError when it is a directory, cannot be opened or
/// cannot be read.
[[nodiscard]] std::string read_text_file(const std::string& path);

}  // namespace odocal::host
