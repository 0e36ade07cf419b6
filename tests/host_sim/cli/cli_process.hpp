// Helpers of the `odocal` end-to-end tests: run the real binary, read its JSON, check how it
// refuses bad input.
#pragma once

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace cli_test {

using nlohmann::json;

/// What a run of a program gave: its exit status, stdout and stderr.
struct Result {
  int status = -1;
  std::string out;
  std::string err;
};

/// A file of tests/host_sim/cli/data.
inline std::string data(const std::string& name) {
  return std::string(ODOCAL_CLI_DATA_DIR) + "/" + name;
}

/// Runs `odocal ARGS` through the shell (stdout piped, stderr through a file).
inline Result odocal(const std::string& args) {
  const char* bin_env = std::getenv("ODOCAL_BIN_DIR");
  const std::string bin =
      (bin_env != nullptr ? bin_env : ODOCAL_CLI_BIN_DIR) + std::string("/odocal");
  const std::string err_file = ::testing::TempDir() + "odocal_cli_stderr.txt";
  const std::string command = bin + " " + args + " 2>" + err_file;
  Result r;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) {
    return r;
  }
  char buffer[4096];
  std::size_t n = 0;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) {
    r.out.append(buffer, n);
  }
  const int raw = pclose(pipe);
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::ifstream err(err_file);
  std::stringstream text;
  text << err.rdbuf();
  r.err = text.str();
  return r;
}

/// The run's stdout as one JSON object, failing the test when it exited non-zero or is none.
inline json parse_json(const Result& r) {
  EXPECT_EQ(r.status, 0) << r.err;
  json doc = json::parse(r.out, nullptr, false);
  EXPECT_FALSE(doc.is_discarded()) << r.out;
  EXPECT_TRUE(doc.is_object());
  return doc;
}

/// Exit 2, nothing on stdout, and a message naming `file:line` and the field.
inline void expect_bad_input(const Result& r, const std::string& file, const std::string& line,
                             const std::string& field) {
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_NE(r.err.find(file + ":" + line), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("field '" + field + "'"), std::string::npos) << r.err;
}

/// No float anywhere in `value` is NaN or infinite.
inline void expect_no_nan(const json& value) {
  if (value.is_number_float()) {
    EXPECT_TRUE(std::isfinite(value.get<double>()));
  }
  for (const auto& item : value) {
    if (value.is_structured()) {
      expect_no_nan(item);
    }
  }
}

inline const std::string umbmark_args = "umbmark --side-mm 4000 --wheelbase-mm 340 --json";

/// Writes `bytes` to a file in the test's temporary directory. @return its path.
inline std::string temp_file(const std::string& name, const std::string& bytes) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

/// The whole file, as bytes.
inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Exit 2, nothing on stdout, a message with `where` and `words`, and no library's own words.
inline void expect_refused(const Result& r, const std::string& where, const std::string& words) {
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_NE(r.err.find(where), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(words), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("json.exception"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("basic_filebuf"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("bad_alloc"), std::string::npos) << r.err;
}

}  // namespace cli_test
