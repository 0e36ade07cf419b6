// Runs the real `odocal` binary: JSON keys of every calibration command, the paper's Tables 3
// and 4 through `odocal accuracy`, determinism of `odocal bootstrap`, and exit status 2 with a
// message naming file, line and field for each kind of bad input.
#include <sys/wait.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace {

using nlohmann::json;

struct Result {
  int status = -1;
  std::string out;
  std::string err;
};

std::string data(const std::string& name) {
  return std::string(ODOCAL_CLI_DATA_DIR) + "/" + name;
}

Result odocal(const std::string& args) {
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

json parse_json(const Result& r) {
  EXPECT_EQ(r.status, 0) << r.err;
  json doc = json::parse(r.out, nullptr, false);
  EXPECT_FALSE(doc.is_discarded()) << r.out;
  EXPECT_TRUE(doc.is_object());
  return doc;
}

void expect_bad_input(const Result& r, const std::string& file, const std::string& line,
                      const std::string& field) {
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_NE(r.err.find(file + ":" + line), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("field '" + field + "'"), std::string::npos) << r.err;
}

void expect_no_nan(const json& value) {
  if (value.is_number_float()) {
    EXPECT_TRUE(std::isfinite(value.get<double>()));
  }
  for (const auto& item : value) {
    if (value.is_structured()) {
      expect_no_nan(item);
    }
  }
}

const std::string umbmark_args = "umbmark --side-mm 4000 --wheelbase-mm 340 --json";

TEST(CliUmbmark, JsonHasEveryContractKeyAndProvenance) {
  for (const std::string exact : {"", " --exact"}) {
    const json doc =
        parse_json(odocal(umbmark_args + exact + " --date 2026-03-01 --cw " +
                          data("umbmark_cw.csv") + " --ccw " + data("umbmark_ccw.csv")));
    for (const char* key :
         {"x_cg_cw", "y_cg_cw", "x_cg_ccw", "y_cg_ccw", "r_cg_cw", "r_cg_ccw", "e_max_syst_mm",
          "alpha_deg", "beta_deg", "radius_mm", "e_d", "e_b", "c_l", "c_r", "wheelbase_new_mm",
          "sem_mm", "second_pass_recommended"}) {
      EXPECT_TRUE(doc.contains(key)) << key;
    }
    EXPECT_TRUE(doc["second_pass_recommended"].is_boolean());
    const json& p = doc["provenance"];
    EXPECT_EQ(p["method"], exact.empty() ? "umbmark" : "umbmark-exact");
    EXPECT_EQ(p["runs"], 10);
    EXPECT_EQ(p["date"], "2026-03-01");
    EXPECT_TRUE(p["interval"].is_null());
    expect_no_nan(doc);
    // The fixture was made with E_d = 1.0025, E_b = 1.012 and 15 mm run scatter (σ/√5 ≈ 7 mm
    // on a 4 m square: ~1e-4 in E_d, ~3e-4 in E_b).
    EXPECT_NEAR(doc["e_d"].get<double>(), 1.0025, 3e-4);
    EXPECT_NEAR(doc["e_b"].get<double>(), 1.012, 1e-3);
    EXPECT_NEAR(doc["c_l"].get<double>() + doc["c_r"].get<double>(), 2.0, 1e-12);
  }
}

TEST(CliUmbmark, TextOutputAndNoDateMeansToday) {
  const Result text = odocal("umbmark --side-mm 4000 --wheelbase-mm 340 --cw " +
                             data("umbmark_cw.csv") + " --ccw " + data("umbmark_ccw.csv"));
  EXPECT_EQ(text.status, 0);
  EXPECT_NE(text.out.find("E_d"), std::string::npos);
  const json doc = parse_json(odocal(umbmark_args + " --cw " + data("umbmark_cw.csv") + " --ccw " +
                                     data("umbmark_ccw.csv")));
  EXPECT_EQ(doc["provenance"]["date"].get<std::string>().size(), 10u);
}

TEST(CliUmbmark, BadInputExitsTwoNamingFileLineField) {
  const auto run = [](const std::string& cw) {
    return odocal(umbmark_args + " --cw " + data(cw) + " --ccw " + data("umbmark_ccw.csv"));
  };
  expect_bad_input(run("bad_no_header.csv"), "bad_no_header.csv", "1", "x_mm");
  expect_bad_input(run("bad_non_number.csv"), "bad_non_number.csv", "3", "y_mm");
  expect_bad_input(run("bad_one_run.csv"), "bad_one_run.csv", "2", "x_mm");
  expect_bad_input(run("bad_nan.csv"), "bad_nan.csv", "3", "x_mm");
  expect_bad_input(run("bad_inf.csv"), "bad_inf.csv", "3", "y_mm");
  expect_bad_input(run("bad_absurd.csv"), "bad_absurd.csv", "4", "x_mm");
  expect_bad_input(run("bad_field_count.csv"), "bad_field_count.csv", "3", "y_mm");
  const Result missing = run("no_such_file.csv");
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("no_such_file.csv"), std::string::npos);
  const Result bad_flag = odocal("umbmark --side-mm -4 --wheelbase-mm 340 --cw " +
                                 data("umbmark_cw.csv") + " --ccw " + data("umbmark_ccw.csv"));
  EXPECT_EQ(bad_flag.status, 2);
  EXPECT_NE(bad_flag.err.find("--side-mm"), std::string::npos) << bad_flag.err;
}

