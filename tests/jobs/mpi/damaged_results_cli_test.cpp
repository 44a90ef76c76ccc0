// Damaged results files through the executable: copies of a real campaign's file with
// bytes flipped inside a chosen dataset's chunk (found through HDF5's chunk index, so the
// damage lands where the test says). `ringtol report` refuses them naming the file and the
// dataset, `ringtol verify` lists them, `--resume` computes the damaged samples again to
// the same bits; no command ends in an uncaught exception.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <hdf5.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "jobs/store/campaign_store.h"
#include "tests/support/damage.h"
#include "tests/support/mpi_environment.h"
#include "tests/support/shell.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;
using testing::FlipBytes;
using testing::OverwriteBytes;

const std::string kScene = (std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/paper/scene.toml").string();

// Quick to solve, with every kind of input; monte_carlo, so that the report screens the
// drawn values (where a non-finite value used to end in std::terminate).
const std::string kCampaign = "scene = \"" + kScene + R"("
seed = 5
[design]
kind = "monte_carlo"
samples = 40
[tolerances.ring]
circularity_mm = 0.2
max_order = 4
[tolerances.rollers]
class = "Normal"
max_order = 2
[tolerances.roller_positions]
zone_diameter_mm = 0.05
[tolerances.springs]
class = "pm10"
[solver]
name = "quasistatic"
path_tolerance_um = 2.0
)";

constexpr std::size_t kFlippedBytes = 8;  // as many as the damage that went unnoticed

class DamagedResults : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing::FreshTestFolder("damaged_results_cli_test");
    campaign_ = dir_ / "campaign.toml";
    testing::WriteText(campaign_, kCampaign);
    intact_ = dir_ / "intact.h5";
    const auto run = Ringtol("campaign " + campaign_.string() + " --out " + intact_.string() + " --quiet");
    ASSERT_EQ(run.exit_code, 0) << run.err;
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  testing::ShellOutcome Ringtol(const std::string& arguments) {
    return testing::RunShell(testing::kMpiEnvironment + "timeout 120 " + RINGTOL_EXECUTABLE + " " + arguments,
                             dir_ / "stderr.txt");
  }
  testing::ShellOutcome Report(const std::filesystem::path& results) {
    return Ringtol("report " + results.string() + " --out " + (dir_ / "report.html").string() + " --json " +
                   (dir_ / "report.json").string());
  }
  testing::ShellOutcome Resume(const std::filesystem::path& results) {
    return Ringtol("campaign " + campaign_.string() + " --out " + results.string() + " --quiet --resume");
  }
  std::filesystem::path Copy(const std::string& name, const std::filesystem::path& from) {
    const std::filesystem::path copy = dir_ / name;
    std::filesystem::copy_file(from, copy, std::filesystem::copy_options::overwrite_existing);
    return copy;
  }

  std::filesystem::path dir_, campaign_, intact_;
};

// Where the first chunk of `dataset` starts in the file, and how many bytes it has.
std::pair<haddr_t, hsize_t> FirstChunk(const std::filesystem::path& path, const std::string& dataset) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t data = H5Dopen2(file, dataset.c_str(), H5P_DEFAULT);
  const hsize_t origin[2] = {0, 0};
  unsigned mask = 0;
  haddr_t address = 0;
  hsize_t bytes = 0;
  EXPECT_GE(H5Dget_chunk_info_by_coord(data, origin, &mask, &address, &bytes), 0) << dataset;
  H5Dclose(data);
  H5Fclose(file);
  return {address, bytes};
}

// Every sample of two results files, field by field, solve time aside.
void ExpectSameResults(const std::filesystem::path& a, const std::filesystem::path& b) {
  const CampaignReader x(a);
  const CampaignReader y(b);
  ASSERT_EQ(x.samples(), y.samples());
  for (std::int64_t i = 0; i < x.samples(); ++i) {
    const SampleRecord p = x.ReadSample(i);
    const SampleRecord q = y.ReadSample(i);
    EXPECT_EQ(p.status, q.status) << i;
    EXPECT_EQ(std::memcmp(p.u.data(), q.u.data(), p.u.size() * sizeof(double)), 0) << i;
    EXPECT_EQ(std::memcmp(p.outputs.data(), q.outputs.data(), sizeof(p.outputs)), 0) << i;
  }
}

// What an uncaught exception prints, for every command that must not end in one.
const auto kNoAbort = AllOf(Not(HasSubstr("terminate called")), Not(HasSubstr("Aborted")));

