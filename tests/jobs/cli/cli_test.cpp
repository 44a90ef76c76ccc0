// The `ringtol` executable as a user meets it: help, version, both commands on the
// shipped examples, JSON output, and clear errors before any work.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tests/support/shell.h"
#include "tests/support/text_files.h"

namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

using Outcome = ringtol::testing::ShellOutcome;

Outcome Ringtol(const std::string& arguments) {
  // ctest runs tests in parallel processes: one capture file per test.
  const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  const std::filesystem::path err_file = std::filesystem::path(::testing::TempDir()) / ("ringtol_stderr_" + test + ".txt");
  return ringtol::testing::RunShell(std::string(RINGTOL_EXECUTABLE) + " " + arguments, err_file);
}

std::string Example(const std::string& name) { return std::string(RINGTOL_SOURCE_DIR) + "/examples/paper/" + name; }

TEST(Cli, HelpListsEveryCommand) {
  const Outcome run = Ringtol("--help");
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_THAT(run.out, HasSubstr("simulate"));
  EXPECT_THAT(run.out, HasSubstr("sweep"));
  EXPECT_THAT(run.out, HasSubstr("report"));
  EXPECT_THAT(run.out, HasSubstr("verify"));
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
    EXPECT_THAT(run.out, HasSubstr("dynamic")) << command;
  }
  const Outcome campaign = Ringtol("campaign --help");
  EXPECT_EQ(campaign.exit_code, 0);
  for (const char* option : {"--out", "--resume", "--samples", "--seed", "--json", "--quiet", "--chunk", "--threads"}) {
    EXPECT_THAT(campaign.out, HasSubstr(option)) << option;
  }
  EXPECT_THAT(campaign.out, ::testing::Not(HasSubstr("--test-kill")));
  const Outcome bench = Ringtol("bench --help");
  EXPECT_EQ(bench.exit_code, 0);
  EXPECT_THAT(bench.out, HasSubstr("dynamics"));
  EXPECT_THAT(bench.out, HasSubstr("ladder"));
  for (const char* command : {"bench dynamics", "bench ladder"}) {
    const Outcome run = Ringtol(std::string(command) + " --help");
    EXPECT_EQ(run.exit_code, 0) << command;
    EXPECT_THAT(run.out, HasSubstr("Scene file")) << command;
  }
  for (const auto& [command, option] : {std::pair{"sample", "--scene"}, {"classes", "--toml"}, {"fit", "--orders"},
                                        {"report", "--estimator"}, {"verify", "--json"}}) {
    const Outcome run = Ringtol(std::string(command) + " --help");
    EXPECT_EQ(run.exit_code, 0) << command;
    EXPECT_THAT(run.out, HasSubstr(option)) << command;
  }
}

TEST(Cli, SampleWritesInputsAndASceneThatReplays) {
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir());
  const std::string csv = (dir / "ringtol_cli_inputs.csv").string(), scene = (dir / "ringtol_cli_sample3.toml").string();
  const Outcome run = Ringtol(std::string("sample ") + RINGTOL_SOURCE_DIR +
                              "/examples/tolerances/normal_waterjet.toml --samples 8 --csv " + csv +
                              " --index 3 --scene " + scene);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_THAT(run.out, HasSubstr("sobol, 8 samples"));
  std::ifstream inputs(csv);
  std::string header, line;
  std::getline(inputs, header);
  EXPECT_THAT(header, HasSubstr("ring.order2.amplitude_um"));
  int rows = 0;
  while (std::getline(inputs, line)) ++rows;
  EXPECT_EQ(rows, 8);
  const Outcome replay = Ringtol("simulate " + scene + " --solver linear --json");
  ASSERT_EQ(replay.exit_code, 0) << replay.err;
  EXPECT_EQ(nlohmann::json::parse(replay.out)["status"], "ok");
}

TEST(Cli, SampleRefusesABadDesignSizeBeforeAnyWork) {
  const Outcome run = Ringtol(std::string("sample ") + RINGTOL_SOURCE_DIR +
                              "/examples/tolerances/normal_waterjet.toml --samples 1000");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_THAT(run.err, HasSubstr("design.samples = 1000"));
  EXPECT_EQ(run.out, "");
  const Outcome nowhere = Ringtol(std::string("sample ") + RINGTOL_SOURCE_DIR +
                                  "/examples/tolerances/normal_waterjet.toml --index 0 --scene /nonexistent/s.toml");
  EXPECT_EQ(nowhere.exit_code, 1);
  EXPECT_THAT(nowhere.err, HasSubstr("/nonexistent/s.toml"));
  EXPECT_EQ(nowhere.out, "");
}

