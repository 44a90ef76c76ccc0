// The `ringtol` executable as a user meets it: help, version, both commands on the
// shipped examples, JSON output, and clear errors before any work.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

namespace {

using ::testing::HasSubstr;

struct Outcome {
  int exit_code = -1;
  std::string out;
  std::string err;
};

Outcome Ringtol(const std::string& arguments) {
  // ctest runs tests in parallel processes: one capture file per test.
  const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  const std::filesystem::path err_file = std::filesystem::path(::testing::TempDir()) / ("ringtol_stderr_" + test + ".txt");
  const std::string command = std::string(RINGTOL_EXECUTABLE) + " " + arguments + " 2>" + err_file.string();
  Outcome run;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), static_cast<int>(buffer.size()), pipe) != nullptr) run.out += buffer.data();
  const int status = pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream err(err_file);
  std::stringstream text;
  text << err.rdbuf();
  run.err = text.str();
  return run;
}

std::string Example(const std::string& name) { return std::string(RINGTOL_SOURCE_DIR) + "/examples/paper/" + name; }

TEST(Cli, HelpListsEveryCommand) {
  const Outcome run = Ringtol("--help");
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_THAT(run.out, HasSubstr("simulate"));
  EXPECT_THAT(run.out, HasSubstr("sweep"));
}

TEST(Cli, VersionPrintsTheProjectVersion) {
  const Outcome run = Ringtol("--version");
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_THAT(run.out, HasSubstr("ringtol "));
}

TEST(Cli, EveryCommandHasHelp) {
  for (const char* command : {"simulate", "sweep"}) {
    const Outcome run = Ringtol(std::string(command) + " --help");
    EXPECT_EQ(run.exit_code, 0) << command;
    EXPECT_THAT(run.out, HasSubstr("--solver")) << command;
    EXPECT_THAT(run.out, HasSubstr("--json")) << command;
  }
}

TEST(Cli, SimulateJsonHasEveryDocumentedKey) {
  const Outcome run = Ringtol("simulate " + Example("scene.toml") + " --json --steps 90");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  for (const char* key : {"solver", "status", "d_trajectory_mm", "dist_init_mm", "static_offset_mm", "runout_mm",
                          "min_contact_force_N", "steps"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["status"], "ok");
  EXPECT_EQ(j["solver"], "quasistatic");
  EXPECT_EQ(j["steps"], 90);
  // The nominal scene has no errors: the centre does not move.
  constexpr double kNoMotion = 1e-9;  // [mm] Newton tolerance 1e-12 m = 1e-9 mm
  EXPECT_NEAR(j["d_trajectory_mm"].get<double>(), 0.0, kNoMotion);
  EXPECT_NEAR(j["static_offset_mm"].get<double>(), 0.0, kNoMotion);
}

TEST(Cli, SweepPrintsOneObjectPerCaseWithItsName) {
  const Outcome run = Ringtol("sweep " + Example("orders.toml") + " --json --solver linear --steps 360");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json rows = nlohmann::json::parse(run.out);
  ASSERT_EQ(rows.size(), 13u);
  for (const nlohmann::json& row : rows) {
    EXPECT_TRUE(row.contains("case"));
    EXPECT_EQ(row["status"], "ok") << row.dump();
  }
}

TEST(Cli, SweepTableAndCsvOutput) {
  const std::filesystem::path csv = std::filesystem::path(::testing::TempDir()) / "ringtol_sweep.csv";
  const Outcome run = Ringtol("sweep " + Example("amplitudes.toml") + " --solver linear --steps 90 --csv " + csv.string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_THAT(run.out, HasSubstr("D_traj mm"));
  std::ifstream in(csv);
  std::string line;
  int lines = 0;
  while (std::getline(in, line)) ++lines;
  EXPECT_EQ(lines, 1 + 20);  // header + one row per case
}

TEST(Cli, TrajectoryCsvHasOneRowPerStep) {
  const std::filesystem::path csv = std::filesystem::path(::testing::TempDir()) / "ringtol_path.csv";
  const Outcome run = Ringtol("simulate " + Example("scene.toml") + " --steps 72 --trajectory " + csv.string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::ifstream in(csv);
  std::string header;
  std::getline(in, header);
  EXPECT_THAT(header, HasSubstr("psi_deg,x_mm,y_mm,sensor_mm"));
  int rows = 0;
  for (std::string line; std::getline(in, line);) ++rows;
  EXPECT_EQ(rows, 73);  // psi = 0, 5, ..., 360 deg
}

TEST(Cli, BadSceneIsAClearErrorNamingTheFile) {
  const std::filesystem::path scene = std::filesystem::path(::testing::TempDir()) / "ringtol_bad_scene.toml";
  std::ofstream(scene) << "[ring]\ninner_radius_mm = -302.0\n";
  const Outcome run = Ringtol("simulate " + scene.string());
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_THAT(run.err, HasSubstr("ringtol_bad_scene.toml"));
  EXPECT_TRUE(run.out.empty()) << run.out;
}

TEST(Cli, UnwritableOutputFailsBeforeAnyWork) {
  const Outcome run = Ringtol("simulate " + Example("scene.toml") + " --trajectory /nonexistent-dir/path.csv");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_THAT(run.err, HasSubstr("/nonexistent-dir/path.csv"));
  EXPECT_TRUE(run.out.empty()) << run.out;
}

TEST(Cli, UnknownSolverIsRejected) {
  const Outcome run = Ringtol("simulate " + Example("scene.toml") + " --solver magic");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_THAT(run.err, HasSubstr("magic"));
}

}  // namespace