// Maddahi & Zareinia Tables 3 and 4 through the program, to the printed precision.
TEST(CliAccuracy, ReproducesTables3And4) {
  struct Expected {
    const char* file;
    double rms[3];
    double improvement[3];
  };
  for (const Expected& e :
       {Expected{"table3_systematic.csv", {57.5, 11.0, 7.1}, {0.0, 80.9, 87.6}},
        Expected{"table4_bumps.csv", {3995.3, 742.8, 476.7}, {0.0, 81.4, 88.1}}}) {
    const json doc = parse_json(odocal("accuracy --json --baseline NC " + data(e.file)));
    const json& s = doc["scenarios"];
    ASSERT_EQ(s.size(), 3u);
    const char* names[3] = {"NC", "CL", "CB"};
    for (int i = 0; i < 3; ++i) {
      EXPECT_EQ(s[i]["name"], names[i]);
      EXPECT_EQ(s[i]["trials"], 5);
      EXPECT_NEAR(s[i]["rms_mm"].get<double>(), e.rms[i], 0.05) << e.file << " " << names[i];
      EXPECT_NEAR(s[i]["improvement_pct"].get<double>(), e.improvement[i], 0.05)
          << e.file << " " << names[i];
    }
    EXPECT_EQ(doc["provenance"]["runs"], 15);
  }
  const Result text = odocal("accuracy " + data("table3_systematic.csv"));
  EXPECT_EQ(text.status, 0);
  EXPECT_NE(text.out.find("87.6"), std::string::npos) << text.out;
}

TEST(CliAccuracy, BadInput) {
  expect_bad_input(odocal("accuracy --json " + data("accuracy_bad.csv")), "accuracy_bad.csv", "3",
                   "y_mm");
  expect_bad_input(odocal("accuracy " + data("bad_one_run.csv")), "bad_one_run.csv", "1",
                   "scenario");
  const Result no_baseline = odocal("accuracy --baseline XX " + data("table3_systematic.csv"));
  EXPECT_EQ(no_baseline.status, 2);
  EXPECT_NE(no_baseline.err.find("XX"), std::string::npos);
}

const std::string lateral_args =
    "lateral --length-mm 1000 --wheelbase-mm 150 --dl-mm 60 --dr-mm 60 --json --trials ";

TEST(CliLateral, JsonKeysAndDirection) {
  const json doc = parse_json(odocal(lateral_args + data("lateral_trials.csv")));
  // The fixture drifts ~22 mm left and stops ~15 mm short on a 1 m line:
  // F_lat ≈ 1 + 2·atan(0.022)·150/1000 = 1.0066, F_lon ≈ 1000/985 = 1.015.
  EXPECT_NEAR(doc["f_lat"].get<double>(), 1.0066, 1.5e-3);
  EXPECT_NEAR(doc["f_lon"].get<double>(), 1.0152, 1.5e-3);
  EXPECT_EQ(doc["provenance"]["method"], "maddahi-eq4-eq5");
  EXPECT_EQ(doc["provenance"]["runs"], 10);
}

TEST(CliLateral, BadInput) {
  expect_bad_input(odocal(lateral_args + data("lateral_absurd.csv")), "lateral_absurd.csv", "3",
                   "x_mm");
  expect_bad_input(odocal(lateral_args + data("bad_one_run.csv")), "bad_one_run.csv", "2", "x_mm");
  expect_bad_input(odocal(lateral_args + data("lateral_nan.csv")), "lateral_nan.csv", "3", "y_mm");
}

const std::string bootstrap_args = "bootstrap --json --b 2000 --seed 7 --date 2026-03-01";

