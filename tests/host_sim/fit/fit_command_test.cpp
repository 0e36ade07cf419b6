// `odocal fit` and the OR / CF scenarios of `odocal sim validate`, end to end through the program.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "odocal/host/fit.hpp"
#include "odocal/host/sim_procedures.hpp"

namespace odocal::host {
namespace {

std::string odocal_binary() {
  const char* bin = std::getenv("ODOCAL_BIN_DIR");
  const std::string odocal = bin != nullptr ? std::string(bin) + "/odocal" : "";
  return odocal.empty() || !std::ifstream(odocal) ? std::string() : odocal;
}

int run_command(const std::string& command, std::string& out, std::string& err) {
  // Per process: two test runs on one machine must not read each other's output.
  const std::string tag = std::to_string(::getpid());
  const std::string out_file = ::testing::TempDir() + "odocal_fit_out_" + tag + ".txt";
  const std::string err_file = ::testing::TempDir() + "odocal_fit_err_" + tag + ".txt";
  const int status = std::system((command + " >" + out_file + " 2>" + err_file).c_str());
  std::ifstream o(out_file);
  out.assign(std::istreambuf_iterator<char>(o), std::istreambuf_iterator<char>());
  std::ifstream e(err_file);
  err.assign(std::istreambuf_iterator<char>(e), std::istreambuf_iterator<char>());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// Drives lines and squares on the default simulated robot and writes their tape-measure logs.
std::vector<std::string> simulated_logs(int lines, int squares, const std::string& prefix) {
  SimulatedRobot robot(default_robot(), 3u);
  std::vector<std::string> files;
  for (int i = 0; i < lines + squares; ++i) {
    const drive::Path path =
        i < lines ? drive::make_line(2.0f) : drive::make_umbmark_square((i - lines) % 2 == 0, 1.5f);
    TickLog log;
    EXPECT_TRUE(run_path_logged(robot, path, log, LogTruth::end_only, 20u).completed);
    files.push_back(::testing::TempDir() + prefix + std::to_string(i) + ".csv");
    std::ofstream out(files.back());
    write_tick_log(log, out);
  }
  return files;
}

std::string join(const std::vector<std::string>& files, std::size_t from, std::size_t to) {
  std::string out;
  for (std::size_t i = from; i < to && i < files.size(); ++i) {
    out += " " + files[i];
  }
  return out;
}

TEST(OdocalFitCommand, FitsSimulatedTapeMeasureRunsAndScoresTheHoldout) {
  const std::string odocal = odocal_binary();
  if (odocal.empty()) {
    FAIL() << "odocal not built (cmake --build --preset host builds it)";
  }
  const std::vector<std::string> files = simulated_logs(5, 5, "fit_cmd_run");
  // Fit on 4 lines and 4 squares; hold out one line and one square.
  const std::string logs = join(files, 0, 4) + join(files, 5, 9);
  const std::string holdout = " " + files[4] + " " + files[9];
  const std::string geometry = " --wheel-diameter-mm 60 --wheelbase-mm 150 --counts-per-rev 1440";
  std::string out, err;
  ASSERT_EQ(run_command(odocal + " fit --log" + logs + " --holdout" + holdout + geometry +
                            " --b 200 --seed 4 --json",
                        out, err),
            0)
      << err;
  const nlohmann::json j = nlohmann::json::parse(out);
  for (const char* key : {"wheel_diameter_left_mm", "wheel_diameter_right_mm", "wheelbase_mm",
                          "c_l", "c_r", "e_d", "e_b"}) {
    ASSERT_TRUE(j.at(key).is_number()) << key;
  }
  // The default robot: D_L 59.91, D_R 60.03, b 151.5 mm. Eight end measurements (2 mm, 0.4°)
  // and the slip of ~30 m of travel pin the sizes to a few 1e-4 and the wheelbase to ~1e-3.
  EXPECT_NEAR(j["e_d"].get<double>(), 60.03 / 59.91, 3e-4);
  EXPECT_NEAR(j["wheelbase_mm"].get<double>(), 151.5, 0.5);
  EXPECT_NEAR(j["c_l"].get<double>(), j["wheel_diameter_left_mm"].get<double>() / 60.0, 1e-12);
  EXPECT_NEAR(j["e_b"].get<double>(), j["wheelbase_mm"].get<double>() / 150.0, 1e-12);
  for (const char* key : {"wheel_diameter_left_mm", "wheel_diameter_right_mm", "wheelbase_mm"}) {
    const nlohmann::json& ci = j["ci"][key];
    ASSERT_EQ(ci.size(), 2u) << key;
    EXPECT_LE(ci[0].get<double>(), j[key].get<double>()) << key;
    EXPECT_GE(ci[1].get<double>(), j[key].get<double>()) << key;
  }
  // Eight runs measured at their end in x, y and heading: the heading weighed by the noise of
  // each, estimated apart; the simulator's small, even noise leaves nothing to warn about.
  EXPECT_EQ(j.at("weighting").at("method"), "estimated") << j["weighting"].dump();
  EXPECT_EQ(j.at("weighting").at("runs").get<int>(), 8);
  EXPECT_DOUBLE_EQ(j.at("heading_length_mm").get<double>(),
                   j["weighting"]["heading_length_mm"].get<double>());
  ASSERT_TRUE(j.at("warnings").is_array());
  EXPECT_TRUE(j["warnings"].empty()) << j["warnings"].dump();
  for (const char* block : {"fit", "holdout"}) {
    const nlohmann::json& f = j[block];
    EXPECT_EQ(f["runs"].get<int>(), std::string(block) == "fit" ? 8 : 2);
    // Uncorrected, the 1 % wheelbase error turns every square by 4° too little.
    EXPECT_GT(f["end_rms_before_mm"].get<double>(), 50.0) << block;
    EXPECT_LT(f["end_rms_after_mm"].get<double>(), 0.3 * f["end_rms_before_mm"].get<double>())
        << block;
    EXPECT_NEAR(f["path_rms_after_mm"].get<double>(), f["end_rms_after_mm"].get<double>(), 1e-9);
  }
  // Same seed, same output; no holdout: null.
  std::string again;
  ASSERT_EQ(run_command(odocal + " fit --log" + logs + " --holdout" + holdout + geometry +
                            " --b 200 --seed 4 --json",
                        again, err),
            0);
  EXPECT_EQ(out, again);
  ASSERT_EQ(run_command(odocal + " fit --log" + logs + geometry + " --b 0 --json", out, err), 0);
  EXPECT_TRUE(nlohmann::json::parse(out)["holdout"].is_null());
  // Text output.
  ASSERT_EQ(run_command(odocal + " fit --log" + logs + geometry + " --b 100", out, err), 0);
  EXPECT_NE(out.find("wheelbase_mm"), std::string::npos);
  EXPECT_NE(out.find("95 % interval"), std::string::npos);
}

TEST(OdocalFitCommand, RefusalsAndBadInputExitTwoNamingWhatIsWrong) {
  const std::string odocal = odocal_binary();
  if (odocal.empty()) {
    FAIL() << "odocal not built (cmake --build --preset host builds it)";
  }
  const std::vector<std::string> files = simulated_logs(3, 4, "fit_cmd_bad");
  const std::string geometry = " --wheel-diameter-mm 60 --wheelbase-mm 150 --counts-per-rev 1440";
  std::string out, err;
  EXPECT_EQ(run_command(odocal + " fit --log" + join(files, 0, 3) + geometry, out, err), 2);
  EXPECT_NE(err.find("wheelbase_mm"), std::string::npos) << err;
  EXPECT_TRUE(out.empty());
  EXPECT_EQ(run_command(odocal + " fit --log" + join(files, 3, 7) + geometry, out, err), 2);
  EXPECT_NE(err.find("scale"), std::string::npos) << err;
  EXPECT_NE(err.find("closed loops measured only at the end"), std::string::npos) << err;
  // A bad log names file, line and field.
  const std::string bad = ::testing::TempDir() + "fit_cmd_bad.csv";
  std::ofstream(bad) << "t_s,count_l,count_r,x_mm,y_mm,theta_deg\n0,0,0,,,\n0.1,5,abc,1,0,0\n";
  EXPECT_EQ(run_command(odocal + " fit --log " + bad + geometry, out, err), 2);
  EXPECT_NE(err.find(bad + ":3: field 'count_r'"), std::string::npos) << err;
  // Flags are strict and bounded.
  const char* flags[] = {"--wheel-diameter-mm nan",
                         "--wheelbase-mm 0",
                         "--counts-per-rev -5",
                         "--b 1e3",
                         "--level 1",
                         "--seed -1",
                         "--b 100001"};
  for (const char* flag : flags) {
    const std::string base = std::string(
                                 " --wheel-diameter-mm 60 --wheelbase-mm 150 "
                                 "--counts-per-rev 1440 ") +
                             flag;
    EXPECT_EQ(run_command(odocal + " fit --log " + files[0] + base, out, err), 2) << flag;
    const std::string name = std::string(flag).substr(0, std::string(flag).find(' '));
    EXPECT_NE(err.find(name), std::string::npos) << flag << ": " << err;
  }
  EXPECT_EQ(run_command(odocal + " fit" + geometry, out, err), 2);  // no --log
}

TEST(SimValidate, OracleAndRecommendedCalibrationBesideThePapersScenarios) {
  const std::string odocal = odocal_binary();
  if (odocal.empty()) {
    FAIL() << "odocal not built (cmake --build --preset host builds it)";
  }
  std::string out, err;
  ASSERT_EQ(run_command(odocal + " sim validate --json --replicates 200 --seed 2", out, err), 0)
      << err;
  const nlohmann::json j = nlohmann::json::parse(out);
  for (const char* floor : {"systematic", "bumps"}) {
    std::map<std::string, double> rms;
    for (const nlohmann::json& s : j[floor]["scenarios"]) {
      rms[s["name"].get<std::string>()] = s["rms_mm"].get<double>();
    }
    ASSERT_EQ(rms.size(), 5u) << floor;
    for (const char* name : {"NC", "CL", "CB", "OR", "CF"}) {
      EXPECT_EQ(rms.count(name), 1u) << floor << " " << name;
    }
    ASSERT_TRUE(j[floor].contains("cf")) << floor;
    if (std::string(floor) == "systematic") {
      // Smooth floor: NC carries the default robot's 0.2 % wheel mismatch (~160 mm at the END);
      // the true geometry leaves slip and the 2 mm measurement (a few mm), and the fit is close.
      EXPECT_GT(rms["NC"], 100.0);
      EXPECT_LT(rms["OR"], 20.0);
      EXPECT_LT(rms["CF"], 25.0);
      // The fitted geometry is the default robot's within the fit's precision.
      EXPECT_NEAR(j[floor]["cf"]["wheelbase_mm"].get<double>(), 151.5, 0.5);
    } else {
      // Over the cables each wheel loses 2.6 % of its ground travel: the true geometry does not
      // know that, the fit (made on this floor) does.
      EXPECT_LT(rms["CF"], 0.5 * rms["OR"]);
    }
  }
  // The CF squares' robot time is counted: 20 + 20 straight trials, 2 × 4 squares of 2 m, and 25
  // unseen-path runs of ~10 m per floor take well over 1500 s at 0.1-0.3 m/s.
  EXPECT_GT(j["simulated_s"].get<double>(), 1500.0);
}

}  // namespace
}  // namespace odocal::host