// The command line's own refusals exit 1 like every other bad input (docs/usage.md), not
// with CLI11's internal codes, and say which option and why.
TEST(Cli, OptionErrorsExitOneNamingTheOption) {
  const Outcome range = Ringtol("simulate " + Example("scene.toml") + " --steps -5");
  EXPECT_EQ(range.exit_code, 1);
  EXPECT_THAT(range.err, HasSubstr("--steps"));
  const Outcome unknown = Ringtol("simulate " + Example("scene.toml") + " --no-such-option");
  EXPECT_EQ(unknown.exit_code, 1);
  EXPECT_THAT(unknown.err, HasSubstr("--no-such-option"));
  const Outcome missing = Ringtol("simulate /nonexistent/scene.toml");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_THAT(missing.err, HasSubstr("/nonexistent/scene.toml"));
  EXPECT_EQ(Ringtol("").exit_code, 1);  // a command is required
}

// A step count the user gives must sample the fastest undulation more than twice a period:
// at 3 angles an order-3 ring reads as standing still (D_trajectory 0 against 0.55 mm).
TEST(Cli, SimulateAndSweepRefuseTooFewStepsForTheFastestUndulationNamingTheMinimum) {
  const Outcome three = Ringtol("simulate " + Example("order3.toml") + " --steps 3");
  EXPECT_EQ(three.exit_code, 1);
  EXPECT_THAT(three.err, AllOf(HasSubstr("--steps 3: too few for"), HasSubstr("order3.toml"), HasSubstr(">= 7"),
                               HasSubstr("the ring's order 3, 3 per revolution")));
  EXPECT_EQ(three.out, "");
  EXPECT_EQ(Ringtol("simulate " + Example("order3.toml") + " --steps 7").exit_code, 0);
  // The sweep's orders run to 20: 41 angles.
  const Outcome sweep = Ringtol("sweep " + Example("orders.toml") + " --solver linear --steps 40");
  EXPECT_EQ(sweep.exit_code, 1);
  EXPECT_THAT(sweep.err, AllOf(HasSubstr("--steps 40"), HasSubstr(">= 41"), HasSubstr("order 20")));
}

// A mistyped command is named with the one it most likely meant, at every level, and a
// missing one with the choices; neither is CLI11's bare "A subcommand is required".
TEST(Cli, AnUnknownCommandIsNamedWithTheNearestOne) {
  using ringtol::testing::ExitsWith;
  EXPECT_THAT(Ringtol("campagin"),
              ExitsWith(1, AllOf(HasSubstr("unknown command 'campagin'; did you mean 'campaign'?"),
                                 HasSubstr("allowed: simulate, sweep"))));
  EXPECT_THAT(Ringtol("bench campagin " + Example("scene.toml")),
              ExitsWith(1, AllOf(HasSubstr("unknown command 'bench campagin'; did you mean 'bench campaign'?"),
                                 HasSubstr("allowed: dynamics, ladder, allocate, campaign"))));
  EXPECT_THAT(Ringtol("xyz"),
              ExitsWith(1, AllOf(HasSubstr("unknown command 'xyz'; allowed:"), ::testing::Not(HasSubstr("mean")))));
  EXPECT_THAT(Ringtol(""), ExitsWith(1, HasSubstr("missing command: `ringtol COMMAND`; allowed: simulate")));
  EXPECT_THAT(Ringtol("bench"), ExitsWith(1, HasSubstr("missing command: `ringtol bench COMMAND`; allowed: dynamics")));
  EXPECT_THAT(Ringtol("--no-such-option"), ExitsWith(1, HasSubstr("unknown option '--no-such-option'")));
}