TEST(CliBootstrap, JsonKeysDeterminismAndProvenance) {
  const std::string files = " --training " + data("bootstrap_training.csv") + " --unknowns " +
                            data("bootstrap_unknowns.csv");
  const Result first = odocal(bootstrap_args + files);
  const Result second = odocal(bootstrap_args + files);
  EXPECT_EQ(first.out, second.out);  // same seed, same bytes
  const json doc = parse_json(first);
  ASSERT_EQ(doc["unknowns"].size(), 5u);
  for (const json& u : doc["unknowns"]) {
    for (const char* key : {"lr_l", "lr_r", "boot_l", "boot_r", "ci_l", "ci_r", "r_l", "r_r"}) {
      EXPECT_TRUE(u.contains(key)) << key;
    }
    ASSERT_EQ(u["ci_l"].size(), 2u);
    EXPECT_LT(u["ci_l"][0].get<double>(), u["boot_l"].get<double>());
    EXPECT_GT(u["ci_l"][1].get<double>(), u["boot_l"].get<double>());
    EXPECT_NEAR(u["r_l"].get<double>(), u["boot_l"].get<double>() / u["lr_l"].get<double>(), 1e-12);
  }
  const json& p = doc["provenance"];
  // DESIGN: the percentile interval at the chosen level, unless --interval calibrated.
  EXPECT_EQ(p["interval"], "percentile");
  EXPECT_EQ(p["level"], 0.95);
  EXPECT_EQ(p["effective_level"], 0.95);
  EXPECT_EQ(p["seed"], 7);
  EXPECT_EQ(p["replicates"], 2000);
  expect_no_nan(doc);
  const Result other_seed = odocal("bootstrap --json --b 2000 --seed 8" + files);
  EXPECT_NE(parse_json(other_seed)["unknowns"][0]["boot_l"], doc["unknowns"][0]["boot_l"]);
  // With the geometry, eq. 7 factors per unknown: the fixture's left wheel runs 1.5 % slow.
  const json factors = parse_json(odocal(bootstrap_args + files +
                                         " --interval calibrated --wheelbase-mm 150 --dl-mm 60 "
                                         "--dr-mm 60"));
  EXPECT_EQ(factors["provenance"]["interval"], "percentile-t-calibrated");
  // t_34 widening (m = 20): 2Φ(t_34,0.975) − 1 ≈ 0.958, and the interval is wider.
  EXPECT_NEAR(factors["provenance"]["effective_level"].get<double>(), 0.958, 1e-3);
  const json& plain = doc["unknowns"][0];
  const json& wide = factors["unknowns"][0];
  EXPECT_GT(wide["ci_l"][1].get<double>() - wide["ci_l"][0].get<double>(),
            plain["ci_l"][1].get<double>() - plain["ci_l"][0].get<double>());
  for (const json& u : factors["unknowns"]) {
    EXPECT_NEAR(u["factors_lr"]["f_lat"].get<double>(), 0.985, 0.01);
    EXPECT_NEAR(u["factors_lr"]["f_lon"].get<double>(), 1.0, 0.01);
  }
}

TEST(CliBootstrap, BadInput) {
  const std::string unknowns = " --unknowns " + data("bootstrap_unknowns.csv");
  expect_bad_input(
      odocal(bootstrap_args + " --training " + data("bootstrap_training_few.csv") + unknowns),
      "bootstrap_training_few.csv", "4", "xdot");
  const Result degenerate = odocal(bootstrap_args + " --training " +
                                   data("bootstrap_training_degenerate.csv") + unknowns);
  expect_bad_input(degenerate, "bootstrap_training_degenerate.csv", "2-9", "ydot");
  EXPECT_NE(degenerate.err.find("degenerate"), std::string::npos);
  expect_bad_input(odocal(bootstrap_args + " --training " + data("bad_no_header.csv") + unknowns),
                   "bad_no_header.csv", "1", "xdot");
  const Result b_too_small =
      odocal("bootstrap --b 5 --training " + data("bootstrap_training.csv") + unknowns);
  EXPECT_EQ(b_too_small.status, 2);
  EXPECT_NE(b_too_small.err.find("--b"), std::string::npos) << b_too_small.err;
}