TEST_F(DamagedResults, ReportAndVerifyNameTheDamagedDatasetAndResumeComputesItAgainToTheSameBits) {
  const auto verified = Ringtol("verify " + intact_.string());
  EXPECT_EQ(verified.exit_code, 0) << verified.out << verified.err;
  EXPECT_THAT(verified.out, HasSubstr("Verdict: intact"));
  const auto report = Report(intact_);
  ASSERT_EQ(report.exit_code, 0) << report.err;
  nlohmann::json intact_summary = nlohmann::json::parse(testing::ReadText(dir_ / "report.json"));
  intact_summary.erase("results");  // the file's path

  for (const std::string dataset : {"/inputs/u", "/outputs/d_trajectory_mm", "/outputs/status"}) {
    SCOPED_TRACE(dataset);
    const std::filesystem::path damaged = Copy("damaged.h5", intact_);
    const auto [address, bytes] = FirstChunk(damaged, dataset);
    FlipBytes(damaged, address + bytes / 2 - kFlippedBytes / 2, kFlippedBytes);

    const auto refused = Report(damaged);
    EXPECT_EQ(refused.exit_code, 1);
    EXPECT_THAT(refused.err, AllOf(HasSubstr(damaged.string()), HasSubstr("dataset " + dataset + " is damaged"),
                                   HasSubstr("ringtol verify"), kNoAbort));

    const auto listed = Ringtol("verify " + damaged.string());
    EXPECT_EQ(listed.exit_code, 1) << listed.err;
    EXPECT_THAT(listed.out, AllOf(HasSubstr(dataset), HasSubstr("DAMAGED at samples 0 to 39"),
                                  HasSubstr("A --resume computes 40 samples"), HasSubstr("Verdict: damaged")));
    const auto json = Ringtol("verify --json " + damaged.string());
    EXPECT_EQ(json.exit_code, 1);
    const nlohmann::json verdict = nlohmann::json::parse(json.out);
    EXPECT_EQ(verdict["verdict"], "damaged");
    EXPECT_EQ(verdict["resume_recomputes"], 40);

    const auto resumed = Resume(damaged);
    ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
    EXPECT_THAT(resumed.err, HasSubstr("dataset " + dataset + " was damaged at samples 0 to 39"));
    EXPECT_EQ(Ringtol("verify " + damaged.string()).exit_code, 0);
    ExpectSameResults(intact_, damaged);
    if (dataset == "/inputs/u") {  // the damage that used to change the report without a word
      ASSERT_EQ(Report(damaged).exit_code, 0);
      nlohmann::json summary = nlohmann::json::parse(testing::ReadText(dir_ / "report.json"));
      summary.erase("results");
      EXPECT_EQ(summary, intact_summary);
    }
  }
}

// The damage that used to end in std::terminate: a non-finite drawn value, in a file
// without checksums (as earlier builds wrote; h5repack strips the filters).
TEST_F(DamagedResults, ANonFiniteDrawnValueInAFileWithoutChecksumsIsNamedAsDamage) {
  const std::filesystem::path unchecked = dir_ / "unchecked.h5";
  const auto repacked = testing::RunShell("h5repack -f NONE " + intact_.string() + " " + unchecked.string(),
                                          dir_ / "stderr.txt");
  ASSERT_EQ(repacked.exit_code, 0) << repacked.err;
  const auto verified = Ringtol("verify " + unchecked.string());
  EXPECT_EQ(verified.exit_code, 2);
  EXPECT_THAT(verified.out, AllOf(HasSubstr("no checksum"), HasSubstr("cannot show damage")));

  const std::filesystem::path damaged = Copy("nan.h5", unchecked);
  const std::uint64_t address = FirstChunk(damaged, "/inputs/values").first;
  OverwriteBytes(damaged, address, "\xff\xff\xff\xff");  // sample 0's first drawn value (float32): a NaN
  const auto refused = Report(damaged);
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_THAT(refused.err, AllOf(HasSubstr(damaged.string()), HasSubstr("dataset /inputs/values is damaged"),
                                 HasSubstr("sample 0 is ok but holds a non-finite number at input 0"), kNoAbort));
  EXPECT_EQ(Ringtol("verify " + damaged.string()).exit_code, 1);
}

TEST_F(DamagedResults, DamagedMetadataGivesEveryCommandAClearErrorNamingTheFile) {
  const std::filesystem::path damaged = Copy("superblock.h5", intact_);
  FlipBytes(damaged, 12, kFlippedBytes);  // inside the superblock, which carries a checksum
  for (const auto& run : {Report(damaged), Ringtol("verify " + damaged.string()), Resume(damaged)}) {
    EXPECT_EQ(run.exit_code, 1);
    EXPECT_THAT(run.err, AllOf(HasSubstr("ringtol: error: " + damaged.string()), kNoAbort));
  }
}

}  // namespace
}  // namespace ringtol::jobs
