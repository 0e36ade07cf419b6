#pragma once
// Running the odocal-sim program from a test: where it is, and files for its input.

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

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

/// Runs odocal-sim (in lockstep) with `args` on `script` (written to `name`_in.txt), and returns
/// its reply lines, not the `#` ones; `with_stderr` takes its stderr into them too. Expects exit 0.
inline std::vector<std::string> sim_replies(const std::string& name, const std::string& args,
                                            const std::string& script, bool with_stderr = false) {
  const std::string in = temp_file(name + "_in.txt", script);
  const std::string out = ::testing::TempDir() + name + "_out.txt";
  const int status = std::system(
      (sim_program() + " --speed 0 " + args + " <" + in + " >" + out + (with_stderr ? " 2>&1" : ""))
          .c_str());
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  std::vector<std::string> replies;
  std::ifstream o(out);
  for (std::string l; std::getline(o, l);) {
    if (!l.empty() && l[0] != '#') {
      replies.push_back(l);
    }
  }
  return replies;
}

}  // namespace odocal::test