TEST(CliRos2, FromUmbmarkJsonAndFromFlags) {
  const std::string json_file = ::testing::TempDir() + "odocal_cli_umbmark.json";
  const Result u = odocal(umbmark_args + " --cw " + data("umbmark_cw.csv") + " --ccw " +
                          data("umbmark_ccw.csv"));
  ASSERT_EQ(u.status, 0);
  std::ofstream(json_file) << u.out;
  const json doc = json::parse(u.out);
  const Result yaml = odocal("ros2 --from " + json_file);
  ASSERT_EQ(yaml.status, 0) << yaml.err;
  EXPECT_NE(yaml.out.find("diff_drive_controller:\n  ros__parameters:\n"), std::string::npos);
  const auto value_of = [&](const std::string& key) {
    const auto at = yaml.out.find(key + ": ");
    EXPECT_NE(at, std::string::npos) << key;
    return std::stod(yaml.out.substr(at + key.size() + 2));
  };
  EXPECT_NEAR(value_of("wheel_separation_multiplier"), doc["e_b"].get<double>(), 1e-8);
  EXPECT_NEAR(value_of("left_wheel_radius_multiplier"), doc["c_l"].get<double>(), 1e-8);
  EXPECT_NEAR(value_of("right_wheel_radius_multiplier"), doc["c_r"].get<double>(), 1e-8);
  const Result flags = odocal("ros2 --c-l 0.99 --c-r 1.01 --e-b 1.02 --controller base");
  EXPECT_EQ(flags.status, 0);
  EXPECT_NE(flags.out.find("base:\n  ros__parameters:\n    wheel_separation_multiplier: 1.02\n"),
            std::string::npos)
      << flags.out;
}

TEST(CliRos2, BadInput) {
  const Result bad_json = odocal("ros2 --from " + data("ros2_bad.json"));
  EXPECT_EQ(bad_json.status, 2);
  EXPECT_NE(bad_json.err.find("ros2_bad.json:4"), std::string::npos) << bad_json.err;
  const Result missing = odocal("ros2 --from " + data("ros2_missing_key.json"));
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("field 'e_b'"), std::string::npos) << missing.err;
  EXPECT_EQ(odocal("ros2 --c-l 0.99").status, 2);
  EXPECT_EQ(odocal("ros2 --from x.json --c-l 0.99").status, 2);
}

// ------------------------------------------------------------------ review findings

std::string temp_file(const std::string& name, const std::string& bytes) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A spreadsheet export: UTF-8 byte order mark before the header, CRLF line ends. Same figures as
// the plain file.
TEST(CliCsv, ByteOrderMarkAndCrlfAreAccepted) {
  const auto exported = [](const std::string& name) {
    std::string crlf = "\xEF\xBB\xBF";
    for (const char c : read_text(data(name))) {
      crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    }
    return temp_file("bom_" + name, crlf);
  };
  const json plain = parse_json(odocal(umbmark_args + " --cw " + data("umbmark_cw.csv") +
                                       " --ccw " + data("umbmark_ccw.csv")));
  const json bom = parse_json(odocal(umbmark_args + " --cw " + exported("umbmark_cw.csv") +
                                     " --ccw " + exported("umbmark_ccw.csv")));
  EXPECT_EQ(bom["e_d"], plain["e_d"]);
  EXPECT_EQ(bom["e_b"], plain["e_b"]);
  const std::string accuracy_bom = temp_file(
      "bom_accuracy.csv", "\xEF\xBB\xBFscenario,trial,x_mm,y_mm\r\nNC,1,3,4\r\nCL,1,0,1\r\n");
  const json accuracy = parse_json(odocal("accuracy --json " + accuracy_bom));
  EXPECT_EQ(accuracy["scenarios"][0]["name"], "NC");
  EXPECT_NEAR(accuracy["scenarios"][1]["improvement_pct"].get<double>(), 80.0, 1e-9);
  // A BOM anywhere but the start of line 1 is still junk.
  expect_bad_input(
      odocal("accuracy " +
             temp_file("bom_late.csv", "scenario,trial,x_mm,y_mm\n\xEF\xBB\xBFNC,1,3,4\n")),
      "bom_late.csv", "2", "scenario");
}

