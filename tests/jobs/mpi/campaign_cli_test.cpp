// `ringtol campaign` as users run it: alone and under mpirun, killed and resumed, given
// bad inputs. Results must not depend on the number of ranks, the chunk sizes or
// interruptions: every dataset but the solve times is compared bit for bit.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>
#include <sstream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <hdf5.h>
#include <nlohmann/json.hpp>

#include "jobs/store/campaign_store.h"
#include "tests/support/background_run.h"
#include "tests/support/mpi_environment.h"
#include "tests/support/shell.h"
#include "tests/support/small_campaign.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Ne;

using testing::kMpiEnvironment;
using testing::Mpirun;

const std::string kScene = (std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/paper/scene.toml").string();

// Quick to calibrate and to solve, with every kind of input.
const std::string kCampaign = "scene = \"" + kScene + R"("
seed = 11
[design]
kind = "monte_carlo"
samples = 48
[tolerances.ring]
circularity_mm = 0.2
max_order = 6
[tolerances.rollers]
class = "Normal"
max_order = 2
mode = "inspected"
[tolerances.roller_positions]
zone_diameter_mm = 0.05
[tolerances.springs]
class = "pm10"
[solver]
name = "quasistatic"
path_tolerance_um = 2.0
[spec]
d_trajectory_mm = 0.2
)";

using Outcome = testing::ShellOutcome;  // exit code 128 + signal when killed

using testing::ExitsWith;

std::filesystem::path TestFolder() { return testing::TestFolderPath("campaign_cli_test"); }

// The test's folder, emptied.
std::filesystem::path Folder() { return testing::FreshTestFolder("campaign_cli_test"); }

std::filesystem::path Write(const std::filesystem::path& file, const std::string& text) {
  testing::WriteText(file, text);
  return file;
}

// Runs `prefix ringtol arguments` through the shell; `timeout` guards against a hang.
Outcome RunRingtol(const std::string& prefix, const std::string& arguments) {
  std::filesystem::create_directories(TestFolder());
  return testing::RunShell(kMpiEnvironment + "timeout 120 " + prefix + RINGTOL_EXECUTABLE + " " + arguments,
                           TestFolder() / "stderr.txt");
}

Outcome Campaign(const std::filesystem::path& file, const std::filesystem::path& out, const std::string& options = "",
                 const std::string& prefix = "") {
  return RunRingtol(prefix, "campaign " + file.string() + " --out " + out.string() + " --quiet " + options);
}

bool SameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

// Every sample of two results files, field by field, solve time aside.
void ExpectSameResults(const std::filesystem::path& a, const std::filesystem::path& b) {
  const CampaignReader x(a);
  const CampaignReader y(b);
  ASSERT_EQ(x.samples(), y.samples());
  for (std::int64_t i = 0; i < x.samples(); ++i) {
    const SampleRecord p = x.ReadSample(i);
    const SampleRecord q = y.ReadSample(i);
    ASSERT_NE(p.status, SampleStatus::kPending) << a << " sample " << i;
    EXPECT_EQ(p.status, q.status) << i;
    EXPECT_EQ(p.message, q.message) << i;
    EXPECT_EQ(p.redraws, q.redraws) << i;
    EXPECT_EQ(p.steps, q.steps) << i;
    EXPECT_TRUE(SameBits(p.u, q.u)) << i;
    EXPECT_TRUE(SameBits(p.values, q.values)) << i;
    EXPECT_EQ(std::memcmp(p.outputs.data(), q.outputs.data(), sizeof(p.outputs)), 0) << i;
  }
}

std::int64_t Pending(const std::filesystem::path& file) {
  const CampaignReader results(file);
  const std::vector<SampleStatus> status = results.ReadStatus(0, results.samples());
  return std::count(status.begin(), status.end(), SampleStatus::kPending);
}

TEST(Campaign, AloneItComputesEverySampleAndSummarisesThem) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "campaign.toml", kCampaign);
  const Outcome run = Campaign(file, folder / "results.h5", "--json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // --quiet: no progress; the article's law, which its base scene states, is worth one note.
  EXPECT_THAT(run.err, ::testing::StartsWith("ringtol: note: the contact law F = 1e+07 delta^1.5"));
  EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << run.err;
  EXPECT_THAT(run.err, ::testing::Not(HasSubstr("samples (")));
  const nlohmann::json summary = nlohmann::json::parse(run.out);
  EXPECT_EQ(summary["samples"], 48);
  EXPECT_EQ(summary["samples_done"], 48);
  EXPECT_EQ(summary["run"]["computed"], 48);
  EXPECT_EQ(summary["outputs"]["d_trajectory_mm"]["quantiles"].size(), 4u);
  EXPECT_EQ(summary["outputs"]["d_trajectory_mm"]["upper_spec_limit"], 0.2);
  EXPECT_EQ(summary["in_spec"]["trials"], 48);
  EXPECT_EQ(Pending(folder / "results.h5"), 0);
}

// An 800 mm rotary table: a 400 mm-radius bore on three track rollers of 40 mm outside
// diameter, the size ISO 492's row over 30 up to 50 mm holds.
const std::string kRotaryTableScene = R"([ring]
inner_radius_mm = 400.0
outer_radius_mm = 440.0
thickness_mm = 10.0
density_kg_per_m3 = 2700.0

[[rollers]]
name = "spring"
angle_deg = 90.0
radius_mm = 20.0
mount = "spring"
spring_stiffness_N_per_m = 2000.0
spring_preload_N = 40.0
width_mm = 12.0
density_kg_per_m3 = 7850.0

[[rollers]]
name = "left"
angle_deg = 210.0
radius_mm = 20.0
mount = "fixed"
width_mm = 12.0
density_kg_per_m3 = 7850.0

[[rollers]]
name = "right"
angle_deg = 330.0
radius_mm = 20.0
mount = "fixed"
width_mm = 12.0
density_kg_per_m3 = 7850.0
)";

TEST(Campaign, FortyMillimetreRollersRunUnderACatalogueClass) {
  const std::filesystem::path folder = Folder();
  const auto scene = Write(folder / "rotary_table.toml", kRotaryTableScene);
  const auto file = Write(folder / "campaign.toml", "scene = \"" + scene.string() + R"("
seed = 3
[design]
kind = "monte_carlo"
samples = 8
[tolerances.ring]
circularity_mm = 0.1
max_order = 4
[tolerances.rollers]
class = "Normal"
max_order = 3
[solver]
name = "quasistatic"
[spec]
d_trajectory_mm = 0.2
)");
  const Outcome run = Campaign(file, folder / "results.h5", "--json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json summary = nlohmann::json::parse(run.out);
  EXPECT_EQ(summary["samples_done"], 8);
  EXPECT_EQ(summary["outputs"]["d_trajectory_mm"]["count"], 8);
  // Each roller's form is calibrated on ISO 492 Normal's VDsp at D = 40 mm, series 9:
  // 14 um (S1 Table 2, S2 Table 8.2.2, S3 Table 6.4 (2); docs/tolerances.md §1.2).
  constexpr double kNormalVdspAt40MmSeries9 = 14e-6;  // [m]
  const CampaignReader results(folder / "results.h5");
  int roller_forms = 0;
  for (const sampling::ComponentScale& scale : results.identity().calibrations) {
    if (scale.measure != sampling::FormMeasure::kTwoPointVariation) continue;
    ++roller_forms;
    EXPECT_DOUBLE_EQ(scale.tolerance, kNormalVdspAt40MmSeries9) << scale.component;
  }
  EXPECT_EQ(roller_forms, 3);
}

TEST(CampaignUnderMpirun, OneTwoAndThreeRanksAndAnyChunkSizeWriteIdenticalResults) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "campaign.toml", kCampaign);
  ASSERT_EQ(Campaign(file, folder / "alone.h5").exit_code, 0);
  const Outcome two = Campaign(file, folder / "two.h5", "--chunk 1", Mpirun(2));
  ASSERT_EQ(two.exit_code, 0) << two.err;
  const Outcome three = Campaign(file, folder / "three.h5", "--chunk 7", Mpirun(3));
  ASSERT_EQ(three.exit_code, 0) << three.err;
  const Outcome dedicated = Campaign(file, folder / "dedicated.h5", "--coordinator-computes 0 --json", Mpirun(3));
  ASSERT_EQ(dedicated.exit_code, 0) << dedicated.err;
  // The workers filed every sample in their shards, which the results file indexes; rank 0
  // received per sample at most a chunk's tally (solve time 8, one status 1 and its count
  // 8 bytes), its index handed out (8) and a message's kind byte (1), were every chunk one
  // sample.
  constexpr double kMaxCoordinatorBytesPerSample = 8 + 1 + 8 + 8 + 1;
  const nlohmann::json run = nlohmann::json::parse(dedicated.out)["run"];
  EXPECT_LE(run["coordinator_bytes"].get<double>() / 48, kMaxCoordinatorBytesPerSample);
  EXPECT_EQ(run["shards"], 3);  // rank 0's computes nothing, and is indexed all the same
  for (const auto& [name, ranks] : {std::pair{"two.h5", 2}, std::pair{"three.h5", 3}, std::pair{"dedicated.h5", 3}}) {
    EXPECT_EQ(IndexedShards(folder / name).size(), static_cast<std::size_t>(ranks)) << name;
  }
  ExpectSameResults(folder / "alone.h5", folder / "two.h5");
  ExpectSameResults(folder / "alone.h5", folder / "three.h5");
  ExpectSameResults(folder / "alone.h5", folder / "dedicated.h5");
  // And as h5py reads them: the shards' index against the file written alone.
  for (const char* name : {"two.h5", "three.h5"}) {
    const std::string python = "/usr/bin/python3 " + std::string(RINGTOL_SOURCE_DIR) + "/tests/jobs/mpi/same_columns.py " +
                               (folder / "alone.h5").string() + " " + (folder / name).string() + " > " +
                               (folder / "python.txt").string() + " 2>&1";
    EXPECT_EQ(std::system(python.c_str()), 0) << name << ": " << testing::ReadText(folder / "python.txt");
  }
}