// --seed takes the campaign file's range, stated once (jobs/inputs/sampling_file.h): CLI11
// alone read -1 and 2^64 both as 2^64 - 1, and 0x10 as 16 (and --samples 016 as 14).
TEST(Cli, SeedOutsideTheFilesRangeIsRefusedNamingTheRange) {
  using ringtol::testing::ExitsWith;
  const std::string sample = std::string("sample ") + RINGTOL_SOURCE_DIR + "/examples/tolerances/normal_waterjet.toml";
  for (const char* seed : {"-1", "18446744073709551616", "9223372036854775808", "0x10", "1e3"}) {
    EXPECT_THAT(Ringtol(sample + " --seed " + seed),
                ExitsWith(1, AllOf(HasSubstr(std::string("--seed: ") + seed + ": not a decimal integer in range"),
                                   HasSubstr("allowed: an integer >= 0 and <= 9223372036854775807"))))
        << seed;
  }
  // --samples is decimal too: 016 is 16 samples, not 14.
  const Outcome sixteen = Ringtol(sample + " --samples 016 --seed 010");
  EXPECT_EQ(sixteen.exit_code, 0) << sixteen.err;
  EXPECT_THAT(sixteen.out, HasSubstr("16 samples, seed 10,"));
  EXPECT_THAT(Ringtol(sample + " --samples 0x10"), ExitsWith(1, HasSubstr("--samples: 0x10: not a decimal integer")));
  const Outcome largest = Ringtol(sample + " --samples 8 --seed 9223372036854775807");
  EXPECT_EQ(largest.exit_code, 0) << largest.err;
  EXPECT_THAT(largest.out, HasSubstr("seed 9223372036854775807"));
}

// Every integer option is read as decimal, as --seed and --samples are: CLI11 alone reads
// integers with base detection, "0360" as 240 and "0x10" as 16. Leading zeros are decimal;
// anything else is refused naming the option, the value and the allowed range.
TEST(Cli, EveryIntegerOptionIsReadAsDecimalAndRefusedOutsideItsRange) {
  using ringtol::testing::ExitsWith;
  const std::string source = RINGTOL_SOURCE_DIR;
  const std::string scene = Example("scene.toml"), campaign = source + "/examples/campaigns/default.toml";
  const std::string allocation = source + "/examples/allocation/default.toml";
  const std::string tolerances = source + "/examples/tolerances/normal_waterjet.toml";
  const std::string profile = source + "/examples/measured/ring_profile.csv";
  const std::string out = (std::filesystem::path(::testing::TempDir()) / "ringtol_decimal_options.h5").string();
  struct Option {
    std::string command;  // everything before the option
    std::string option;
    std::string allowed;  // the range the message states
  };
  const std::vector<Option> options = {
      {"simulate " + scene, "--steps", ">= 1 and <= 2000000"},
      {"sweep " + Example("orders.toml"), "--steps", ">= 1 and <= 2000000"},
      {"simulate " + scene, "--revolutions", ">= 0 and <= 2147483647"},
      {"sample " + tolerances + " --scene " + out, "--index", ">= 0 and <= 1099511627775"},
      {"sample " + tolerances, "--samples", ">= 1 and <= 1099511627776"},
      {"fit " + profile, "--orders", ">= 1 and <= 1000"},
      {"bench dynamics " + scene, "--orders", ">= 1 and <= 1000"},
      {"bench ladder " + scene, "--repeats", ">= 1 and <= 1000"},
      {"bench campaign " + campaign, "--samples", ">= 1 and <= 1099511627776"},
      {"bench campaign " + campaign, "--threads", ">= 0 and <= 4096"},
      {"bench allocate " + allocation, "--threads", ">= 0 and <= 4096"},
      {"campaign " + campaign + " --out " + out, "--samples", ">= 1 and <= 1099511627776"},
      {"campaign " + campaign + " --out " + out, "--chunk", ">= 0 and <= 1099511627776"},
      {"campaign " + campaign + " --out " + out, "--coordinator-computes", ">= -1 and <= 1"},
      {"allocate " + allocation + " --out " + out, "--threads", ">= 0 and <= 4096"},
      {"allocate " + allocation + " --out " + out, "--chunk", ">= 0 and <= 1099511627776"},
      {"report " + profile + " --out " + out, "--bootstrap", ">= 0 and <= 100000"},
      {"report " + profile + " --out " + out, "--screening-samples", ">= 16 and <= 1073741824"},
  };
  for (const Option& o : options) {
    const std::string allowed = "; allowed: an integer " + o.allowed;
    EXPECT_THAT(Ringtol(o.command + " " + o.option + " 0x10"),
                ExitsWith(1, HasSubstr(o.option + ": 0x10: not a decimal integer" + allowed)))
        << o.command << " " << o.option;
    EXPECT_THAT(Ringtol(o.command + " " + o.option + " 99999999999999999999"),
                ExitsWith(1, HasSubstr(o.option + ": 99999999999999999999: out of range" + allowed)))
        << o.command << " " << o.option;
  }
  EXPECT_THAT(Ringtol("campaign " + campaign + " --out " + out + " --threads 4097"),
              ExitsWith(1, HasSubstr("--threads: 4097: out of range; allowed: an integer >= 0 and <= 4096")));
  // Leading zeros are decimal: 0360 steps are 360, and sample 010 is the tenth after the first.
  const Outcome steps = Ringtol("simulate " + Example("order3.toml") + " --steps 0360 --json");
  ASSERT_EQ(steps.exit_code, 0) << steps.err;
  EXPECT_EQ(nlohmann::json::parse(steps.out).at("steps"), 360);
  const Outcome index = Ringtol("sample " + tolerances + " --index 010 --scene " + out + ".toml");
  ASSERT_EQ(index.exit_code, 0) << index.err;
  EXPECT_THAT(index.out, HasSubstr("sample 10 "));
}

