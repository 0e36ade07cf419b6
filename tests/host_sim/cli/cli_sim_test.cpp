// `odocal-sim`'s scripted input: a store in a missing directory, over-long lines, endless input
// without line ends.
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "cli_process.hpp"

namespace {

using namespace cli_test;

Result odocal_sim(const std::string& args, const std::string& input_file,
                  const std::string& shell_prefix = "") {
  const char* bin_env = std::getenv("ODOCAL_BIN_DIR");
  const std::string bin =
      (bin_env != nullptr ? bin_env : ODOCAL_CLI_BIN_DIR) + std::string("/odocal-sim");
  const std::string out_file = ::testing::TempDir() + "odocal_sim_stdout.txt";
  const std::string err_file = ::testing::TempDir() + "odocal_sim_stderr.txt";
  Result r;
  const int raw = std::system((shell_prefix + bin + " --speed 0 " + args + " <" + input_file +
                               " >" + out_file + " 2>" + err_file)
                                  .c_str());
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.out = read_text(out_file);
  r.err = read_text(err_file);
  return r;
}

TEST(CliSim, StoreInAMissingDirectoryIsRefusedAtStart) {
  const Result r = odocal_sim("--store " + ::testing::TempDir() + "no_such_dir/store.bin",
                              temp_file("sim_version.txt", "version\n"));
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(r.out.empty()) << r.out;  // refused before the console answered anything
  EXPECT_NE(r.err.find("no_such_dir"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("does not exist"), std::string::npos) << r.err;
}

// A 4 MB line without a line end took 30 s (each read rescanned the whole buffer) and held all
// of it in memory. It is refused whole, as on a terminal, and the next line is answered.
TEST(CliSim, OverLongScriptedLinesAreRefusedInLinearTime) {
  const std::string input =
      temp_file("sim_long_line.txt", std::string(4u << 20, 'a') + "\nversion\n");
  const auto start = std::chrono::steady_clock::now();
  const Result r = odocal_sim("", input);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out.rfind("err line_too_long ", 0), 0u) << r.out.substr(0, 200);
  EXPECT_NE(r.out.find("\nok name=odocal version="), std::string::npos) << r.out.substr(0, 200);
  // Linear: a few hundred ns per byte; the quadratic reader needed ~30 s.
  EXPECT_LT(seconds, 5.0);
}

// Endless input without a line end (/dev/zero) runs in constant memory: 64 MB of NUL bytes under
// a 32 MB address-space limit (the program needs under 16 MB; the old reader kept all of it).
TEST(CliSim, InputWithoutLineEndsUsesConstantMemory) {
  const std::string input = ::testing::TempDir() + "sim_zeros.txt";
  {
    std::ofstream out(input, std::ios::binary);
    const std::string zeros(1u << 20, '\0');
    for (int i = 0; i < 64; ++i) {
      out << zeros;
    }
    out << "\nversion\n";
  }
  const Result r = odocal_sim("", input, "ulimit -v 32768; exec ");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out.rfind("err non_ascii ", 0), 0u) << r.out.substr(0, 200);
  EXPECT_NE(r.out.find("\nok name=odocal version="), std::string::npos) << r.out.substr(0, 200);
}

}  // namespace