// Runs the campaign with `options` (resuming `out` if it exists) and the test hook that
// kills the coordinator after 10 samples of this run; checks that between 1 and
// `at_most_missing` samples were left pending, then resumes with `options` and checks
// that exactly those are computed.
void KillAfterTenThenResume(const std::filesystem::path& file, const std::filesystem::path& out,
                            const std::string& options, std::int64_t at_most_missing) {
  const std::string resume = std::filesystem::exists(out) ? " --resume" : "";
  const Outcome killed = Campaign(file, out, options + resume + " --chunk 3 --commit-seconds 0 --test-kill-after 10");
  constexpr int kKilledBySigkill = 128 + SIGKILL;  // the shell's report of a child killed by signal 9
  ASSERT_EQ(killed.exit_code, kKilledBySigkill) << killed.err;
  const std::int64_t missing = Pending(out);
  EXPECT_GT(missing, 0);
  EXPECT_LE(missing, at_most_missing);
  const Outcome resumed = Campaign(file, out, options + " --resume --json");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  const nlohmann::json summary = nlohmann::json::parse(resumed.out);
  EXPECT_EQ(summary["run"]["computed"], missing);
  EXPECT_EQ(summary["run"]["already_done"], summary["samples"].get<std::int64_t>() - missing);
}

TEST(Campaign, AfterTheCoordinatorIsKilledResumeComputesOnlyWhatIsMissing) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "campaign.toml", kCampaign);
  ASSERT_EQ(Campaign(file, folder / "whole.h5").exit_code, 0);
  KillAfterTenThenResume(file, folder / "killed.h5", "", 48 - 10);
  ExpectSameResults(folder / "whole.h5", folder / "killed.h5");
}

TEST(CampaignUnderMpirun, AfterAWorkerIsKilledUnderMpirunResumeCompletesTheSameFile) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "campaign.toml", kCampaign);
  ASSERT_EQ(Campaign(file, folder / "whole.h5").exit_code, 0);
  const Outcome killed = Campaign(file, folder / "killed.h5", "--chunk 2 --commit-seconds 0 --test-kill-rank 1", Mpirun(2));
  EXPECT_NE(killed.exit_code, 0);
  const Outcome resumed = Campaign(file, folder / "killed.h5", "--resume", Mpirun(2));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  ExpectSameResults(folder / "whole.h5", folder / "killed.h5");
}

// Finished samples in the shards of a results file written under mpirun, each counted once.
std::int64_t DoneInShards(const std::filesystem::path& out) {
  std::set<std::int64_t> done;
  for (const std::filesystem::path& shard : FindShards(out)) {
    const CampaignReader reader(shard);
    for (const SampleRange& range : ReadShardContents(shard, reader.identity(), reader.samples()).finished) {
      for (std::int64_t i = range.begin; i < range.end; ++i) done.insert(i);
    }
  }
  return static_cast<std::int64_t>(done.size());
}

TEST(CampaignUnderMpirun, AfterTheCoordinatorIsKilledResumeContinuesTheShardsAndComputesOnlyWhatIsMissing) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "campaign.toml", kCampaign);
  const std::filesystem::path out = folder / "killed.h5";
  ASSERT_EQ(Campaign(file, folder / "whole.h5").exit_code, 0);
  const Outcome killed = Campaign(file, out, "--chunk 3 --commit-seconds 0 --test-kill-after 10", Mpirun(2));
  EXPECT_NE(killed.exit_code, 0);
  const std::int64_t done = DoneInShards(out);
  EXPECT_GE(done, 10);
  EXPECT_LT(done, 48);
  EXPECT_EQ(Pending(out), 48) << "the index written at the start shows what the shards held then";
  const Outcome resumed = Campaign(file, out, "--resume --json", Mpirun(2));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(nlohmann::json::parse(resumed.out)["run"]["computed"], 48 - done);
  EXPECT_EQ(IndexedShards(out), FindShards(out));
  ExpectSameResults(folder / "whole.h5", out);
}

// Fewer ranks than the shards: the others' shards stay and are indexed as they are; a
// resume with nothing left to compute writes the same index, byte for byte.
TEST(CampaignUnderMpirun, AResumeWithFewerRanksKeepsTheOtherShardsAndANoOpResumeChangesNoByte) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "campaign.toml", kCampaign);
  const std::filesystem::path out = folder / "r.h5";
  ASSERT_EQ(Campaign(file, folder / "whole.h5").exit_code, 0);
  ASSERT_EQ(Campaign(file, out, "--samples 20 --coordinator-computes 0", Mpirun(3)).exit_code, 0);
  const Outcome grown = Campaign(file, out, "--resume --samples 48 --json", Mpirun(2));
  ASSERT_EQ(grown.exit_code, 0) << grown.err;
  EXPECT_EQ(nlohmann::json::parse(grown.out)["run"]["computed"], 28);
  EXPECT_EQ(IndexedShards(out), (std::vector<std::filesystem::path>{ShardPath(out, 0), ShardPath(out, 1), ShardPath(out, 2)}));
  ExpectSameResults(folder / "whole.h5", out);
  const std::string index = testing::ReadText(out);
  const std::string shard = testing::ReadText(ShardPath(out, 2));
  const Outcome again = Campaign(file, out, "--resume --json");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(nlohmann::json::parse(again.out)["run"]["computed"], 0);
  EXPECT_TRUE(testing::ReadText(out) == index) << "a resume with nothing to compute rewrote the index differently";
  EXPECT_TRUE(testing::ReadText(ShardPath(out, 2)) == shard);
}

// Shards are named beside a results file given by a relative path as the index names them.
TEST(CampaignUnderMpirun, AResultsFileNamedRelativeToTheWorkingFolderResumes) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "campaign.toml", kCampaign);
  ASSERT_EQ(Campaign(file, folder / "whole.h5").exit_code, 0);
  const std::string here = Mpirun(2) + "-wdir " + folder.string() + " ";
  ASSERT_EQ(RunRingtol(here, "campaign campaign.toml --out r.h5 --quiet --samples 20").exit_code, 0);
  const Outcome resumed = RunRingtol(here, "campaign campaign.toml --out r.h5 --quiet --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  ExpectSameResults(folder / "whole.h5", folder / "r.h5");
}

// A campaign begun in one process continues under mpirun: its file becomes shard 0 of the
// index, in place; `ringtol join` makes one file of the index again, with the same samples.
TEST(CampaignUnderMpirun, AFileBegunAloneContinuesInShardsAndJoinsBackIntoOneFile) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "campaign.toml", kCampaign);
  const std::filesystem::path out = folder / "r.h5";
  ASSERT_EQ(Campaign(file, folder / "whole.h5").exit_code, 0);
  ASSERT_EQ(Campaign(file, out, "--samples 20").exit_code, 0);
  const Outcome resumed = Campaign(file, out, "--resume --samples 48 --json", Mpirun(3));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_EQ(nlohmann::json::parse(resumed.out)["run"]["computed"], 28);
  EXPECT_EQ(IndexedShards(out), (std::vector<std::filesystem::path>{ShardPath(out, 0), ShardPath(out, 1), ShardPath(out, 2)}));
  ExpectSameResults(folder / "whole.h5", out);
  const Outcome verified = RunRingtol("", "verify " + out.string());
  EXPECT_EQ(verified.exit_code, 0) << verified.out << verified.err;
  EXPECT_THAT(verified.out, HasSubstr("48 done"));
  const std::string python = "/usr/bin/python3 " + std::string(RINGTOL_SOURCE_DIR) + "/tests/jobs/mpi/read_results.py " +
                             out.string() + " > " + (folder / "python.txt").string() + " 2>&1";
  EXPECT_EQ(std::system(python.c_str()), 0) << testing::ReadText(folder / "python.txt");
  EXPECT_THAT(testing::ReadText(folder / "python.txt"), HasSubstr("samples ok of 48"));

  const Outcome copy = RunRingtol("", "join " + out.string() + " --out " + (folder / "copy.h5").string());
  ASSERT_EQ(copy.exit_code, 0) << copy.err;
  EXPECT_THAT(copy.out, AllOf(HasSubstr("joined 3 shards"), HasSubstr("48 samples")));
  EXPECT_THAT(RunRingtol("", "join " + (folder / "copy.h5").string()), ExitsWith(1, HasSubstr("no shards")));
  ASSERT_EQ(RunRingtol("", "join " + out.string()).exit_code, 0);
  EXPECT_TRUE(FindShards(out).empty());
  ExpectSameResults(folder / "whole.h5", out);
  ExpectSameResults(folder / "whole.h5", folder / "copy.h5");
}