// A value with a character no one can see is shown with it escaped, here a zero-width
// space after a solver's name.
TEST(Cli, OptionValuesShowInvisibleCharactersEscaped) {
  const Outcome run = Ringtol("simulate " + Example("scene.toml") + " --solver 'linear\xE2\x80\x8B'");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_THAT(run.err, HasSubstr("linear\\u200B not in"));
}

// --out naming a folder is a mistake to name, not a results file to resume.
TEST(Cli, CampaignOutNamingAFolderSaysSo) {
  const std::filesystem::path folder = std::filesystem::path(::testing::TempDir()) / "ringtol_out_folder";
  std::filesystem::create_directories(folder);
  const Outcome run = Ringtol(std::string("campaign ") + RINGTOL_SOURCE_DIR + "/examples/campaigns/default.toml --out " +
                              folder.string());
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_THAT(run.err, HasSubstr("--out names a folder"));
  EXPECT_THAT(run.err, ::testing::Not(HasSubstr("--resume")));
}

TEST(Cli, ClassesListsTheCatalogueAndItsSources) {
  const Outcome list = Ringtol("classes");
  EXPECT_EQ(list.exit_code, 0);
  EXPECT_THAT(list.out, HasSubstr("Normal, P0"));
  EXPECT_THAT(list.out, HasSubstr("waterjet"));
  // Each class by the diameters it covers (ISO's "over ... up to"), where its row count
  // said nothing a designer could use; a gap between rows shows.
  EXPECT_THAT(list.out, HasSubstr("ISO 492 normal tolerance class: over 2.5 up to 800 mm\n"));
  EXPECT_THAT(list.out, HasSubstr("ISO 492 tolerance class 2: over 2.5 up to 400 mm\n"));
  EXPECT_THAT(list.out, HasSubstr("IT7 of the centre-circle diameter: over 250 up to 400, over 500 up to 800 mm\n"));
  EXPECT_THAT(list.out, ::testing::Not(HasSubstr("rows)")));
  const Outcome toml = Ringtol("classes --toml");
  EXPECT_THAT(toml.out, HasSubstr("source = "));
}