// ROS 2 declares the multipliers as doubles: every value must read back as a float (a '.' or an
// exponent), and as exactly the double odocal computed.
TEST(CliRos2, ValuesAreFloatLiteralsThatRoundTrip) {
  const auto values = [](const Result& yaml) {
    std::vector<std::string> out;
    for (const std::string key : {"wheel_separation_multiplier", "left_wheel_radius_multiplier",
                                  "right_wheel_radius_multiplier"}) {
      const auto at = yaml.out.find("    " + key + ": ");
      EXPECT_NE(at, std::string::npos) << key;
      const auto start = at + key.size() + 6;
      out.push_back(yaml.out.substr(start, yaml.out.find('\n', start) - start));
    }
    return out;
  };
  const Result ones = odocal("ros2 --c-l 1 --c-r 2 --e-b 1.000000000000000222");
  ASSERT_EQ(ones.status, 0) << ones.err;
  const std::vector<std::string> text = values(ones);
  const double expected[3] = {1.000000000000000222, 1.0, 2.0};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NE(text[i].find_first_of(".eE"), std::string::npos) << text[i];
    EXPECT_EQ(std::stod(text[i]), expected[i]) << text[i];
  }
  const std::string json_file = ::testing::TempDir() + "odocal_cli_umbmark_rt.json";
  const Result u = odocal(umbmark_args + " --cw " + data("umbmark_cw.csv") + " --ccw " +
                          data("umbmark_ccw.csv"));
  ASSERT_EQ(u.status, 0);
  std::ofstream(json_file) << u.out;
  const json doc = json::parse(u.out);
  const std::vector<std::string> from = values(odocal("ros2 --from " + json_file));
  EXPECT_EQ(std::stod(from[0]), doc["e_b"].get<double>());
  EXPECT_EQ(std::stod(from[1]), doc["c_l"].get<double>());
  EXPECT_EQ(std::stod(from[2]), doc["c_r"].get<double>());
}

TEST(CliRos2, ControllerNameAndMultipliersAreValidated) {
  const std::string values = "ros2 --c-l 0.99 --c-r 1.01 --e-b 1.02 --controller ";
  EXPECT_EQ(odocal(values + "_base_2").status, 0);
  for (const std::string bad : {"'a b'", "2base", "''", "'base:'", "'x\ny'", "base-1"}) {
    const Result r = odocal(values + bad);
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_TRUE(r.out.empty()) << r.out;
    EXPECT_NE(r.err.find("--controller"), std::string::npos) << r.err;
  }
  for (const std::string bad : {"--c-l 0", "--c-l nan", "--c-r inf", "--e-b 11", "--e-b 1x"}) {
    const Result r = odocal("ros2 --c-l 1 --c-r 1 --e-b 1 " + bad);
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_NE(r.err.find(bad.substr(0, 5)), std::string::npos) << r.err;
  }
  const std::string zero = temp_file("ros2_zero.json", R"({"c_l": 0, "c_r": 1, "e_b": 1})");
  const Result r = odocal("ros2 --from " + zero);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("field 'c_l'"), std::string::npos) << r.err;
}

// Errors of 1e155 mm overflow x² + y²; scenario names that are not text break the JSON.
TEST(CliAccuracy, AbsurdErrorsAndNonAsciiNamesAreRefused) {
  expect_bad_input(odocal("accuracy --json " + data("accuracy_huge.csv")), "accuracy_huge.csv", "4",
                   "x_mm");
  const std::string bad_name = temp_file("accuracy_not_utf8.csv",
                                         "scenario,trial,x_mm,y_mm\nNC,1,1,1\nN\xFF"
                                         "C,1,2,2\n");
  const Result r = odocal("accuracy --json " + bad_name);
  expect_bad_input(r, "accuracy_not_utf8.csv", "3", "scenario");
  EXPECT_NE(r.err.find("ASCII"), std::string::npos) << r.err;
}

// A baseline RMS of 0 leaves the improvement undefined: null in JSON, n/a in text, never 0.
TEST(CliAccuracy, ZeroBaselineHasNoImprovementInJsonOrText) {
  const json doc = parse_json(odocal("accuracy --json " + data("accuracy_zero_baseline.csv")));
  ASSERT_EQ(doc["scenarios"].size(), 2u);
  EXPECT_EQ(doc["scenarios"][0]["rms_mm"], 0.0);
  EXPECT_NEAR(doc["scenarios"][1]["rms_mm"].get<double>(), std::sqrt(12.5), 1e-12);
  for (const json& s : doc["scenarios"]) {
    EXPECT_TRUE(s["improvement_pct"].is_null());
  }
  const Result text = odocal("accuracy " + data("accuracy_zero_baseline.csv"));
  EXPECT_EQ(text.status, 0);
  EXPECT_NE(text.out.find("n/a"), std::string::npos) << text.out;
  EXPECT_EQ(text.out.find("0.0 \n"), std::string::npos) << text.out;
}