TEST(Campaign, ANewRunRefusesToStartOverShardsOfAnEarlierOne) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "campaign.toml", kCampaign);
  testing::WriteText(ShardPath(folder / "results.h5", 1), "left by a killed run");
  EXPECT_THAT(Campaign(file, folder / "results.h5"),
              ExitsWith(Ne(0), AllOf(HasSubstr("results.h5.shard-1"), HasSubstr("--resume"))));
  EXPECT_FALSE(std::filesystem::exists(folder / "results.h5"));
}

TEST(Campaign, ResumeWithMoreSamplesGrowsTheFileAsIfRunWhole) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "campaign.toml", kCampaign);
  ASSERT_EQ(Campaign(file, folder / "whole.h5").exit_code, 0);
  ASSERT_EQ(Campaign(file, folder / "grown.h5", "--samples 20").exit_code, 0);
  const Outcome grown = Campaign(file, folder / "grown.h5", "--resume --samples 48 --json");
  ASSERT_EQ(grown.exit_code, 0) << grown.err;
  EXPECT_EQ(nlohmann::json::parse(grown.out)["run"]["computed"], 28);
  ExpectSameResults(folder / "whole.h5", folder / "grown.h5");
  EXPECT_THAT(Campaign(file, folder / "grown.h5", "--resume --samples 10"), ExitsWith(Ne(0), HasSubstr("grown.h5")));
  // Grown beyond the campaign file's 48, it resumes without --samples at its own size.
  ASSERT_EQ(Campaign(file, folder / "grown.h5", "--resume --samples 60").exit_code, 0);
  const Outcome again = Campaign(file, folder / "grown.h5", "--resume --json");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(nlohmann::json::parse(again.out)["run"]["computed"], 0);
  EXPECT_EQ(CampaignReader(folder / "grown.h5").samples(), 60);
}

// Growing a finished file and being killed while at it: the resume that follows must
// still end with the file an uninterrupted run of the larger campaign writes.
TEST(Campaign, AKillWhileResumeGrowsTheFileLosesNothing) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "campaign.toml", kCampaign);
  ASSERT_EQ(Campaign(file, folder / "whole.h5").exit_code, 0);
  ASSERT_EQ(Campaign(file, folder / "grown.h5", "--samples 20").exit_code, 0);
  // The killed run is itself a resume that grows the file from 20 samples to 48.
  KillAfterTenThenResume(file, folder / "grown.h5", "--samples 48", 28 - 10);
  ExpectSameResults(folder / "whole.h5", folder / "grown.h5");
}

TEST(Campaign, ProgressGoesToStderrAsPlainLinesWhenNotATerminal) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "campaign.toml", kCampaign);
  const Outcome run = RunRingtol("", "campaign " + file.string() + " --out " + (folder / "r.h5").string() +
                                  " --progress-seconds 0.001");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_THAT(run.err, HasSubstr("campaign: 48/48 samples (100.0 %)"));
  EXPECT_THAT(run.err, HasSubstr("failed"));
  EXPECT_THAT(run.out, AllOf(HasSubstr("d_trajectory_mm"), HasSubstr("within spec"), HasSubstr("samples/s")));
}

TEST(Campaign, ProgressIsABarRedrawnInPlaceOnATerminal) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "campaign.toml", kCampaign);
  // util-linux `script` runs the command on a pseudo-terminal and copies what it shows.
  const std::string inner = kMpiEnvironment + RINGTOL_EXECUTABLE + " campaign " + file.string() + " --out " +
                            (folder / "r.h5").string() + " >/dev/null";
  const std::string command = "script -qec '" + inner + "' " + (folder / "terminal.txt").string() + " >/dev/null";
  ASSERT_EQ(std::system(command.c_str()), 0);
  const std::string shown = testing::ReadText(folder / "terminal.txt");
  EXPECT_THAT(shown, HasSubstr("\r["));
  EXPECT_THAT(shown, HasSubstr("##############################] 48/48 samples (100.0 %)"));
  EXPECT_THAT(shown, ::testing::Not(HasSubstr("campaign: ")));
}

TEST(Campaign, AnExistingResultsFileIsNeverOverwrittenOrTakenForAnother) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "campaign.toml", kCampaign);
  const auto text = Write(folder / "notes.h5", "not hdf5\n");
  EXPECT_THAT(Campaign(file, text),
              ExitsWith(1, AllOf(HasSubstr("notes.h5"), HasSubstr("exists"), HasSubstr("--resume"))));
  EXPECT_THAT(Campaign(file, text, "--resume"), ExitsWith(1, AllOf(HasSubstr("notes.h5"), HasSubstr("HDF5"))));
  EXPECT_EQ(testing::ReadText(text), "not hdf5\n");

  ASSERT_EQ(Campaign(file, folder / "whole.h5").exit_code, 0);
  std::string bytes = testing::ReadText(folder / "whole.h5");
  bytes.resize(bytes.size() / 2);
  Write(folder / "truncated.h5", bytes);
  EXPECT_THAT(Campaign(file, folder / "truncated.h5", "--resume"), ExitsWith(1, HasSubstr("truncated.h5")));
  EXPECT_EQ(testing::ReadText(folder / "truncated.h5"), bytes);

  const auto other = Write(folder / "other.toml", testing::ReplaceOnce(kCampaign, "seed = 11", "seed = 12"));
  EXPECT_THAT(Campaign(other, folder / "whole.h5", "--resume"),
              ExitsWith(1, AllOf(HasSubstr("whole.h5"), HasSubstr("another campaign"))));
  EXPECT_THAT(Campaign(file, folder / "absent.h5", "--resume"),
              ExitsWith(1, AllOf(HasSubstr("absent.h5"), HasSubstr("--resume"))));
}

TEST(CampaignUnderMpirun, BadInputStopsEveryRankWithOneClearMessageBeforeAnySample) {
  const std::filesystem::path folder = Folder();
  const auto unknown_class =
      Write(folder / "class.toml", testing::ReplaceOnce(kCampaign, "class = \"Normal\"", "class = \"P9\""));
  EXPECT_THAT(Campaign(unknown_class, folder / "r.h5", "", Mpirun(2)),
              ExitsWith(Ne(0), AllOf(HasSubstr("class.toml"), HasSubstr("P9"))));
  EXPECT_FALSE(std::filesystem::exists(folder / "r.h5"));

  const auto no_scene = Write(folder / "scene.toml", testing::ReplaceOnce(kCampaign, kScene, "/nonexistent/scene.toml"));
  EXPECT_THAT(Campaign(no_scene, folder / "r.h5", "", Mpirun(2)),
              ExitsWith(Ne(0), AllOf(HasSubstr("scene.toml"), HasSubstr("/nonexistent/scene.toml"))));

  const auto file = Write(folder / "campaign.toml", kCampaign);
  EXPECT_THAT(Campaign(file, folder / "no" / "such" / "r.h5", "", Mpirun(2)),
              ExitsWith(Ne(0), AllOf(HasSubstr("r.h5"), HasSubstr("does not exist"))));

  EXPECT_THAT(Campaign(file, folder / "r.h5", "--chunk-seconds 0"),
              ExitsWith(Ne(0), AllOf(HasSubstr("--chunk-seconds"), HasSubstr("> 0"))));
}

TEST(Campaign, ResultsReadInH5pyAndH5dumpWithTheDocumentedSchema) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "campaign.toml", kCampaign);
  ASSERT_EQ(Campaign(file, folder / "r.h5").exit_code, 0);
  const Outcome dump = RunRingtol("", "--version");  // the shell and environment work
  ASSERT_EQ(dump.exit_code, 0);
  const std::string h5dump = "h5dump -H " + (folder / "r.h5").string() + " > " + (folder / "dump.txt").string();
  ASSERT_EQ(std::system(h5dump.c_str()), 0);
  const std::string header = testing::ReadText(folder / "dump.txt");
  for (const char* name : {"schema_version", "campaign_file", "base_scene", "\"u\"", "\"values\"", "\"status\"",
                           "\"d_trajectory_mm\"", "\"solve_time_s\"", "H5T_ENUM", "\"pending\""}) {
    EXPECT_THAT(header, HasSubstr(name));
  }
  const std::string script = std::string(RINGTOL_SOURCE_DIR) + "/tests/jobs/mpi/read_results.py";
  const std::string python = "/usr/bin/python3 " + script + " " + (folder / "r.h5").string() + " > " +
                             (folder / "python.txt").string() + " 2>&1";
  EXPECT_EQ(std::system(python.c_str()), 0) << testing::ReadText(folder / "python.txt");
  EXPECT_THAT(testing::ReadText(folder / "python.txt"), HasSubstr("48 samples ok"));
}

