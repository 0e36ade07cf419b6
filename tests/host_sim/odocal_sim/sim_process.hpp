#pragma once
// Running the odocal-sim program from a test: where it is, and files for its input.

#include <cstdlib>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace odocal::test {

/// The odocal-sim executable ctest passes in ODOCAL_BIN_DIR; "" when it is not built.
inline std::string sim_program() {
  const char* bin = std::getenv("ODOCAL_BIN_DIR");
  const std::string sim = bin != nullptr ? std::string(bin) + "/odocal-sim" : "";
  return sim.empty() || !std::ifstream(sim) ? std::string() : sim;
}

/// Writes `content` to a file of that name in the test's temporary directory; its path.
inline std::string temp_file(const std::string& name, const std::string& content) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << content;
  return path;
}

}  // namespace odocal::test