TEST(Cli, FitPrintsTheHarmonicsOfTheExampleExport) {
  const Outcome run =
      Ringtol(std::string("fit ") + RINGTOL_SOURCE_DIR + "/examples/measured/ring_profile.csv --orders 10 --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json fit = nlohmann::json::parse(run.out);
  EXPECT_EQ(fit["harmonics"].size(), 10u);
  EXPECT_EQ(fit["harmonics"][1]["order"], 2);
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

// Round rollers: every revolution is the first, so the life values are the
// one-revolution ones; only the linear rung adds the every-revolution values.
TEST(Cli, SimulateReportsTheLifeOverRevolutions) {
  const Outcome linear = Ringtol("simulate " + Example("order3.toml") + " --json --solver linear --steps 360 --revolutions 3");
  ASSERT_EQ(linear.exit_code, 0) << linear.err;
  const nlohmann::json j = nlohmann::json::parse(linear.out);
  ASSERT_TRUE(j.contains("life")) << j.dump();
  const nlohmann::json& life = j["life"];
  EXPECT_EQ(life["status"], "ok");
  EXPECT_EQ(life["revolutions"], 3);
  for (const char* key : {"d_trajectory_mm", "runout_mm", "error_motion_total_mm", "error_motion_synchronous_mm",
                          "error_motion_asynchronous_mm", "error_motion_fundamental_mm"}) {
    EXPECT_TRUE(life["over_revolutions"].contains(key)) << key;
    EXPECT_TRUE(life["every_revolution"].contains(key)) << key;
  }
  EXPECT_NEAR(life["over_revolutions"]["d_trajectory_mm"].get<double>(), j["d_trajectory_mm"].get<double>(), 1e-9);
  EXPECT_NEAR(life["every_revolution"]["runout_mm"].get<double>(), j["runout_mm"].get<double>(), 1e-9);
  const Outcome exact = Ringtol("simulate " + Example("order3.toml") + " --solver quasistatic --steps 360 --revolutions 2");
  ASSERT_EQ(exact.exit_code, 0) << exact.err;
  EXPECT_THAT(exact.out, HasSubstr("error motion"));
  EXPECT_THAT(exact.out, ::testing::Not(HasSubstr("every")));
  const Outcome refused = Ringtol("simulate " + Example("order3.toml") + " --revolutions -1");
  EXPECT_NE(refused.exit_code, 0);
  EXPECT_THAT(refused.err, HasSubstr("--revolutions"));
}

// The order-3 example with an order-2 lobe of 14 um on each roller (rollers of one size),
// their phases geared together or not ([life] phase_locked_rollers).
std::filesystem::path LobedRollersScene(bool locked) {
  const std::filesystem::path scene =
      std::filesystem::path(::testing::TempDir()) / (locked ? "ringtol_locked_scene.toml" : "ringtol_free_scene.toml");
  std::ifstream in(Example("order3.toml"));
  std::stringstream read;
  read << in.rdbuf();
  std::string text = read.str();
  const std::string round = "harmonics = []";
  for (std::size_t at = text.find(round, text.find("[[rollers]]")); at != std::string::npos; at = text.find(round, at)) {
    text.replace(at, round.size(), "harmonics = [{ order = 2, amplitude_mm = 0.014, phase_deg = 45.0 }]");
  }
  std::ofstream(scene) << text << "\n[life]\nphase_locked_rollers = " << (locked ? "true" : "false") << "\n";
  return scene;
}

// The every-revolution column says which life it is: every phase of each roller, or the
// cycle after which phase-locked rollers repeat. The N-revolution values are the same.
TEST(Cli, SimulateSaysWhichLifeItsEveryRevolutionColumnIs) {
  const std::string options = " --solver linear --steps 360 --revolutions 5";
  const Outcome free = Ringtol("simulate " + LobedRollersScene(false).string() + options);
  const Outcome locked = Ringtol("simulate " + LobedRollersScene(true).string() + options);
  ASSERT_EQ(free.exit_code, 0) << free.err;
  ASSERT_EQ(locked.exit_code, 0) << locked.err;
  EXPECT_THAT(free.out, HasSubstr("every phase"));
  EXPECT_THAT(locked.out, HasSubstr("locked: cycle 5"));
  const Outcome free_json = Ringtol("simulate " + LobedRollersScene(false).string() + options + " --json");
  const Outcome locked_json = Ringtol("simulate " + LobedRollersScene(true).string() + options + " --json");
  ASSERT_EQ(free_json.exit_code, 0) << free_json.err;
  ASSERT_EQ(locked_json.exit_code, 0) << locked_json.err;
  const nlohmann::json a = nlohmann::json::parse(free_json.out)["life"];
  const nlohmann::json b = nlohmann::json::parse(locked_json.out)["life"];
  EXPECT_EQ(a["phase_locked_rollers"], false);
  EXPECT_EQ(a["cycle"], 0);
  EXPECT_EQ(b["phase_locked_rollers"], true);
  EXPECT_EQ(b["cycle"], 5);
  EXPECT_EQ(a["over_revolutions"], b["over_revolutions"]);
  // Every phase of three lobes of 14 um passes the one assembly's five revolutions by far
  // more than the linear rung's allowance.
  EXPECT_GT(a["every_revolution"]["d_trajectory_mm"].get<double>(),
            b["every_revolution"]["d_trajectory_mm"].get<double>() + 1e-3 * b["allowance_um"].get<double>());
}

// Every error-motion number says through which filter and over which revolutions it was
// read, and unfiltered is a choice the scene states: the rollers' order-2 lobes pass at
// about 120 undulations a revolution, which the default 50 UPR filter all but removes.
TEST(Cli, SimulateStatesTheErrorMotionFilterAndReadsUnfilteredWhereTheSceneSaysSo) {
  const std::filesystem::path filtered = LobedRollersScene(false);
  const std::filesystem::path unfiltered = std::filesystem::path(::testing::TempDir()) / "ringtol_unfiltered.toml";
  {
    std::ifstream in(filtered);
    std::stringstream read;
    read << in.rdbuf();
    std::string text = read.str();
    const std::size_t sensor = text.find("[sensor]\n");
    ASSERT_NE(sensor, std::string::npos);
    text.insert(sensor + 9, "error_motion_cutoff_upr = 0\n");
    std::ofstream(unfiltered) << text;
  }
  const std::string options = " --solver linear --steps 360 --revolutions 3 --json";
  const Outcome a = Ringtol("simulate " + filtered.string() + options);
  const Outcome b = Ringtol("simulate " + unfiltered.string() + options);
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const nlohmann::json with = nlohmann::json::parse(a.out)["life"];
  const nlohmann::json without = nlohmann::json::parse(b.out)["life"];
  EXPECT_EQ(with["error_motion_filter_cutoff_upr"], 50.0);
  EXPECT_THAT(with["over_revolutions"]["error_motion_reading"].get<std::string>(),
              AllOf(HasSubstr("Gaussian filter at 50 UPR"), HasSubstr("over 3 revolutions")));
  EXPECT_THAT(with["every_revolution"]["error_motion_reading"].get<std::string>(),
              AllOf(HasSubstr("Gaussian filter at 50 UPR"), HasSubstr("every revolution of the life")));
  EXPECT_EQ(without["error_motion_filter_cutoff_upr"], 0.0);
  EXPECT_THAT(without["every_revolution"]["error_motion_reading"].get<std::string>(), HasSubstr("unfiltered"));
  const auto asynchronous = [](const nlohmann::json& life) {
    return life["every_revolution"]["error_motion_asynchronous_mm"].get<double>();
  };
  EXPECT_LT(asynchronous(with), 0.1 * asynchronous(without));
  EXPECT_EQ(with["every_revolution"]["d_trajectory_mm"], without["every_revolution"]["d_trajectory_mm"]);
  const Outcome text = Ringtol("simulate " + filtered.string() + " --solver linear --steps 360 --revolutions 3");
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_THAT(text.out, HasSubstr("Gaussian filter at 50 UPR (ISO 16610-21)"));
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

// How many times `text` holds `piece`.
int Occurrences(const std::string& text, const std::string& piece) {
  int count = 0;
  for (std::size_t at = text.find(piece); at != std::string::npos; at = text.find(piece, at + 1)) ++count;
  return count;
}

// A contact law the scene file states shapes the answer by the user's choice: a one-line
// note naming the file and keys; one from the defaults (its materials') a warning. Before,
// both were a warning of two lines, which the quick start's first run printed.
TEST(Cli, SimulateNotesALawTheSceneStatesAndWarnsOfOneFromTheDefaults) {
  const std::string table = std::string(RINGTOL_SOURCE_DIR) + "/examples/rotary_table/scene.toml";
  const std::filesystem::path article_law = std::filesystem::path(::testing::TempDir()) / "ringtol_cli_table_article.toml";
  ringtol::testing::WriteText(
      article_law, ringtol::testing::ReplaceOnce(ringtol::testing::ReadText(table), "law = \"penalty\"",
                                                 "law = \"penalty\"\nstiffness_N_per_m_e = 1.0e7\nexponent = 1.5"));
  const Outcome noted = Ringtol("simulate " + article_law.string() + " --steps 90 --json");
  EXPECT_EQ(noted.exit_code, 0) << noted.err;
  EXPECT_THAT(noted.err, AllOf(::testing::StartsWith("ringtol: note: the contact law F = 1e+07 delta^1.5"),
                               HasSubstr("that " + article_law.string() + " states ([contact] stiffness_N_per_m_e and "
                                         "exponent)"),
                               HasSubstr(" um at ")));
  EXPECT_EQ(Occurrences(noted.err, "\n"), 1) << noted.err;
  EXPECT_TRUE(nlohmann::json::accept(noted.out));  // stdout stays the result alone

  const Outcome materials = Ringtol("simulate " + table + " --steps 90");
  EXPECT_EQ(materials.exit_code, 0);
  EXPECT_EQ(materials.err, "");

  // Rubber-soft materials (10 MPa) under the paper's rig: the default law sinks 0.6 mm.
  const std::filesystem::path soft = std::filesystem::path(::testing::TempDir()) / "ringtol_cli_soft.toml";
  std::string text = ringtol::testing::ReadText(Example("scene.toml"));
  text = ringtol::testing::ReplaceOnce(text, "stiffness_N_per_m_e = 1.0e7", "");
  text = ringtol::testing::ReplaceOnce(text, "exponent = 1.5", "");
  text = ringtol::testing::ReplaceOnce(text, "youngs_modulus_GPa = 70.0", "youngs_modulus_GPa = 0.01");
  ringtol::testing::WriteText(soft, text);
  const Outcome warned = Ringtol("simulate " + soft.string() + " --steps 90");
  EXPECT_EQ(warned.exit_code, 0) << warned.err;
  EXPECT_THAT(warned.err, AllOf(::testing::StartsWith("ringtol: warning: the contact law"),
                                HasSubstr("It is the law of the ring's and rollers' materials")));
}

TEST(Cli, SweepNotesTheLawOnceForAllItsCases) {
  const Outcome run = Ringtol("sweep " + Example("orders.toml") + " --json --solver linear --steps 90");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(Occurrences(run.err, "ringtol: note: the contact law"), 1) << run.err;
  EXPECT_THAT(run.err, HasSubstr("paper/scene.toml states"));
}

// bench campaign runs the campaign's scene, so it says what a campaign says of its law.
TEST(Cli, BenchCampaignNotesTheLawItsSceneStates) {
  const std::filesystem::path file = std::filesystem::path(::testing::TempDir()) / "ringtol_cli_bench_campaign.toml";
  ringtol::testing::WriteText(file, "scene = \"" + Example("scene.toml") +
                                        "\"\nseed = 1\n[design]\nkind = \"monte_carlo\"\nsamples = 8\n"
                                        "[tolerances.ring]\nclass = \"precise\"\n");
  const Outcome run = Ringtol("bench campaign " + file.string() + " --no-report");
  EXPECT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(Occurrences(run.err, "ringtol: note: the contact law F = 1e+07 delta^1.5"), 1) << run.err;
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

// A short dynamic scene: the order-3 example with a 0.05 s settle and a tenth of a
// revolution listed, so a history is 100 ms long and a steady revolution exists.
std::filesystem::path ShortDynamicScene() {
  const std::filesystem::path scene = std::filesystem::path(::testing::TempDir()) / "ringtol_dynamic_scene.toml";
  std::ifstream in(Example("order3.toml"));
  std::stringstream text;
  text << in.rdbuf() << "\n[motion]\nsettle_s = 0.05\nrevolutions = 0.1\n";
  std::ofstream(scene) << text.str();
  return scene;
}

TEST(Cli, DynamicSimulateWritesItsHistoryAndSteadyRevolution) {
  const std::filesystem::path csv = std::filesystem::path(::testing::TempDir()) / "ringtol_history.csv";
  const Outcome run = Ringtol("simulate " + ShortDynamicScene().string() +
                              " --solver dynamic --steps 90 --json --history " + csv.string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  EXPECT_EQ(j["solver"], "dynamic");
  EXPECT_EQ(j["dynamic_start"], "quasistatic_equilibrium");
  EXPECT_EQ(j["status"], "ok") << j.dump();
  ASSERT_TRUE(j.contains("steady"));
  EXPECT_EQ(j["steady"]["status"], "ok");
  EXPECT_TRUE(j["steady"]["d_trajectory_mm"].is_number());
  EXPECT_EQ(j["d_trajectory_first_mm"], j["d_trajectory_mm"]);
  EXPECT_EQ(j["d_trajectory_steady_mm"], j["steady"]["d_trajectory_mm"]);
  EXPECT_EQ(j["history_status"], "ok");
  std::ifstream in(csv);
  std::string header;
  std::getline(in, header);
  EXPECT_THAT(header, HasSubstr("time_s,psi_deg,x_um,y_um,spring_travel_um,spring_spin_deg,"));
  EXPECT_THAT(header, HasSubstr("fixed_b_slip_mm_per_s"));
  int rows = 0;
  for (std::string line; std::getline(in, line);) ++rows;
  // 0.05 s + 0.1 revolution at 270 deg/s (0.1333 s) = 0.1833 s at 1 ms: 184 samples.
  EXPECT_EQ(rows, 184);
}

TEST(Cli, HistoryNeedsTheDynamicSolverAndSaysSoBeforeAnyWork) {
  // An existing trajectory file must survive the refusal: options are checked before any
  // output is opened.
  const std::filesystem::path kept = std::filesystem::path(::testing::TempDir()) / "ringtol_kept_trajectory.csv";
  std::ofstream(kept) << "earlier results\n";
  const Outcome run =
      Ringtol("simulate " + Example("scene.toml") + " --trajectory " + kept.string() + " --history /tmp/never.csv");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_THAT(run.err, HasSubstr("--history"));
  EXPECT_THAT(run.err, HasSubstr("--solver dynamic"));
  EXPECT_TRUE(run.out.empty()) << run.out;
  std::ifstream in(kept);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "earlier results");
}

// A time-free rung's path is steady by construction: its first and steady revolutions are
// its one D_trajectory, and it has no start.
TEST(Cli, QuasistaticJsonHasNoSteadyRevolutionAndOneDiameterForBoth) {
  const Outcome run = Ringtol("simulate " + Example("order3.toml") + " --json --steps 90");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json j = nlohmann::json::parse(run.out);
  EXPECT_FALSE(j.contains("steady"));
  EXPECT_FALSE(j.contains("dynamic_start"));
  EXPECT_EQ(j["d_trajectory_first_mm"], j["d_trajectory_mm"]);
  EXPECT_EQ(j["d_trajectory_steady_mm"], j["d_trajectory_mm"]);
}

TEST(Cli, DynamicStartIsOneOfItsNamesAndSaysWhichWhenNot) {
  const Outcome run = Ringtol("simulate " + Example("scene.toml") + " --solver dynamic --dynamic-start centred");
  EXPECT_NE(run.exit_code, 0);
  EXPECT_THAT(run.err, HasSubstr("centred"));
  EXPECT_THAT(run.err, HasSubstr("article_settle"));
}

TEST(Cli, AccuracyIsFullOrFastAndSimulateSaysWhichWhenFast) {
  const Outcome rough = Ringtol("simulate " + Example("scene.toml") + " --accuracy rough");
  EXPECT_NE(rough.exit_code, 0);
  EXPECT_THAT(rough.err, AllOf(HasSubstr("--accuracy"), HasSubstr("rough"), HasSubstr("full"), HasSubstr("fast")));
  const Outcome fast = Ringtol("simulate " + Example("scene.toml") + " --solver auto --angles spectral --accuracy fast");
  ASSERT_EQ(fast.exit_code, 0) << fast.err;
  EXPECT_THAT(fast.out, HasSubstr("solver            auto, accuracy fast"));
  const Outcome json = Ringtol("simulate " + Example("scene.toml") + " --accuracy fast --json");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  EXPECT_EQ(nlohmann::json::parse(json.out)["accuracy"], "fast");
}

TEST(Cli, DynamicSweepWritesFirstAndSteadyRevolutionsToItsTableAndCsv) {
  const std::filesystem::path sweep = std::filesystem::path(::testing::TempDir()) / "ringtol_dynamic_sweep.toml";
  std::ofstream(sweep) << "scene = \"" << ShortDynamicScene().string()
                       << "\"\n[study]\ntarget = \"ring\"\norders = [2]\namplitudes_mm = [0.14]\n";
  const std::filesystem::path csv = std::filesystem::path(::testing::TempDir()) / "ringtol_dynamic_sweep.csv";
  const Outcome run = Ringtol("sweep " + sweep.string() + " --solver dynamic --dynamic-start article_settle --steps 36 --csv " +
                              csv.string());
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_THAT(run.out, HasSubstr("D_first mm"));
  EXPECT_THAT(run.out, HasSubstr("D_steady mm"));
  std::ifstream in(csv);
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  EXPECT_THAT(header, HasSubstr(",d_trajectory_first_mm,d_trajectory_steady_mm,dynamic_start"));
  EXPECT_THAT(row, HasSubstr(",article_settle"));
}

TEST(Cli, BenchDynamicsPrintsBothTables) {
  const Outcome run = Ringtol("bench dynamics " + Example("scene.toml") + " --orders 3 --rates-deg-per-s 10 100");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_THAT(run.out, HasSubstr("Start transient at 270 deg/s after a 0.5 s settle"));
  EXPECT_THAT(run.out, HasSubstr("1 um above"));
}

}  // namespace