// `ringtol inputs` prints chosen samples' design points and values as the reader gives
// them (kept or replayed: jobs/store tests the replay), and refuses samples outside the file.
TEST(Campaign, InputsPrintsChosenSamplesAsCsvAndStoreInputsKeepsEverySample) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "campaign.toml", kCampaign);
  const std::filesystem::path out = folder / "r.h5";
  ASSERT_EQ(Campaign(file, out, "--store-inputs").exit_code, 0);
  {
    const hid_t h5 = H5Fopen(out.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const hid_t attribute = H5Aopen(h5, "inputs_stored_below", H5P_DEFAULT);
    std::int64_t stored_below = 0;
    EXPECT_GE(H5Aread(attribute, H5T_NATIVE_INT64, &stored_below), 0);
    H5Aclose(attribute);
    H5Fclose(h5);
    EXPECT_EQ(stored_below, std::numeric_limits<std::int64_t>::max());
  }
  const Outcome printed = RunRingtol("", "inputs " + out.string() + " --samples 3:6");
  ASSERT_EQ(printed.exit_code, 0) << printed.err;
  std::istringstream lines(printed.out);
  std::vector<std::string> rows;
  for (std::string line; std::getline(lines, line);) rows.push_back(line);
  ASSERT_EQ(rows.size(), 4u);  // the header and samples 3, 4, 5
  const CampaignReader reader(out);
  const std::size_t d = reader.identity().inputs.size();
  EXPECT_THAT(rows[0], AllOf(HasSubstr("sample,status,u_0,"), HasSubstr("," + reader.identity().inputs.back().name)));
  EXPECT_EQ(std::count(rows[1].begin(), rows[1].end(), ','), static_cast<std::ptrdiff_t>(1 + 2 * d));
  const SampleRecord four = reader.ReadSample(4);
  EXPECT_EQ(rows[2].substr(0, rows[2].find(',', 2)), "4,ok");
  EXPECT_THAT(rows[2], HasSubstr(fmt::format(",{},", four.u.front())));
  EXPECT_THAT(RunRingtol("", "inputs " + out.string() + " --samples 40:49"),
              ExitsWith(1, AllOf(HasSubstr("--samples 40:49"), HasSubstr("0 to 47"))));

}

// Samples on disk in a results file being written (0 while it does not exist yet): under
// mpirun in its shards, whose index shows what they held when the run started.
std::int64_t Done(const std::filesystem::path& file) {
  try {
    if (!FindShards(file).empty()) return DoneInShards(file);
    if (!std::filesystem::exists(file)) return 0;
    std::int64_t done = 0;
    for (const SampleRange& run : CampaignReader(file).Finished()) done += run.end - run.begin;
    return done;
  } catch (const std::exception&) {
    return 0;  // caught between creation and its name appearing
  }
}

using testing::Ended;
using testing::Running;
using testing::Wait;
using testing::WaitWithin;
using testing::WaitFor;

// `command` in the background, its output in the test's folder.
Running Start(const std::string& command, const std::string& name) {
  return testing::Start(kMpiEnvironment + "exec " + command, TestFolder(), name);
}

// What a run stopped by a signal said on stderr.
struct StopReport {
  std::int64_t on_disk = -1;
  std::int64_t total = -1;
  std::int64_t computed = -1;  // by the stopped run
  std::string resume;          // the command line it gave to continue
};

// Plain string search rather than <regex>, whose GCC 12 headers trip -Wmaybe-uninitialized
// in the sanitizer build.
StopReport ParseStop(const std::string& err, const std::string& signal_name) {
  const std::string head = "stopped by " + signal_name + ": ";
  const std::size_t at = err.find(head);
  std::istringstream line(at == std::string::npos ? std::string() : err.substr(at + head.size()));
  StopReport report;
  std::string of, total, samples, are, on, disk, in;
  line >> report.on_disk >> of >> report.total >> samples >> are >> on >> disk >> in;
  const std::size_t computed = err.find(" computed by this run", at);
  const std::size_t open = computed == std::string::npos ? computed : err.rfind('(', computed);
  const std::size_t next_line = computed == std::string::npos ? computed : err.find("\n  ", computed);
  if (at == std::string::npos || !line || open == std::string::npos || next_line == std::string::npos) {
    ADD_FAILURE() << "no stop report for " << signal_name << " in: " << err;
    return {};
  }
  report.computed = std::stoll(err.substr(open + 1, computed - open - 1));
  const std::size_t end = err.find('\n', next_line + 3);
  report.resume = err.substr(next_line + 3, end == std::string::npos ? std::string::npos : end - next_line - 3);
  return report;
}

// One interruption of a campaign: `command` runs until `ready(samples on disk)`, gets
// `signal` (at mpirun when `launcher`), and must stop cleanly, keeping on disk what was
// there before plus every sample it reports computed. Returns what it printed.
template <typename Ready>
StopReport Interrupt(const std::string& command, const std::filesystem::path& out, int signal, bool launcher,
                     Ready ready, const std::string& name) {
  const std::int64_t before = Done(out);
  const Running run = Start(command, name);
  EXPECT_TRUE(WaitFor([&] { return std::filesystem::exists(out) && ready(Done(out)); }));
  kill(run.pid, signal);
  const Ended ended = Wait(run);
  // Alone the exit code is the shell's 128 + signal; mpirun has its own for an aborted
  // job, and passes SIGINT on to the ranks as SIGTERM.
  const std::string signal_name = launcher ? "SIGTERM" : signal == SIGINT ? "SIGINT" : "SIGTERM";
  EXPECT_FALSE(ended.killed) << name << ": killed by signal " << ended.code << "; " << ended.err;
  if (launcher) {
    EXPECT_NE(ended.code, 0) << name;
  } else {
    EXPECT_EQ(ended.code, 128 + signal) << name << ": " << ended.err;
  }
  EXPECT_EQ(ended.out, "") << name << ": a stopped run prints no summary";
  const StopReport stop = ParseStop(ended.err, signal_name);
  EXPECT_EQ(stop.on_disk, Done(out)) << name;
  EXPECT_EQ(stop.on_disk, before + stop.computed) << name << ": a sample it computed is missing from the file";
  EXPECT_THAT(stop.resume, AllOf(HasSubstr(out.string()), HasSubstr("--resume"))) << name;
  return stop;
}

// A moment to stop a run: `signal` once the run has put `fraction` of the samples it
// lacked on disk (0: as soon as its file exists).
struct Moment {
  int signal;
  double fraction;
  const char* name;
};

// About 5 ms a sample (ten times the steps of kCampaign's), so that runs of a few
// hundred samples last long enough to be stopped at chosen moments.
std::filesystem::path SlowCampaign(const std::filesystem::path& folder, std::int64_t samples) {
  return Write(folder / "campaign.toml",
               testing::ReplaceOnce(testing::ReplaceOnce(kCampaign, "samples = 48", "samples = " + std::to_string(samples)),
                                    "path_tolerance_um = 2.0", "path_tolerance_um = 0.2"));
}

// Stops a campaign of `samples` at each of `moments` in turn, every run continuing the
// file with the command the previous one printed, then lets the last run finish. No
// sample may be computed twice, and the file must end as an uninterrupted run's.
void StopThenFinish(const std::string& prefix, std::int64_t samples, const std::vector<Moment>& moments) {
  const std::filesystem::path folder = Folder();
  const auto file = SlowCampaign(folder, samples);
  ASSERT_EQ(Campaign(file, folder / "whole.h5").exit_code, 0);
  const std::filesystem::path out = folder / "stopped.h5";
  std::string command = prefix + RINGTOL_EXECUTABLE + " campaign " + file.string() + " --out " + out.string() +
                        " --quiet --json --commit-seconds 0.05";
  std::int64_t on_disk = 0;
  std::int64_t computed = 0;
  for (const Moment& moment : moments) {
    const std::int64_t lacking = samples - on_disk;
    const auto wanted = std::max<std::int64_t>(1, std::llround(moment.fraction * static_cast<double>(lacking)));
    const StopReport stop = Interrupt(
        command, out, moment.signal, !prefix.empty(),
        [&](std::int64_t done) { return moment.fraction == 0 || done >= on_disk + wanted; }, moment.name);
    ASSERT_LT(stop.on_disk, samples) << moment.name << ": the run finished before it was stopped: make it longer";
    on_disk = stop.on_disk;
    computed += stop.computed;
    command = stop.resume;
  }
  const Ended last = Wait(Start(command, "last"));
  ASSERT_EQ(last.code, 0) << last.err;
  const nlohmann::json summary = nlohmann::json::parse(last.out);
  EXPECT_EQ(summary["run"]["already_done"], on_disk);
  EXPECT_EQ(computed + summary["run"]["computed"].get<std::int64_t>(), samples) << "a sample was computed twice or never";
  ExpectSameResults(folder / "whole.h5", out);
}

TEST(Campaign, SigtermOrSigintAtAnyMomentKeepsEveryFinishedSampleAndResumeEndsAsAnUninterruptedRun) {
  StopThenFinish("", 400, {{SIGTERM, 0.0, "start"}, {SIGINT, 0.01, "middle"}, {SIGTERM, 0.5, "end"}});
}

// mpirun passes a signal on to the ranks one odls_base_sigkill_timeout (1 s) later, so each
// run computes about a second's worth past the moment (500 samples on two loaded cores,
// 1,500 on idle ones; under the sanitizers about a tenth of that): the campaign is long
// enough for two such seconds and more, and stopped twice.
#if defined(__SANITIZE_ADDRESS__)
constexpr std::int64_t kSamplesPastTwoForwardedSignals = 1500;
#else
constexpr std::int64_t kSamplesPastTwoForwardedSignals = 6000;
#endif
TEST(CampaignUnderMpirun, SigtermOrSigintToMpirunKeepsEveryFinishedSampleAndResumeEndsAsAnUninterruptedRun) {
  StopThenFinish(Mpirun(2), kSamplesPastTwoForwardedSignals, {{SIGTERM, 0.0, "start"}, {SIGINT, 0.01, "middle"}});
}