// Every command-line number: a finite decimal within human bounds, else exit 2 naming the flag,
// with a short message (no 300-digit bounds) and nothing on stdout.
TEST(CliFlags, NumbersAreFiniteAndBounded) {
  const std::string umbmark_files =
      " --cw " + data("umbmark_cw.csv") + " --ccw " + data("umbmark_ccw.csv");
  const std::string umbmark = "umbmark" + umbmark_files;
  const std::string lateral_files = " --trials " + data("lateral_trials.csv");
  const std::string lateral_ok = "--length-mm 1000 --wheelbase-mm 150 --dl-mm 60 --dr-mm 60";
  const std::string bootstrap = "bootstrap --training " + data("bootstrap_training.csv") +
                                " --unknowns " + data("bootstrap_unknowns.csv");
  struct Case {
    std::string args;
    std::string flag;
  };
  const Case cases[] = {
      {umbmark + " --wheelbase-mm 340 --side-mm nan", "--side-mm"},
      {umbmark + " --wheelbase-mm 340 --side-mm 4000x", "--side-mm"},
      {umbmark + " --wheelbase-mm 340 --side-mm 0x10", "--side-mm"},
      {umbmark + " --wheelbase-mm 340 --side-mm 1e400", "--side-mm"},
      {umbmark + " --side-mm 4000 --wheelbase-mm inf", "--wheelbase-mm"},
      {umbmark + " --side-mm 4000 --wheelbase-mm 0", "--wheelbase-mm"},
      {"lateral" + lateral_files + " --wheelbase-mm 150 --dl-mm 60 --dr-mm 60 --length-mm -1",
       "--length-mm"},
      {"lateral" + lateral_files + " --length-mm 1000 --wheelbase-mm 150 --dr-mm 60 --dl-mm nan",
       "--dl-mm"},
      {"lateral" + lateral_files + " --length-mm 1000 --wheelbase-mm 150 --dl-mm 60 --dr-mm 1e9",
       "--dr-mm"},
      {"lateral" + lateral_files + " " + lateral_ok + " --theta-l-rad 1e-300", "--theta-l-rad"},
      {"lateral" + lateral_files + " " + lateral_ok + " --theta-l-rad 1910", "--theta-l-rad"},
      {"lateral" + lateral_files + " " + lateral_ok + " --theta-l-rad -1", "--theta-l-rad"},
      {bootstrap + " --level 0", "--level"},
      {bootstrap + " --level 1", "--level"},
      {bootstrap + " --level nan", "--level"},
      {bootstrap + " --b 0", "--b"},
      {bootstrap + " --b 99", "--b"},
      {bootstrap + " --b 1000001", "--b"},
      {bootstrap + " --b 2e3", "--b"},
      {bootstrap + " --seed -1", "--seed"},
      {bootstrap + " --seed 18446744073709551616", "--seed"},
      {bootstrap + " --seed 1.5", "--seed"},
      {bootstrap + " --wheelbase-mm 150 --dl-mm 60 --dr-mm nan", "--dr-mm"},
      {bootstrap + " --dl-mm 60", "--wheelbase-mm"},
      {bootstrap + " --date 2020-13-45", "--date"},
      {bootstrap + " --date 2021-02-29", "--date"},
      {bootstrap + " --date 2021-04-31", "--date"},
      {bootstrap + " --date 2021-1-01", "--date"},
      {"accuracy " + data("table3_systematic.csv") + " --date 0000-00-00", "--date"},
  };
  for (const Case& c : cases) {
    const Result r = odocal(c.args);
    EXPECT_EQ(r.status, 2) << c.args << "\n" << r.err;
    EXPECT_TRUE(r.out.empty()) << c.args << "\n" << r.out;
    EXPECT_NE(r.err.find(c.flag), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_LT(r.err.size(), 400u) << r.err;
  }
  // The edges that are allowed.
  EXPECT_EQ(odocal(bootstrap + " --seed 18446744073709551615 --b 100 --level 0.5 --date "
                               "2024-02-29")
                .status,
            0);
  EXPECT_EQ(odocal("lateral" + lateral_files + " " + lateral_ok + " --theta-l-rad 34").status, 0);
}

// β = 0 exactly: the legs are straight, the radius infinite. JSON has no infinity: null; the
// angles are 0, never −0.
TEST(CliUmbmark, StraightLegsHaveNoRadiusAndNoNegativeZero) {
  const std::string files =
      " --cw " + data("umbmark_zero.csv") + " --ccw " + data("umbmark_zero.csv");
  for (const std::string exact : {"", " --exact"}) {
    const Result r = odocal(umbmark_args + exact + files);
    const json doc = parse_json(r);
    EXPECT_TRUE(doc["radius_mm"].is_null());
    EXPECT_EQ(doc["beta_deg"], 0.0);
    EXPECT_EQ(doc["alpha_deg"], 0.0);
    EXPECT_FALSE(std::signbit(doc["beta_deg"].get<double>()));
    EXPECT_FALSE(std::signbit(doc["alpha_deg"].get<double>()));
    EXPECT_EQ(r.out.find("-0.0"), std::string::npos) << r.out;
    EXPECT_EQ(doc["e_d"], 1.0);
    const Result text = odocal("umbmark --side-mm 4000 --wheelbase-mm 340" + exact + files);
    EXPECT_EQ(text.status, 0);
    EXPECT_NE(text.out.find("inf"), std::string::npos) << text.out;
    EXPECT_EQ(text.out.find("-0 "), std::string::npos) << text.out;
  }
  // With a curvature the radius is a number: R = (L/2)/sin(β/2).
  const json curved = parse_json(odocal(umbmark_args + " --cw " + data("umbmark_cw.csv") +
                                        " --ccw " + data("umbmark_ccw.csv")));
  const double beta_rad = curved["beta_deg"].get<double>() * M_PI / 180.0;
  EXPECT_NEAR(curved["radius_mm"].get<double>(), 2000.0 / std::sin(beta_rad / 2.0), 1e-6);
}

TEST(CliBootstrap, AbsurdTrainingValuesAreRefusedByLineAndField) {
  const Result r = odocal(bootstrap_args + " --training " + data("bootstrap_training_absurd.csv") +
                          " --unknowns " + data("bootstrap_unknowns.csv"));
  expect_bad_input(r, "bootstrap_training_absurd.csv", "6", "xdot");
  EXPECT_EQ(r.err.find("degenerate"), std::string::npos) << r.err;
}

// An unknown standing still: its LR estimates are 0, so r = boot/lr is undefined (null), and
// its eq. 7 factors too; every other field is a number and the other unknowns are unaffected.
TEST(CliBootstrap, UnknownAtRestHasNullRatiosOnly) {
  const std::string files = " --training " + data("bootstrap_training.csv") + " --unknowns " +
                            data("bootstrap_unknowns_at_rest.csv");
  const json doc =
      parse_json(odocal(bootstrap_args + files + " --wheelbase-mm 150 --dl-mm 60 --dr-mm 60"));
  ASSERT_EQ(doc["unknowns"].size(), 2u);
  const json& rest = doc["unknowns"][0];
  EXPECT_TRUE(rest["r_l"].is_null());
  EXPECT_TRUE(rest["r_r"].is_null());
  EXPECT_TRUE(rest["factors_lr"].is_null());
  EXPECT_EQ(rest["lr_l"], 0.0);
  for (const char* key : {"lr_r", "boot_l", "boot_r"}) {
    EXPECT_TRUE(rest[key].is_number()) << key;
  }
  EXPECT_TRUE(rest["ci_l"][0].is_number());
  const json& moving = doc["unknowns"][1];
  EXPECT_NEAR(moving["r_l"].get<double>(),
              moving["boot_l"].get<double>() / moving["lr_l"].get<double>(), 1e-12);
  EXPECT_TRUE(moving["factors_lr"].is_object());
  expect_no_nan(doc);
  const Result text = odocal("bootstrap" + files);
  EXPECT_EQ(text.status, 0) << text.err;
  EXPECT_NE(text.out.find("n/a"), std::string::npos) << text.out;
}

}  // namespace