TEST(Campaign, ASecondSignalDuringTheStopEndsTheRunAtOnceAndResumeStillCompletesTheFile) {
  const std::filesystem::path folder = Folder();
  const auto file = SlowCampaign(folder, 400);
  ASSERT_EQ(Campaign(file, folder / "whole.h5").exit_code, 0);
  const std::filesystem::path out = folder / "stopped.h5";
  const Running run = Start(std::string(RINGTOL_EXECUTABLE) + " campaign " + file.string() + " --out " + out.string() +
                                " --quiet --commit-seconds 0.05",
                            "twice");
  ASSERT_TRUE(WaitFor([&] { return Done(out) > 0; }));
  // Two different signals: the kernel merges a second pending signal of the same kind
  // into the first, but never two kinds.
  kill(run.pid, SIGINT);
  kill(run.pid, SIGTERM);
  const Ended ended = Wait(run);
  EXPECT_TRUE(ended.killed) << "exit code " << ended.code << "; " << ended.err;
  EXPECT_THAT(ended.code, ::testing::AnyOf(SIGINT, SIGTERM));
  const Outcome resumed = Campaign(file, out, "--resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  ExpectSameResults(folder / "whole.h5", out);
}

// --samples allows up to 2^40 (jobs/cli/main.cpp). Nothing at a run's start or stop may
// grow with the count asked for: such a run puts its first samples on disk at once, stops
// within a second of SIGTERM and is continued at once by --resume. Before, 2^40 samples
// computed nothing in 10 minutes and ignored SIGTERM, and 2^31 took 106 s to the first
// sample and 187 s to stop (two busy cores). A Release build here takes about 3 s to its
// first sample (the calibration, mostly) and 0.1 s to stop (the samples in hand and a
// commit): the bounds leave ten times that and more for the sanitizer build on CI's two
// cores, and the old code misses them even at 2^31.
constexpr double kFirstSampleSeconds = 60.0;
constexpr double kStopSeconds = 5.0;

TEST(Campaign, TwoToTheFortySamplesStartAtOnceStopWithinSecondsOfSigtermAndResumeAtOnce) {
  const std::filesystem::path folder = Folder();
  const std::filesystem::path out = folder / "huge.h5";
  constexpr std::int64_t kMostSamples = std::int64_t{1} << 40;
  const std::string command = std::string(RINGTOL_EXECUTABLE) + " campaign " + RINGTOL_SOURCE_DIR +
                              "/examples/campaigns/default.toml --samples " + std::to_string(kMostSamples) +
                              " --out " + out.string() + " --quiet --commit-seconds 0.05";
  std::int64_t on_disk = 0;
  for (const std::string resume : {"", " --resume"}) {
    const Running run = Start(command + resume, resume.empty() ? "huge" : "huge_resumed");
    const auto start = std::chrono::steady_clock::now();
    const auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    while (Done(out) <= on_disk && seconds() < kFirstSampleSeconds) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    EXPECT_GT(Done(out), on_disk) << "no sample on disk after " << kFirstSampleSeconds << " s" << resume;
    kill(run.pid, SIGTERM);
    const std::optional<Ended> ended = WaitWithin(run, kStopSeconds);
    ASSERT_TRUE(ended) << "SIGTERM did not stop the run" << resume << " within " << kStopSeconds << " s";
    EXPECT_FALSE(ended->killed) << ended->err;
    EXPECT_EQ(ended->code, 128 + SIGTERM) << ended->err;
    const StopReport stop = ParseStop(ended->err, "SIGTERM");
    EXPECT_EQ(stop.total, kMostSamples);
    EXPECT_GT(stop.computed, 0) << resume;
    EXPECT_EQ(stop.on_disk, on_disk + stop.computed) << resume;
    EXPECT_EQ(stop.on_disk, Done(out)) << resume;
    on_disk = stop.on_disk;
  }
  const ResultsCheck check = CheckResults(out);
  EXPECT_TRUE(check.intact());
  EXPECT_EQ(check.done, on_disk);
}

// A stopped run of 2^40 samples is read in the time of the samples it finished: report and
// join read no further than the farthest one (SampleTable::written_end), and the report
// counts the rest as pending without reading them. Before, report ran out of memory
// (std::bad_alloc, three columns of 2^40 values) and join read every status chunk of 2^40
// rows, still running after 2 minutes. A Release build here takes 3 s for the report of
// 2,879 samples (replaying its orbits, mostly) and 0.3 s for the join; the bound leaves
// the sanitizer build on CI's two cores ample room.
constexpr double kReadStoppedRunSeconds = 60.0;

TEST(CampaignUnderMpirun, AStoppedRunOfTwoToTheFortySamplesIsReportedAndJoinedInTheTimeOfItsFinishedSamples) {
  const std::filesystem::path folder = Folder();
  const std::filesystem::path out = folder / "huge.h5";
  constexpr std::int64_t kMostSamples = std::int64_t{1} << 40;
  const Running run = Start(Mpirun(2) + RINGTOL_EXECUTABLE + " campaign " + RINGTOL_SOURCE_DIR +
                                "/examples/campaigns/default.toml --samples " + std::to_string(kMostSamples) +
                                " --out " + out.string() + " --quiet --commit-seconds 0.05",
                            "huge_sharded");
  ASSERT_TRUE(WaitFor([&] { return Done(out) > 0; }));
  kill(run.pid, SIGTERM);
  const Ended ended = Wait(run);  // mpirun's own exit code varies with its version
  const std::int64_t finished = ParseStop(ended.err, "SIGTERM").on_disk;
  ASSERT_GT(finished, 0);
  const std::string limit = "timeout " + std::to_string(static_cast<int>(kReadStoppedRunSeconds)) + " ";
  const Outcome report = RunRingtol(limit, "report " + out.string() + " --out " + (folder / "huge.html").string() +
                                               " --json " + (folder / "huge.json").string());
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const nlohmann::json samples = nlohmann::json::parse(testing::ReadText(folder / "huge.json")).at("samples");
  EXPECT_EQ(samples.at("campaign"), kMostSamples);
  EXPECT_EQ(samples.at("done"), finished);
  EXPECT_EQ(samples.at("used"), kMostSamples);
  EXPECT_EQ(samples.at("pending"), kMostSamples - finished);
  const Outcome join = RunRingtol(limit, "join " + out.string() + " --out " + (folder / "joined.h5").string());
  ASSERT_EQ(join.exit_code, 0) << join.err;
  EXPECT_EQ(Done(folder / "joined.h5"), finished);
}

// A second run started on the --out of a running one: told that another run writes it,
// never to remove it (a killed run's files get that advice, and only they).
void ExpectASecondRunToldAnotherRunWritesIt(const std::string& prefix) {
  const std::filesystem::path folder = Folder();
  const auto file = SlowCampaign(folder, 4000);
  const std::filesystem::path out = folder / "running.h5";
  const Running run = Start(prefix + RINGTOL_EXECUTABLE + " campaign " + file.string() + " --out " + out.string() +
                                " --quiet --commit-seconds 0.05",
                            "running");
  ASSERT_TRUE(WaitFor([&] { return Done(out) > 0; }));
  for (const char* resume : {"", "--resume"}) {
    EXPECT_THAT(Campaign(file, out, resume),
                ExitsWith(1, AllOf(HasSubstr(out.string() + ": another ringtol run is writing it"),
                                   HasSubstr("open for writing"), ::testing::Not(HasSubstr("remove")))))
        << resume;
  }
  kill(run.pid, SIGTERM);
  Wait(run);
  // Stopped, its files are a stopped run's: continue them, or remove them.
  EXPECT_THAT(Campaign(file, out), ExitsWith(1, AllOf(HasSubstr("--resume"), HasSubstr("remove"))));
}

TEST(Campaign, ASecondRunOnTheOutOfARunningOneIsToldAnotherRunWritesItNeverToRemoveIt) {
  ExpectASecondRunToldAnotherRunWritesIt("");
}

TEST(CampaignUnderMpirun, ASecondRunOnTheShardsOfARunningOneIsToldAnotherRunWritesThem) {
  ExpectASecondRunToldAnotherRunWritesIt(Mpirun(2));
}

// A truncated shard holds nothing to continue: verify, report and join name it and the
// resume that recovers it, and that resume (alone, of a run under mpirun) sets it aside,
// keeping its bytes, and computes its samples again, to the file an uninterrupted run writes.
TEST(CampaignUnderMpirun, ATruncatedShardIsNamedByEveryCommandAndAResumeComputesItsSamplesAgain) {
  const std::filesystem::path folder = Folder();
  const auto file = Write(folder / "campaign.toml", kCampaign);
  ASSERT_EQ(Campaign(file, folder / "whole.h5").exit_code, 0);
  const std::filesystem::path out = folder / "sharded.h5";
  ASSERT_EQ(Campaign(file, out, "", Mpirun(2)).exit_code, 0);
  const std::filesystem::path shard = ShardPath(out, 1);
  const std::string truncate = "truncate -s " + std::to_string(std::filesystem::file_size(shard) / 2) + " " +
                               shard.string();
  ASSERT_EQ(std::system(truncate.c_str()), 0);
  const std::string truncated = testing::ReadText(shard);
  const auto names_it = AllOf(HasSubstr("sharded.h5.shard-1 cannot be read"), HasSubstr("--out " + out.string() + " --resume"),
                              HasSubstr("sharded.h5.shard-1.unreadable"));
  EXPECT_THAT(RunRingtol("", "verify " + out.string()), ExitsWith(1, names_it));
  EXPECT_THAT(RunRingtol("", "report " + out.string() + " --out " + (folder / "report.html").string()),
              ExitsWith(1, names_it));
  EXPECT_THAT(RunRingtol("", "join " + out.string()), ExitsWith(1, names_it));
  const Outcome resumed = Campaign(file, out, "--resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_THAT(resumed.err, HasSubstr("set aside as " + shard.string() + ".unreadable"));
  EXPECT_EQ(testing::ReadText(ShardPath(out, 1).string() + ".unreadable"), truncated);
  ExpectSameResults(folder / "whole.h5", out);
  EXPECT_TRUE(CheckResults(out).intact());
}

// A real kill -9 while samples are being written, several times over, then a resume.
TEST(CampaignSlow, SigkillWhileWritingThenResumeMatchesAnUninterruptedRun) {
  const std::filesystem::path folder = Folder();
  constexpr std::int64_t kSamples = 1200;
  const auto file = Write(folder / "campaign.toml", testing::ReplaceOnce(kCampaign, "samples = 48", "samples = 1200"));
  ASSERT_EQ(Campaign(file, folder / "whole.h5").exit_code, 0);
  const std::filesystem::path out = folder / "killed.h5";
  // After each run has put more samples on disk, kill it at a different moment of its
  // commit cycle (commits every 50 ms).
  for (const int extra_milliseconds : {0, 37, 5, 71}) {
    const std::int64_t before = Done(out);
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      const std::string command = kMpiEnvironment + "exec " + RINGTOL_EXECUTABLE + " campaign " + file.string() +
                                  " --out " + out.string() + " --quiet --commit-seconds 0.05" +
                                  (std::filesystem::exists(out) ? " --resume" : "") + " >/dev/null 2>&1";
      execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (Done(out) <= before && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(extra_milliseconds));
    kill(child, SIGKILL);
    int status = 0;
    waitpid(child, &status, 0);
    EXPECT_TRUE(WIFSIGNALED(status)) << "the run finished before it was killed: make the campaign longer";
  }
  const std::int64_t missing = Pending(out);
  EXPECT_GT(missing, 0);
  EXPECT_LT(missing, kSamples);
  const Outcome resumed = Campaign(file, out, "--resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  ExpectSameResults(folder / "whole.h5", out);
}

// The six-roller stage (examples/six_roller_stage): four fixed rollers, two more than the
// ring needs, under two springs. Its campaign ends with every sample ok and none sent to
// the dynamic rung; before the support rule (docs/model.md §7, "Contacts that open") 227
// of its 512 samples failed, 225 of them as lift_off on the dynamic rung.
TEST(Campaign, TheSixRollerStagesCampaignEndsWithEverySampleOk) {
  const std::filesystem::path file =
      std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/six_roller_stage/campaign.toml";
  const Outcome run = Campaign(file, Folder() / "stage.h5", "--samples 128 --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json summary = nlohmann::json::parse(run.out);
  EXPECT_EQ(summary["samples_ok"], 128) << summary["failures"].dump();
  EXPECT_EQ(summary["rungs"]["dynamic"]["samples"], 0);
  EXPECT_EQ(summary["rungs"]["quasistatic"]["failed"], 0);
  EXPECT_TRUE(summary["life"]["computed"].get<bool>());
}

// The symmetric stage (examples/symmetric_stage): a third fixed roller opposite the spring.
// Its campaign ends with every sample ok, some with the outer rollers off the bore for part
// of the turn and the ring on the middle one; under a rule that asked for two fixed rollers
// nearly all of its draws failed (docs/model.md §7, "Contacts that open").
TEST(Campaign, TheSymmetricStagesCampaignEndsWithEverySampleOkThoughRollersOpen) {
  const std::filesystem::path file =
      std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/symmetric_stage/campaign.toml";
  const Outcome run = Campaign(file, Folder() / "symmetric.h5", "--samples 128 --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json summary = nlohmann::json::parse(run.out);
  EXPECT_EQ(summary["samples_ok"], 128) << summary["failures"].dump();
  EXPECT_GT(summary["contacts"]["samples_with_opening"].get<int>(), 0) << summary["contacts"].dump();
  EXPECT_EQ(summary["contacts"]["rollers"]["fixed_c"]["samples"], 0) << summary["contacts"].dump();  // the middle one holds
}

// A campaign that leaves the life out ([outputs] life = false): its summary, its report and
// its JSON say so instead of showing numbers, verify finds the file whole, and resuming it
// with the life on is refused, naming the key.
// The article's assembly with a third fixed roller at 250 deg and an order-2 bore of 0.1 mm
// (tests/solvers/contact_opening_test.cpp): fixed_a leaves the bore for about a third of
// every turn, the ring resting on the others. A campaign around it ends with every sample
// ok and stores each sample's shares, which are what `ringtol simulate` gives the sample
// replayed alone; its summary and its report count the samples and name the roller. The
// life, which reads the linear rung's phasors, is NaN for those samples and counted, and
// verify takes that for what it is, not for damage.
TEST(Campaign, RecordsWhichRollersLeftTheBoreAndHowOftenItHappens) {
  const std::filesystem::path folder = Folder();
  std::string scene = testing::ReadText(std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/paper/scene.toml");
  const std::string round = "harmonics = []                    # e.g.";
  const std::size_t at = scene.find(round);
  ASSERT_NE(at, std::string::npos) << "examples/paper/scene.toml's ring harmonics line moved";
  scene.replace(at, round.size(), "harmonics = [{ order = 2, amplitude_mm = 0.1, phase_deg = 30.0 }] #");
  scene += "\n[[rollers]]\nname = \"fixed_c\"\nangle_deg = 250.0\nradius_mm = 5.0\nmount = \"fixed\"\nwidth_mm = 4.0\ndensity_kg_per_m3 = 7850.0\n";
  testing::WriteText(folder / "scene.toml", scene);
  const std::filesystem::path file = folder / "campaign.toml", results = folder / "results.h5";
  testing::WriteText(file,
                     "scene = \"scene.toml\"\nseed = 5\n[design]\nkind = \"monte_carlo\"\nsamples = 8\n"
                     "[tolerances.roller_positions]\nzone_diameter_mm = 0.005\n[solver]\nname = \"quasistatic\"\n");
  const Outcome run = Campaign(file, results, "--json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const nlohmann::json summary = nlohmann::json::parse(run.out);
  EXPECT_EQ(summary["samples_ok"], 8) << summary["failures"].dump();
  EXPECT_EQ(summary["life"]["samples_without_life"], 8);
  EXPECT_EQ(summary["outputs"]["life_d_trajectory_mm"]["count"], 0);
  const nlohmann::json contacts = summary["contacts"];
  EXPECT_EQ(contacts["samples_ok"], 8);
  EXPECT_EQ(contacts["samples_with_opening"], 8);
  const nlohmann::json& fixed_a = contacts["rollers"]["fixed_a"];
  EXPECT_EQ(fixed_a["samples"], 8);
  EXPECT_GT(fixed_a["median_percent_of_turn"].get<double>(), 20.0);
  EXPECT_LT(fixed_a["max_percent_of_turn"].get<double>(), 50.0);
  for (const char* closed : {"spring", "fixed_b", "fixed_c"}) {
    EXPECT_EQ(contacts["rollers"][closed]["samples"], 0) << closed;
  }

  const jobs::CampaignReader reader(results);
  EXPECT_EQ(reader.identity().rollers, (std::vector<std::string>{"spring", "fixed_a", "fixed_b", "fixed_c"}));
  constexpr std::int64_t kReplayed = 3;
  const jobs::SampleRecord stored = reader.ReadSample(kReplayed);
  ASSERT_EQ(stored.off_bore.size(), 4u);
  const std::filesystem::path replayed = folder / "sample.toml";
  ASSERT_EQ(RunRingtol("", fmt::format("sample {} --index {} --scene {}", file.string(), kReplayed, replayed.string()))
                .exit_code,
            0);
  const Outcome alone = RunRingtol(
      "", fmt::format("simulate {} --solver quasistatic --steps {} --json", replayed.string(), stored.steps));
  ASSERT_EQ(alone.exit_code, 0) << alone.err;
  const nlohmann::json forces = nlohmann::json::parse(alone.out)["contact_force_N"];
  for (std::size_t r = 0; r < 4; ++r) {
    EXPECT_EQ(stored.off_bore[r], static_cast<double>(forces[r]["off_bore_percent"].get<float>())) << "roller " << r;
  }

  const std::filesystem::path html = folder / "report.html", json = folder / "report.json";
  const Outcome report = RunRingtol("", "report " + results.string() + " --out " + html.string() + " --json " + json.string());
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const nlohmann::json reported = nlohmann::json::parse(testing::ReadText(json));
  EXPECT_EQ(reported["contacts"], contacts);
  EXPECT_EQ(reported["life"]["samples_without_life"], 8);
  EXPECT_THAT(testing::ReadText(html), AllOf(HasSubstr("8 of 8 ok samples"), HasSubstr("has life values")));
  const Outcome verify = RunRingtol("", "verify " + results.string());
  EXPECT_EQ(verify.exit_code, 0) << verify.err << verify.out;
}

// Disposition of a measured ring (examples/measured/disposition.toml): its D_trajectory
// spreads about 0.150 mm with the rollers' draws, its q99 near 0.160 mm. Against 0.17 mm
// the ring passes (exit 0), against 0.16 mm the verdict is undecided and names the samples
// that would decide it (exit 4), against 0.15 mm it fails (exit 3); the report gives the
// same verdict as the summary.
TEST(Campaign, ADispositionGivesItsVerdictAsItsExitCode) {
  const std::filesystem::path folder = Folder();
  const std::filesystem::path example = std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/measured";
  const std::string text = testing::ReadText(example / "disposition.toml");
  ASSERT_NE(text.find("d_trajectory_mm = 0.17\n"), std::string::npos);
  for (const std::string name : {"scene.toml", "ring_profile.csv"}) {
    std::filesystem::copy_file(example / name, folder / name);
  }
  struct Case {
    const char* limit;
    int exit_code;
    const char* verdict;
  };
  for (const Case& c : {Case{"0.17", 0, "pass"}, Case{"0.16", 4, "undecided"}, Case{"0.15", 3, "fail"}}) {
    SCOPED_TRACE(c.limit);
    std::string campaign = text;
    campaign.replace(campaign.find("d_trajectory_mm = 0.17"), 22, std::string("d_trajectory_mm = ") + c.limit);
    const std::filesystem::path file = folder / (std::string("disposition_") + c.verdict + ".toml");
    const std::filesystem::path results = folder / (std::string(c.verdict) + ".h5");
    testing::WriteText(file, campaign);
    const Outcome run = Campaign(file, results, "--samples 512 --json");
    ASSERT_EQ(run.exit_code, c.exit_code) << run.err;
    const nlohmann::json disposition = nlohmann::json::parse(run.out)["disposition"];
    EXPECT_EQ(disposition["verdict"], c.verdict);
    EXPECT_EQ(disposition["yield"]["trials"], 512);
    EXPECT_DOUBLE_EQ(disposition["required_yield"].get<double>(), 0.99);
    if (c.exit_code == 4) {
      EXPECT_GT(disposition["samples_to_decide"].get<std::int64_t>(), 512);
    }
    const Outcome text_run = RunRingtol("", "campaign " + file.string() + " --out " + (folder / "text.h5").string() +
                                                " --samples 512 --quiet");
    EXPECT_EQ(text_run.exit_code, c.exit_code);
    EXPECT_THAT(text_run.out, HasSubstr(std::string("disposition       ") + c.verdict + ":"));
    std::filesystem::remove(folder / "text.h5");
    const std::filesystem::path html = folder / "report.html", json = folder / "report.json";
    const Outcome report = RunRingtol("", "report " + results.string() + " --out " + html.string() + " --json " + json.string());
    ASSERT_EQ(report.exit_code, 0) << report.err;
    EXPECT_EQ(nlohmann::json::parse(testing::ReadText(json))["disposition"], disposition);
    EXPECT_THAT(testing::ReadText(html), HasSubstr(std::string("Disposition</strong>: ") + c.verdict));
  }
}

// A campaign that draws its rings from measured parts keeps what identifies them: its
// results file names each export with its CRC-32, resuming with the same parts goes on, and
// resuming after one export changed is refused, naming it.
TEST(Campaign, APopulationIsPartOfTheResultsIdentityAndAChangedPartIsRefused) {
  const std::filesystem::path folder = Folder();
  std::filesystem::copy(std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/populations/rings", folder / "rings");
  const std::filesystem::path file = folder / "campaign.toml", results = folder / "results.h5";
  testing::WriteText(file, "scene = \"" + std::string(RINGTOL_SOURCE_DIR) +
                               "/examples/paper/scene.toml\"\n[design]\nkind = \"monte_carlo\"\nsamples = 8\n"
                               "[population.ring]\nfolder = \"rings\"\norders = 8\n"
                               "[tolerances.roller_positions]\nclass = \"IT7\"\n[solver]\nname = \"quasistatic\"\n"
                               "[outputs]\nlife = false\n");
  const Outcome run = Campaign(file, results, "--samples 4");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_THAT(jobs::CampaignReader(results).identity().population,
              AllOf(HasSubstr("draw = resample"), HasSubstr("ring_03.csv crc32 "), HasSubstr("ring_20.csv crc32 ")));
  const Outcome grown = Campaign(file, results, "--resume --samples 8");
  ASSERT_EQ(grown.exit_code, 0) << grown.err;

  std::string ring = testing::ReadText(folder / "rings/ring_03.csv");
  const std::size_t reading = ring.find("\n0.0, ") + 7;
  ring[reading + 8] = ring[reading + 8] == '9' ? '8' : '9';  // one reading, in its last digits
  testing::WriteText(folder / "rings/ring_03.csv", ring);
  const Outcome resumed = Campaign(file, results, "--resume --samples 12");
  EXPECT_EQ(resumed.exit_code, 1);
  EXPECT_THAT(resumed.err, AllOf(HasSubstr("population"), HasSubstr("ring_03.csv")));
}

// `ringtol match`: a measured ring and a batch of four rollers, three nearly round and one
// with a 20 um three-lobe form. Every one of the 24 assignments is simulated. A fixed roller's
// lobe moves the ring by its own size, while the soft spring takes up the spring roller's:
// the 12 assignments that put the lobed roller on a fixed slot rank last, tens of micrometres
// behind, and the best does not. What a random choice gives is the distribution over all 24,
// and the heuristic, limited below 24, also keeps the lobed roller off the fixed slots.
TEST(Match, RecommendsTheRollersThatLowerTheOutputAndStatesTheGainOverARandomChoice) {
  const std::filesystem::path folder = Folder();
  std::filesystem::create_directory(folder / "batch");
  for (int k = 0; k < 4; ++k) {
    const double lobe = k == 2 ? 20.0 : 0.3;  // um: roller_2 is the lobed one
    std::string csv = "angle_deg, deviation_um\n";
    for (int degree = 0; degree < 360; degree += 5) {
      const double theta = degree * 3.141592653589793 / 180.0;
      csv += fmt::format("{}, {:.4f}\n", degree, lobe * std::cos(3.0 * theta + k) + 0.2 * std::cos(2.0 * theta + 2.0 * k));
    }
    testing::WriteText(folder / "batch" / fmt::format("roller_{}.csv", k), csv);
  }
  const std::filesystem::path measured = std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/measured";
  for (const std::string name : {"scene.toml", "ring_profile.csv"}) std::filesystem::copy_file(measured / name, folder / name);
  const std::filesystem::path file = folder / "campaign.toml";
  testing::WriteText(file, "scene = \"scene.toml\"\n[population.rollers]\nfolder = \"batch\"\norders = 6\n"
                           "reference = \"own_mean\"\n[solver]\nname = \"quasistatic\"\n[spec]\nd_trajectory_mm = 0.2\n");
  const Outcome exhaustive = RunRingtol("", "match " + file.string() + " --json --top 24");
  ASSERT_EQ(exhaustive.exit_code, 0) << exhaustive.err;
  const nlohmann::json all = nlohmann::json::parse(exhaustive.out);
  EXPECT_EQ(all["output"], "d_trajectory_mm");
  EXPECT_TRUE(all["search"]["exhaustive"].get<bool>());
  EXPECT_EQ(all["search"]["assignments"], 24);
  ASSERT_EQ(all["ranked"].size(), 24u);
  const auto lobed_on_fixed = [](const nlohmann::json& ranked) {
    return ranked["rollers"]["fixed_a"] == "roller_2.csv" || ranked["rollers"]["fixed_b"] == "roller_2.csv";
  };
  EXPECT_FALSE(lobed_on_fixed(all["best"])) << all["best"].dump();
  for (std::size_t k = 0; k < 24; ++k) EXPECT_EQ(lobed_on_fixed(all["ranked"][k]), k >= 12) << k;
  const double best = all["best"]["value"].get<double>();
  EXPECT_GT(all["ranked"][12]["value"].get<double>() - all["ranked"][11]["value"].get<double>(), 0.01);
  EXPECT_EQ(all["random_choice"]["assignments"], 24);
  EXPECT_GT(all["random_choice"]["mean"].get<double>(), best);
  EXPECT_GT(all["gain_over_median_percent"].get<double>(), 0.0);

  const Outcome heuristic = RunRingtol("", "match " + file.string() + " --json --exhaustive-limit 10 --budget 4");
  ASSERT_EQ(heuristic.exit_code, 0) << heuristic.err;
  // The threads share the assignments out, never the answer.
  for (const char* threads : {"1", "3"}) {
    EXPECT_EQ(RunRingtol("", "match " + file.string() + " --json --exhaustive-limit 10 --budget 4 --threads " + threads).out,
              heuristic.out)
        << threads << " threads";
    EXPECT_EQ(RunRingtol("", "match " + file.string() + " --json --top 24 --threads " + threads).out, exhaustive.out)
        << threads << " threads";
  }
  const nlohmann::json searched = nlohmann::json::parse(heuristic.out);
  EXPECT_FALSE(searched["search"]["exhaustive"].get<bool>());
  EXPECT_THAT(searched["search"]["description"].get<std::string>(), HasSubstr("not proven optimal"));
  EXPECT_FALSE(lobed_on_fixed(searched["best"])) << searched["best"].dump();

  const Outcome text = RunRingtol("", "match " + file.string());
  EXPECT_THAT(text.out, AllOf(HasSubstr("search            exhaustive: all 24 assignments of 4 parts to 3 rollers"),
                              HasSubstr("random choice"), HasSubstr("gain")));

  // Only the fixed slots from the batch (the spring roller stays as the scene has it): the
  // 6 of 12 assignments that take the lobed roller rank last.
  const std::filesystem::path fixed = folder / "fixed.toml";
  testing::WriteText(fixed, "scene = \"scene.toml\"\n[population.rollers]\nfolder = \"batch\"\norders = 6\n"
                            "reference = \"own_mean\"\nrollers = [\"fixed_a\", \"fixed_b\"]\n[solver]\n"
                            "name = \"quasistatic\"\n[spec]\nd_trajectory_mm = 0.2\n");
  const Outcome two = RunRingtol("", "match " + fixed.string() + " --json --top 12");
  ASSERT_EQ(two.exit_code, 0) << two.err;
  const nlohmann::json slots = nlohmann::json::parse(two.out);
  EXPECT_EQ(slots["search"]["assignments"], 12);
  ASSERT_EQ(slots["ranked"].size(), 12u);
  EXPECT_FALSE(slots["best"]["rollers"].contains("spring")) << slots["best"].dump();
  for (std::size_t k = 0; k < 12; ++k) EXPECT_EQ(lobed_on_fixed(slots["ranked"][k]), k >= 6) << k;
  // Fitted to assemblies of the file's other tolerances (roller positions not yet bored):
  // the same 4 draws for every assignment, ranked by the mean; the lobed roller still goes
  // on the spring. A file with nothing else to draw is refused.
  const Outcome bare = RunRingtol("", "match " + file.string() + " --draws 4");
  EXPECT_EQ(bare.exit_code, 1);
  EXPECT_THAT(bare.err, HasSubstr("--draws draws the file's other tolerances"));
  const std::filesystem::path positions = folder / "positions.toml";
  testing::WriteText(positions, testing::ReadText(file) + "[tolerances.roller_positions]\nzone_diameter_mm = 0.07\n"
                                                          "[design]\nkind = \"sobol\"\nsamples = 8\n");
  const Outcome drawn = RunRingtol("", "match " + positions.string() + " --json --top 24 --draws 4");
  ASSERT_EQ(drawn.exit_code, 0) << drawn.err;
  const nlohmann::json robust = nlohmann::json::parse(drawn.out);
  EXPECT_EQ(robust["draws"], 4);
  ASSERT_EQ(robust["ranked"].size(), 24u);
  for (std::size_t k = 0; k < 24; ++k) {
    const nlohmann::json& entry = robust["ranked"][k];
    EXPECT_EQ(lobed_on_fixed(entry), k >= 12) << k;
    EXPECT_GE(entry["worst"].get<double>(), entry["value"].get<double>()) << k;
    EXPECT_EQ(entry["failed"], 0) << entry.dump();
  }
  EXPECT_NE(robust["best"]["value"].get<double>(), best);  // the positions moved it
  EXPECT_EQ(RunRingtol("", "match " + positions.string() + " --draws 9").exit_code, 1);  // beyond the design's 8

  testing::WriteText(folder / "ring.toml", "scene = \"scene.toml\"\n[tolerances.rollers]\nclass = \"Normal\"\n");
  const Outcome refused = RunRingtol("", "match " + (folder / "ring.toml").string());
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_THAT(refused.err, HasSubstr("[population.rollers]"));
}

// Disposition of a measured roller (examples/measured/roller_disposition.toml): the class
// draws the other two rollers only, so the measured one at fixed_a keeps its fitted outline
// in every assembly, and the verdict comes as for a ring.
TEST(Campaign, AMeasuredRollerIsJudgedWithTheOthersDrawnFromTheirClass) {
  const std::filesystem::path file = std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/measured/roller_disposition.toml";
  const std::filesystem::path results = Folder() / "roller.h5";
  const Outcome run = Campaign(file, results, "--samples 64 --json");
  ASSERT_EQ(run.exit_code, 4) << run.err;  // 64 samples cannot show 99 % at 95 % confidence
  EXPECT_EQ(nlohmann::json::parse(run.out)["disposition"]["verdict"], "undecided");
  const jobs::CampaignReader reader(results);
  int drawn_shapes = 0;
  for (const sampling::SampledInput& input : reader.identity().inputs) {
    EXPECT_FALSE(input.name.starts_with("roller.fixed_a.order") || input.name.starts_with("roller.fixed_a.size"))
        << input.name;
    drawn_shapes += input.source == sampling::ErrorSource::kRollerShape ? 1 : 0;
  }
  EXPECT_GT(drawn_shapes, 0);  // spring's and fixed_b's
}

// Disposition of a measured roller against a measured batch
// (examples/measured/roller_batch_disposition.toml): the batch fills the spring and fixed_b
// with two different parts of its 12, and fixed_a keeps its measured outline.
TEST(Campaign, AMeasuredRollerIsJudgedWithTheOthersFromAMeasuredBatch) {
  const std::filesystem::path file =
      std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/measured/roller_batch_disposition.toml";
  const std::filesystem::path results = Folder() / "roller.h5";
  const Outcome run = Campaign(file, results, "--samples 64 --json");
  ASSERT_EQ(run.exit_code, 4) << run.err;  // 64 samples cannot show 99 % at 95 % confidence
  EXPECT_EQ(nlohmann::json::parse(run.out)["disposition"]["verdict"], "undecided");
  const jobs::CampaignReader reader(results);
  std::vector<std::size_t> parts;
  for (std::size_t k = 0; k < reader.identity().inputs.size(); ++k) {
    const std::string& name = reader.identity().inputs[k].name;
    EXPECT_FALSE(name.starts_with("roller.fixed_a.population") || name.starts_with("roller.fixed_a.order") ||
                 name.starts_with("roller.fixed_a.size"))
        << name;  // its position is drawn, its shape is its own
    if (name.ends_with("population.part_index")) parts.push_back(k);
  }
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(reader.identity().inputs[parts[0]].name, "roller.spring.population.part_index");
  const std::size_t d = reader.identity().inputs.size();
  const std::vector<double> values = reader.ReadValues(0, 64);
  for (std::size_t i = 0; i < 64; ++i) {
    EXPECT_NE(values[i * d + parts[0]], values[i * d + parts[1]]) << "sample " << i;
    EXPECT_LT(values[i * d + parts[1]], 12.0);
  }
}

TEST(Campaign, WithoutTheLifeItSaysSoAndItsReportAndVerifyRead) {
  const std::filesystem::path folder = Folder();
  const std::string life_on = testing::SmallCampaign(std::string(RINGTOL_SOURCE_DIR) + "/examples/paper/scene.toml", 3, 8);
  const std::filesystem::path file = folder / "campaign.toml", results = folder / "results.h5";
  testing::WriteText(file, life_on + "[outputs]\nlife = false\n");
  const Outcome run = RunRingtol("", "campaign " + file.string() + " --out " + results.string() + " --threads 1 --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_THAT(run.out, AllOf(HasSubstr("were not computed"), HasSubstr("[outputs] life = false")));
  // The table's rows: one-revolution outputs only.
  EXPECT_THAT(run.out, AllOf(HasSubstr("\nd_trajectory_mm "), ::testing::Not(HasSubstr("\nlife_d_trajectory_mm ")),
                             ::testing::Not(HasSubstr("\nerror_motion_total_mm "))));

  const std::filesystem::path html = folder / "report.html", json = folder / "report.json";
  const Outcome report = RunRingtol("", "report " + results.string() + " --out " + html.string() + " --json " + json.string());
  ASSERT_EQ(report.exit_code, 0) << report.err;
  EXPECT_THAT(testing::ReadText(html), HasSubstr("were not computed"));
  const nlohmann::json reported = nlohmann::json::parse(testing::ReadText(json));
  EXPECT_EQ(reported["life"], nlohmann::json({{"computed", false}}));
  EXPECT_TRUE(reported["outputs"].contains("d_trajectory_mm"));
  EXPECT_FALSE(reported["outputs"].contains("life_d_trajectory_mm"));
  EXPECT_FALSE(reported.contains("error_motion"));

  const Outcome verify = RunRingtol("", "verify " + results.string());
  EXPECT_EQ(verify.exit_code, 0) << verify.err << verify.out;

  testing::WriteText(file, life_on);
  const Outcome resume = RunRingtol("", "campaign " + file.string() + " --out " + results.string() + " --resume --quiet");
  EXPECT_EQ(resume.exit_code, 1);
  EXPECT_THAT(resume.err, HasSubstr("outputs.life differs ('false' in the file, 'true' now)"));
}

// solver.accuracy = "fast": the summary's solver says it, the results file stores it, and
// resuming the file at the default accuracy is refused, naming the key.
TEST(Campaign, AtFastAccuracyItSaysSoAndResumeRefusesAnotherAccuracy) {
  const std::filesystem::path folder = Folder();
  const std::string full = testing::SmallCampaign(std::string(RINGTOL_SOURCE_DIR) + "/examples/paper/scene.toml", 3, 8);
  const std::filesystem::path file = folder / "campaign.toml", results = folder / "results.h5";
  testing::WriteText(file, testing::ReplaceOnce(full, "[solver]\n", "[solver]\naccuracy = \"fast\"\n"));
  const Outcome run = RunRingtol("", "campaign " + file.string() + " --out " + results.string() + " --threads 1 --quiet");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_THAT(run.out, HasSubstr("solver quasistatic, accuracy fast"));
  EXPECT_EQ(CampaignReader(results).identity().accuracy, solvers::Accuracy::kFast);

  testing::WriteText(file, full);
  const Outcome resume = RunRingtol("", "campaign " + file.string() + " --out " + results.string() + " --resume --quiet");
  EXPECT_EQ(resume.exit_code, 1);
  EXPECT_THAT(resume.err, HasSubstr("solver.accuracy differs ('fast' in the file, 'full' now)"));
}

}  // namespace
}  // namespace ringtol::jobs