// ------------------------------------------------------------------ issue 14: strict host input

void expect_refused(const Result& r, const std::string& where, const std::string& words) {
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_NE(r.err.find(where), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(words), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("json.exception"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("basic_filebuf"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("bad_alloc"), std::string::npos) << r.err;
}

// A hand-edited key given twice used to go through with the last value (exit 0).
TEST(CliJson, DuplicateKeysAreRefusedInEveryObject) {
  const Result top = odocal(
      "ros2 --from " +
      temp_file("dup_top.json", "{\"c_l\": 1.0,\n \"c_r\": 1.0,\n \"e_b\": 1.0,\n \"c_l\": 1.5}"));
  expect_refused(top, "dup_top.json:4: field 'c_l'", "more than once");
  const Result nested =
      odocal("ros2 --from " + temp_file("dup_nested.json",
                                        "{\"c_l\": 1, \"c_r\": 1, \"e_b\": 1,\n \"provenance\": "
                                        "{\"runs\": 5,\n \"runs\": 6}}"));
  expect_refused(nested, "dup_nested.json:3: field 'runs'", "more than once");
  // The same key in two different objects is not a duplicate.
  const Result separate =
      odocal("ros2 --from " +
             temp_file("dup_separate.json",
                       "{\"c_l\": 1, \"c_r\": 1, \"e_b\": 1, \"x\": [{\"a\": 1}, {\"a\": 2}]}"));
  EXPECT_EQ(separate.status, 0) << separate.err;
}

TEST(CliJson, OverflowNulAndDirectoryAreNamedInPlainWords) {
  expect_refused(
      odocal("ros2 --from " + temp_file("huge.json", "{\"c_l\": 1,\n \"c_r\": 1e400, \"e_b\": 1}")),
      "huge.json:2: field 'c_r'", "out of range");
  expect_refused(
      odocal("ros2 --from " + temp_file("nul.json", std::string("{\"c_l\": 1,\n \"c_r\": 1") +
                                                        '\0' + ", \"e_b\": 1}")),
      "nul.json:2", "NUL byte");
  expect_refused(odocal("ros2 --from " + ::testing::TempDir()), ::testing::TempDir(),
                 "is a directory");
}

TEST(CliCsv, DirectoryNulAndOverflowAreNamed) {
  const std::string ccw = " --ccw " + data("umbmark_ccw.csv");
  expect_refused(odocal(umbmark_args + " --cw " + ::testing::TempDir() + ccw), ::testing::TempDir(),
                 "is a directory");
  // The message goes on past the NUL byte (it used to end where the byte was printed).
  const Result nul =
      odocal(umbmark_args + " --cw " +
             temp_file("nul.csv", std::string("x_mm,y_mm\n1,2\n3,") + '\0' + "4\n") + ccw);
  expect_refused(nul, "nul.csv:3: field 'y_mm'", "contains a NUL byte");
  EXPECT_EQ(nul.err.find('\0'), std::string::npos);
  const Result huge =
      odocal(umbmark_args + " --cw " + temp_file("huge.csv", "x_mm,y_mm\n1e400,2\n3,4\n") + ccw);
  expect_refused(huge, "huge.csv:2: field 'x_mm'", "out of range");
  EXPECT_EQ(huge.err.find("not a number"), std::string::npos) << huge.err;
}

// Old Mac exports end lines with a bare CR, as the robot's console accepts: same figures as LF.
TEST(CliCsv, CarriageReturnLineEndsAreLines) {
  std::string cr;
  for (const char c : read_text(data("umbmark_cw.csv"))) {
    cr += c == '\n' ? '\r' : c;
  }
  const json plain = parse_json(odocal(umbmark_args + " --cw " + data("umbmark_cw.csv") +
                                       " --ccw " + data("umbmark_ccw.csv")));
  const json mac = parse_json(odocal(umbmark_args + " --cw " + temp_file("cr_cw.csv", cr) +
                                     " --ccw " + data("umbmark_ccw.csv")));
  EXPECT_EQ(mac["e_d"], plain["e_d"]);
  EXPECT_EQ(mac["e_b"], plain["e_b"]);
}

// 1e-310 is a (subnormal) number: it is taken, and only a range check may refuse it.
TEST(CliCsv, SubnormalIsANumber) {
  const Result tiny = odocal(umbmark_args + " --cw " +
                             temp_file("tiny.csv", "x_mm,y_mm\n1e-310,2\n3,4\n5,1\n2,2\n4,3\n") +
                             " --ccw " + data("umbmark_ccw.csv"));
  EXPECT_EQ(tiny.status, 0) << tiny.err;
  EXPECT_EQ(tiny.err.find("not a number"), std::string::npos) << tiny.err;
}

TEST(CliLateral, TooManyTrialsSaysTheLimit) {
  std::string trials = "x_mm,y_mm\n";
  for (int i = 0; i < 1025; ++i) {
    trials += std::to_string(990 + i % 7) + "," + std::to_string(i % 5) + "\n";
  }
  const Result r = odocal(
      "lateral --length-mm 1000 --wheelbase-mm 150 --dl-mm 60 --dr-mm 60 "
      "--trials " +
      temp_file("lateral_1025.csv", trials));
  expect_refused(r, "lateral_1025.csv:1026: field 'x_mm'", "too many trials");
  EXPECT_NE(r.err.find("1024"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("too few"), std::string::npos) << r.err;
}

// B predictions per unknown are kept for the percentiles: 2000 unknowns at B = 10^6 would need
// 32 GB. The work is bounded (10^7 predictions) and the message says what fits.
TEST(CliBootstrap, HugeWorkIsRefusedBeforeAllocating) {
  std::string unknowns = "xdot,ydot,thetadot\n";
  for (int i = 0; i < 2000; ++i) {
    unknowns += "0.3,0.01,0.01\n";
  }
  const Result r = odocal("bootstrap --b 1000000 --training " + data("bootstrap_training.csv") +
                          " --unknowns " + temp_file("unknowns_2000.csv", unknowns));
  expect_refused(r, "unknowns_2000.csv:12: field 'xdot'", "at most 10 unknowns with this --b");
}

// ------------------------------------------------------------------ odocal-sim input

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
