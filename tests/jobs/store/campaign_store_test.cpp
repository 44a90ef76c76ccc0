#include "jobs/store/campaign_store.h"

#include <hdf5.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "jobs/inputs/input_error.h"
#include "jobs/campaign/campaign.h"
#include "jobs/campaign/sample_record.h"
#include "tests/support/damage.h"
#include "tests/support/older_results.h"
#include "tests/support/small_campaign.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;
using testing::FlipBytes;

constexpr std::size_t kInputs = 4;
constexpr std::size_t kStoredMessageChars = 255;  // /failures/message: 256 bytes with the terminator

fs::path TestFolder() { return ringtol::testing::FreshTestFolder("campaign_store_test"); }

// The samples of runs, one by one.
std::vector<std::int64_t> Indices(const std::vector<SampleRange>& runs) {
  std::vector<std::int64_t> indices;
  for (const SampleRange& run : runs) {
    for (std::int64_t index = run.begin; index < run.end; ++index) indices.push_back(index);
  }
  return indices;
}

std::string ReadBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

CampaignIdentity TestIdentity() {
  CampaignIdentity identity;
  identity.ringtol_version = "0.1.0";
  identity.catalogue_version = "iso-2024.1";
  identity.campaign_path = "campaigns/demo.toml";
  identity.campaign_file = "[campaign]\nsamples = 100\nseed = 7\n\n[tolerances.ring]\nclass = \"IT5\"\n";
  identity.base_scene = "[ring]\nradius_mm = 302\n\n[[rollers]]\nname = \"spring\"\n";
  identity.design = "sobol";
  identity.solver = "quasistatic";
  identity.seed = 0x9E3779B97F4A7C15u;
  identity.rollers = {"spring", "fixed_a", "fixed_b"};
  for (std::size_t i = 0; i + 1 < kInputs; ++i) {
    const int order = static_cast<int>(i) + 2;
    identity.inputs.push_back({"ring.order" + std::to_string(order) + ".amplitude_um",
                               sampling::ErrorSource::kRingShape, -1, order, "ring.order" + std::to_string(order),
                               "ring"});
  }
  identity.inputs.push_back({"roller.spring.position.offset_um", sampling::ErrorSource::kRollerPosition, 1, 0,
                             "roller.spring.position", "roller.spring.position"});
  identity.spec = {{"runout_mm", 0.012}, {"max_contact_force_N", 2500.0}};
  return identity;
}

// A sample whose every field is a pure function of its index, so that any run, killed or
// not, must store the same bits. Every 11th fails in the solver, every 17th throws.
SampleRecord DeterministicRecord(std::int64_t index) {
  const double x = static_cast<double>(index);
  SampleRecord record;
  record.index = index;
  for (std::size_t j = 0; j < kInputs; ++j) {
    const double k = static_cast<double>(j);
    record.u.push_back(std::fmod(0.5 + x * 0.6180339887498949 + k * 0.7548776662466927, 1.0));
    record.values.push_back(std::sin(x + k) * 1e3 / 3.0);
  }
  record.redraws = static_cast<std::int32_t>(index % 3);
  record.steps = 360 + static_cast<std::int32_t>(index % 7);
  record.rung = static_cast<std::int8_t>(index % 3);
  record.d_trajectory_error = x * 1e-7;
  record.solve_time = 1e-3 * std::sqrt(x + 1.0);
  if (index % 11 == 5) {
    record.status = FromSolverStatus(solvers::Status::kNotConverged);
    record.message = "Newton iteration failed at angle " + std::to_string(index % 360) + " deg";
    record.outputs.fill(std::numeric_limits<double>::quiet_NaN());
  } else if (index % 17 == 3) {
    record.status = SampleStatus::kException;
    record.message = "sample " + std::to_string(index) + ": " + std::string(300, 'x');
    record.outputs.fill(std::numeric_limits<double>::quiet_NaN());
  } else {
    record.status = SampleStatus::kOk;
    for (std::size_t k = 0; k < kOutputCount; ++k) record.outputs[k] = x * 1e-3 + static_cast<double>(k) / 7.0;
    // Shares no float32 holds exactly, and a roller that never leaves the bore.
    record.off_bore = {std::fmod(x * 0.37, 100.0), 0.0, 100.0 / (x + 3.0)};
  }
  return record;
}

std::vector<std::uint64_t> Bits(const std::vector<double>& values) {
  std::vector<std::uint64_t> bits;
  for (const double value : values) bits.push_back(std::bit_cast<std::uint64_t>(value));
  return bits;
}

std::vector<std::uint64_t> Bits(const std::array<double, kOutputCount>& values) {
  return Bits(std::vector<double>(values.begin(), values.end()));
}

// What the file holds for `written`: values rounded to float32, messages cut to 255 bytes,
// outputs NaN unless ok.
SampleRecord AsStored(SampleRecord written) {
  for (double& value : written.values) value = static_cast<double>(static_cast<float>(value));
  if (written.message.size() > kStoredMessageChars) written.message.resize(kStoredMessageChars);
  for (double& share : written.off_bore) share = static_cast<double>(static_cast<float>(share));
  if (written.status != SampleStatus::kOk) {
    written.outputs.fill(std::numeric_limits<double>::quiet_NaN());
    written.d_trajectory_error = std::numeric_limits<double>::quiet_NaN();
    written.off_bore.clear();
  }
  return written;
}

// What a file of schema 3 or before holds for a stored record: no life outputs.
SampleRecord WithoutLife(SampleRecord stored) {
  for (std::size_t k = 0; k < kOutputCount; ++k) {
    if (IsLifeOutput(k)) stored.outputs[k] = std::numeric_limits<double>::quiet_NaN();
  }
  return stored;
}

// Bit for bit (NaN included), field by field, so that a failure says which field.
void ExpectStored(const SampleRecord& actual, const SampleRecord& written) {
  const SampleRecord expected = AsStored(written);
  SCOPED_TRACE("sample " + std::to_string(expected.index));
  EXPECT_EQ(actual.index, expected.index);
  EXPECT_EQ(actual.status, expected.status);
  EXPECT_EQ(actual.message, expected.message);
  EXPECT_EQ(Bits(actual.u), Bits(expected.u));
  EXPECT_EQ(Bits(actual.values), Bits(expected.values));
  EXPECT_EQ(actual.redraws, expected.redraws);
  EXPECT_EQ(actual.steps, expected.steps);
  EXPECT_EQ(Bits(actual.outputs), Bits(expected.outputs));
  EXPECT_EQ(Bits(actual.off_bore), Bits(expected.off_bore));
  EXPECT_EQ(actual.rung, expected.rung);
  EXPECT_EQ(std::bit_cast<std::uint64_t>(actual.d_trajectory_error), std::bit_cast<std::uint64_t>(expected.d_trajectory_error));
  EXPECT_EQ(std::bit_cast<std::uint64_t>(actual.solve_time), std::bit_cast<std::uint64_t>(expected.solve_time));
}

void ExpectPendingRow(const SampleRecord& actual) {
  SCOPED_TRACE("sample " + std::to_string(actual.index));
  EXPECT_EQ(actual.status, SampleStatus::kPending);
  EXPECT_TRUE(std::all_of(actual.u.begin(), actual.u.end(), [](double v) { return std::isnan(v); }));
  EXPECT_TRUE(std::all_of(actual.outputs.begin(), actual.outputs.end(), [](double v) { return std::isnan(v); }));
  EXPECT_EQ(actual.steps, 0);
  EXPECT_EQ(actual.rung, kNoRung);
  EXPECT_EQ(actual.message, "");
}

std::string InputErrorOf(const std::function<void()>& action) {
  return ringtol::testing::MessageOf<InputError>(action);
}

// Writes every pending sample of [0, samples) as its DeterministicRecord, committing every
// `batch`, each batch added back to front like results arriving from many ranks.
void WriteDeterministic(
    const fs::path& path, std::int64_t samples, std::size_t batch, const std::function<void()>& opened = [] {}) {
  // The test identity is no campaign that could replay a draw: every sample keeps its inputs.
  CampaignStoreOptions options;
  options.inputs_stored_below = std::numeric_limits<std::int64_t>::max();
  CampaignStore store = fs::exists(path) ? CampaignStore::Resume(path, TestIdentity(), samples)
                                         : CampaignStore::Create(path, TestIdentity(), samples, options);
  opened();
  const std::vector<std::int64_t> pending = Indices(store.Pending(0, samples));
  for (std::size_t i = 0; i < pending.size(); ++i) {
    const std::size_t first = i / batch * batch;
    const std::size_t last = std::min(first + batch, pending.size()) - 1;
    store.Add(DeterministicRecord(pending[first + last - i]));
    if (store.buffered() == batch) store.Commit();
  }
}

// ---------------------------------------------------------------------------------------

TEST(SampleStatus, SharesNumbersAndNamesWithSolverStatuses) {
  for (int value = 0; value <= kLastSolverStatus; ++value) {
    const auto status = static_cast<solvers::Status>(value);
    EXPECT_EQ(static_cast<int>(FromSolverStatus(status)), value);
    EXPECT_EQ(SampleStatusName(FromSolverStatus(status)), solvers::StatusName(status));
  }
  EXPECT_EQ(SampleStatusName(SampleStatus::kPending), "pending");
  EXPECT_EQ(SampleStatusName(SampleStatus::kOk), "ok");
  EXPECT_EQ(SampleStatusName(SampleStatus::kException), "exception");
  EXPECT_EQ(SampleStatusName(SampleStatus::kNonFiniteOutput), "non_finite_output");
  EXPECT_EQ(SampleStatusName(SampleStatus::kSamplingFailed), "sampling_failed");
}

TEST(SampleStatus, ListsEveryStatusOnceWithPendingFirstAndDistinctNames) {
  const std::vector<SampleStatus>& all = AllSampleStatuses();
  ASSERT_EQ(all.size(), 15u);  // pending, the 11 solver statuses, 3 campaign failures
  EXPECT_EQ(all.front(), SampleStatus::kPending);
  std::set<std::string_view> names;
  std::set<int> values;
  for (const SampleStatus status : all) {
    names.insert(SampleStatusName(status));
    values.insert(static_cast<int>(status));
  }
  EXPECT_EQ(names.size(), all.size());
  EXPECT_EQ(values.size(), all.size());
}

// The rung column names its numbers as the status column does, so that h5py and h5dump
// show "quasistatic" rather than 1; the numbers themselves read back as written.
TEST(CampaignStore, TheRungColumnIsAnEnumerationOfTheRungsNames) {
  const fs::path path = TestFolder() / "results.h5";
  {
    CampaignStore store = CampaignStore::Create(path, TestIdentity(), 4);
    for (std::int64_t i = 0; i < 3; ++i) store.Add(DeterministicRecord(i));
  }
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const hid_t dataset = H5Dopen2(file, "/outputs/rung", H5P_DEFAULT);
  const hid_t type = H5Dget_type(dataset);
  EXPECT_EQ(H5Tget_class(type), H5T_ENUM);
  std::map<std::string, int> members;
  for (int m = 0; m < H5Tget_nmembers(type); ++m) {
    char* name = H5Tget_member_name(type, static_cast<unsigned>(m));
    std::int8_t value = 0;
    H5Tget_member_value(type, static_cast<unsigned>(m), &value);
    members[name] = value;
    H5free_memory(name);
  }
  H5Tclose(type);
  H5Dclose(dataset);
  H5Fclose(file);
  EXPECT_EQ(members, (std::map<std::string, int>{{"none", -1}, {"linear", 0}, {"quasistatic", 1}, {"dynamic", 2}}));
  const CampaignReader reader(path);
  const std::vector<std::int8_t> rungs = reader.ReadRungs(0, 4);
  EXPECT_EQ(rungs, (std::vector<std::int8_t>{DeterministicRecord(0).rung, DeterministicRecord(1).rung,
                                             DeterministicRecord(2).rung, kNoRung}));
}

TEST(CampaignStore, RoundTripsEveryFieldBitForBitAcrossOutOfOrderCommits) {
  const fs::path path = TestFolder() / "results.h5";
  constexpr std::int64_t kSamples = 40;
  const std::vector<std::int64_t> first = {31, 5, 6, 0, 7, 39, 20, 3};
  const std::vector<std::int64_t> second = {19, 2, 33, 4, 21, 1, 17};
  {
    CampaignStore store = CampaignStore::Create(path, TestIdentity(), kSamples);
    EXPECT_EQ(store.samples(), kSamples);
    EXPECT_EQ(store.path(), path);
    for (const std::int64_t index : first) store.Add(DeterministicRecord(index));
    EXPECT_EQ(store.buffered(), first.size());
    store.Commit();
    EXPECT_EQ(store.buffered(), 0u);
    for (const std::int64_t index : second) store.Add(DeterministicRecord(index));
    store.Commit();
  }
  const CampaignReader reader(path);
  EXPECT_EQ(reader.samples(), kSamples);
  EXPECT_EQ(reader.schema_version(), kCampaignSchemaVersion);
  const CampaignIdentity expected = TestIdentity();
  const CampaignIdentity& identity = reader.identity();
  EXPECT_EQ(identity.ringtol_version, expected.ringtol_version);
  EXPECT_EQ(identity.catalogue_version, expected.catalogue_version);
  EXPECT_EQ(identity.campaign_path, expected.campaign_path);
  EXPECT_EQ(identity.campaign_file, expected.campaign_file);
  EXPECT_EQ(identity.base_scene, expected.base_scene);
  EXPECT_EQ(identity.design, expected.design);
  EXPECT_EQ(identity.solver, expected.solver);
  EXPECT_EQ(identity.seed, expected.seed);
  EXPECT_EQ(identity.rollers, expected.rollers);
  ASSERT_EQ(identity.inputs.size(), expected.inputs.size());
  for (std::size_t i = 0; i < expected.inputs.size(); ++i) {
    EXPECT_EQ(identity.inputs[i].name, expected.inputs[i].name);
    EXPECT_EQ(identity.inputs[i].source, expected.inputs[i].source);
    EXPECT_EQ(identity.inputs[i].roller, expected.inputs[i].roller);
    EXPECT_EQ(identity.inputs[i].order, expected.inputs[i].order);
    EXPECT_EQ(identity.inputs[i].quantity, expected.inputs[i].quantity);
    EXPECT_EQ(identity.inputs[i].component, expected.inputs[i].component);
  }
  ASSERT_EQ(identity.spec.size(), 2u);  // in kOutputNames order
  EXPECT_EQ(identity.spec[0].output, "runout_mm");
  EXPECT_EQ(std::bit_cast<std::uint64_t>(identity.spec[0].upper), std::bit_cast<std::uint64_t>(0.012));
  EXPECT_EQ(identity.spec[1].output, "max_contact_force_N");
  EXPECT_EQ(identity.spec[1].upper, 2500.0);

  std::set<std::int64_t> written(first.begin(), first.end());
  written.insert(second.begin(), second.end());
  const std::vector<SampleStatus> statuses = reader.ReadStatus(0, kSamples);
  for (std::int64_t index = 0; index < kSamples; ++index) {
    if (written.count(index) > 0) {
      ExpectStored(reader.ReadSample(index), DeterministicRecord(index));
      EXPECT_EQ(statuses[static_cast<std::size_t>(index)], DeterministicRecord(index).status);
    } else {
      ExpectPendingRow(reader.ReadSample(index));
    }
  }
  const std::vector<double> runout = reader.ReadOutput("runout_mm", 4, 3);
  const std::vector<double> expected_runout = {AsStored(DeterministicRecord(4)).outputs[3],
                                               AsStored(DeterministicRecord(5)).outputs[3],
                                               AsStored(DeterministicRecord(6)).outputs[3]};
  EXPECT_EQ(Bits(runout), Bits(expected_runout));
  EXPECT_TRUE(std::isnan(runout[1]));  // sample 5 did not converge
  EXPECT_THROW(reader.ReadOutput("runout_um", 0, 1), std::invalid_argument);
  EXPECT_THROW(reader.ReadStatus(kSamples - 1, 2), std::out_of_range);
}

TEST(CampaignStore, StoresNaNOutputsForFailedSamplesWhateverTheRecordSays) {
  const fs::path path = TestFolder() / "results.h5";
  SampleRecord failed = DeterministicRecord(0);
  failed.status = SampleStatus::kNonFiniteOutput;
  failed.message = "runout_mm is infinite";
  failed.outputs.fill(1.5);
  CampaignStore::Create(path, TestIdentity(), 1).Add(failed);
  const SampleRecord stored = CampaignReader(path).ReadSample(0);
  EXPECT_EQ(stored.status, SampleStatus::kNonFiniteOutput);
  EXPECT_TRUE(std::all_of(stored.outputs.begin(), stored.outputs.end(), [](double v) { return std::isnan(v); }));
}

TEST(CampaignStore, TruncatesMessagesTo255BytesWithoutSplittingACharacter) {
  const fs::path path = TestFolder() / "results.h5";
  SampleRecord ascii = DeterministicRecord(0);
  ascii.status = SampleStatus::kException;
  ascii.message = std::string(254, 'a') + "bcdef";
  SampleRecord utf8 = ascii;
  utf8.index = 1;
  utf8.message = std::string(254, 'a') + "\xC2\xB5m";  // "µ" would straddle byte 255
  {
    CampaignStore store = CampaignStore::Create(path, TestIdentity(), 2);
    store.Add(ascii);
    store.Add(utf8);
  }
  const CampaignReader reader(path);
  EXPECT_EQ(reader.ReadSample(0).message, std::string(254, 'a') + "b");
  EXPECT_EQ(reader.ReadSample(1).message, std::string(254, 'a'));
}

TEST(CampaignStore, ReportsSamplesPendingUntilTheirCommit) {
  const fs::path path = TestFolder() / "results.h5";
  CampaignStore store = CampaignStore::Create(path, TestIdentity(), 6);
  EXPECT_EQ(Indices(store.Pending(0, 6)), (std::vector<std::int64_t>{0, 1, 2, 3, 4, 5}));
  store.Add(DeterministicRecord(4));
  store.Add(DeterministicRecord(1));
  EXPECT_EQ(Indices(store.Pending(0, 6)), (std::vector<std::int64_t>{0, 1, 2, 3, 4, 5}));
  store.Commit();
  EXPECT_EQ(Indices(store.Pending(0, 6)), (std::vector<std::int64_t>{0, 2, 3, 5}));
  EXPECT_EQ(Indices(store.Pending(1, 4)), (std::vector<std::int64_t>{2, 3}));
  EXPECT_EQ(Indices(store.Pending(3, 3)), (std::vector<std::int64_t>{}));
  EXPECT_THROW(store.Pending(2, 7), std::out_of_range);
}

// Shards: the main file and two shards of a 40-sample campaign in chunks of 8. Block 0 and
// half of block 2 are the main file's; the rest of block 2 and blocks 1 and 3 one shard's,
// block 4 the other's, which also holds a different record of sample 0.
constexpr std::int64_t kShardedSamples = 40;
constexpr std::int64_t kShardChunk = 8;

CampaignStoreOptions ShardChunks() {
  CampaignStoreOptions options;
  options.chunk_samples = kShardChunk;
  return options;
}

void WriteRange(CampaignStore& store, std::int64_t begin, std::int64_t end) {
  for (std::int64_t index = begin; index < end; ++index) store.Add(DeterministicRecord(index));
  store.Commit();
}

// The main file, still open, and its two shards, closed.
CampaignStore ShardedCampaign(const fs::path& path) {
  CampaignStore main = CampaignStore::Create(path, TestIdentity(), kShardedSamples, ShardChunks());
  WriteRange(main, 0, 8);
  WriteRange(main, 16, 20);
  {
    CampaignStore shard = CampaignStore::Create(ShardPath(path, 1), TestIdentity(), kShardedSamples, ShardChunks());
    WriteRange(shard, 8, 16);
    WriteRange(shard, 20, 32);
  }
  {
    CampaignStore shard = CampaignStore::Create(ShardPath(path, 2), TestIdentity(), kShardedSamples, ShardChunks());
    WriteRange(shard, 32, 40);
    SampleRecord other = DeterministicRecord(1);
    other.index = 0;
    shard.Add(other);
  }
  return main;
}

TEST(CampaignStore, AbsorbingShardsStoresEverySampleAsIfWrittenDirectly) {
  const fs::path path = TestFolder() / "results.h5";
  {
    CampaignStore main = ShardedCampaign(path);
    EXPECT_EQ(main.chunk_rows(), kShardChunk);
    ASSERT_EQ(FindShards(path), (std::vector<fs::path>{ShardPath(path, 1), ShardPath(path, 2)}));
    const CampaignStore::Absorbed first = main.Absorb(ShardPath(path, 1));
    EXPECT_EQ(first.samples, 20);        // blocks 1 and 3 whole, half of block 2 one by one
    EXPECT_EQ(first.chunk_samples, 16);  // blocks 1 and 3
    EXPECT_GT(first.bytes, 0);
    const CampaignStore::Absorbed second = main.Absorb(ShardPath(path, 2));
    EXPECT_EQ(second.samples, 8);  // block 4; sample 0 is the main file's already
    EXPECT_EQ(second.chunk_samples, 8);
    EXPECT_EQ(FindShards(path).size(), 2u);  // left for their owner to remove
    EXPECT_TRUE(main.Pending(0, kShardedSamples).empty());
  }
  const CampaignReader reader(path);
  for (std::int64_t index = 0; index < kShardedSamples; ++index) {
    ExpectStored(reader.ReadSample(index), DeterministicRecord(index));
  }
  const ResultsCheck check = CheckResults(path);
  EXPECT_TRUE(check.intact());
  EXPECT_TRUE(check.checksummed());
  EXPECT_EQ(check.done, kShardedSamples);
}

TEST(CampaignStore, AbsorbingAShardAgainCopiesNothingTwice) {
  const fs::path path = TestFolder() / "results.h5";
  {
    CampaignStore main = ShardedCampaign(path);
    main.Absorb(ShardPath(path, 1));
    const CampaignStore::Absorbed again = main.Absorb(ShardPath(path, 1));
    EXPECT_EQ(again.samples, 0);
  }
  const CampaignReader reader(path);
  for (std::int64_t index = 0; index < 32; ++index) ExpectStored(reader.ReadSample(index), DeterministicRecord(index));
}

TEST(CampaignStore, AbsorbRefusesAShardOfAnotherCampaignAndLeavesIt) {
  const fs::path path = TestFolder() / "results.h5";
  CampaignStore main = CampaignStore::Create(path, TestIdentity(), kShardedSamples, ShardChunks());
  CampaignIdentity other = TestIdentity();
  other.seed += 1;
  { CampaignStore::Create(ShardPath(path, 1), other, kShardedSamples, ShardChunks()); }
  EXPECT_THAT(InputErrorOf([&] { main.Absorb(ShardPath(path, 1)); }),
              AllOf(HasSubstr(ShardPath(path, 1).string()), HasSubstr("another campaign"), HasSubstr("seed")));
  EXPECT_TRUE(fs::exists(ShardPath(path, 1)));
}

TEST(FindShards, ListsTheShardsOfOneResultsFileInRankOrder) {
  const fs::path folder = TestFolder();
  const fs::path path = folder / "results.h5";
  for (const char* name : {"results.h5.shard-10", "results.h5.shard-2", "results.h5.shard-x", "results.h5.shard-",
                           "other.h5.shard-1"}) {
    std::ofstream(folder / name) << "";
  }
  EXPECT_EQ(FindShards(path), (std::vector<fs::path>{ShardPath(path, 2), ShardPath(path, 10)}));
  EXPECT_EQ(ShardPath(path, 3), folder / "results.h5.shard-3");
}

// The store, not the command, decides how a run writes: one file, or a shard per rank.
TEST(PlanCampaignShards, KeepsOneRankInOneFileAndAdoptsAFileBegunAloneAsShardZero) {
  const fs::path path = TestFolder() / "results.h5";
  EXPECT_FALSE(PlanCampaignShards(path, TestIdentity(), 4, 1, false).sharded);
  EXPECT_TRUE(PlanCampaignShards(path, TestIdentity(), 4, 2, false).sharded);
  WriteDeterministic(path, 4, 4);
  EXPECT_FALSE(PlanCampaignShards(path, TestIdentity(), 4, 1, true).sharded);
  const std::string bytes = ReadBytes(path);
  const ShardPlan plan = PlanCampaignShards(path, TestIdentity(), 4, 2, true);
  EXPECT_TRUE(plan.sharded);
  EXPECT_TRUE(plan.stale.empty());
  EXPECT_FALSE(fs::exists(path));
  EXPECT_EQ(ReadBytes(ShardPath(path, 0)), bytes);
  // Shards of ranks a run does not have are its stale ones; a new run refuses them all.
  fs::rename(ShardPath(path, 0), ShardPath(path, 3));
  EXPECT_EQ(PlanCampaignShards(path, TestIdentity(), 4, 2, true).stale, std::vector<fs::path>{ShardPath(path, 3)});
  EXPECT_THAT(InputErrorOf([&] { PlanCampaignShards(path, TestIdentity(), 4, 2, false); }),
              AllOf(HasSubstr("shards of an earlier run"), HasSubstr("--resume")));
}

TEST(CampaignStore, KeepsTheLastOfTwoRecordsForOneSample) {
  const fs::path path = TestFolder() / "results.h5";
  SampleRecord retried = DeterministicRecord(1);
  retried.index = 0;
  {
    CampaignStore store = CampaignStore::Create(path, TestIdentity(), 1);
    store.Add(DeterministicRecord(0));
    store.Add(retried);
  }
  ExpectStored(CampaignReader(path).ReadSample(0), retried);
}

TEST(CampaignStore, RejectsRecordsThatDoNotFitTheCampaign) {
  const fs::path path = TestFolder() / "results.h5";
  CampaignStore store = CampaignStore::Create(path, TestIdentity(), 3);
  EXPECT_THROW(store.Add(DeterministicRecord(3)), std::invalid_argument);
  EXPECT_THROW(store.Add(DeterministicRecord(-1)), std::invalid_argument);
  SampleRecord short_u = DeterministicRecord(0);
  short_u.u.pop_back();
  EXPECT_THROW(store.Add(short_u), std::invalid_argument);
  SampleRecord pending = DeterministicRecord(0);
  pending.status = SampleStatus::kPending;
  EXPECT_THROW(store.Add(pending), std::invalid_argument);
  EXPECT_EQ(store.buffered(), 0u);
}

TEST(CampaignStore, CreateRefusesAnExistingPathAndAMissingDirectory) {
  const fs::path folder = TestFolder();
  const fs::path existing = folder / "results.h5";
  std::ofstream(existing) << "precious";
  EXPECT_THAT(InputErrorOf([&] { CampaignStore::Create(existing, TestIdentity(), 5); }),
              AllOf(HasSubstr(existing.string()), HasSubstr("already exists"), HasSubstr("--resume")));
  EXPECT_EQ(ReadBytes(existing), "precious");

  const fs::path orphan = folder / "no_such_folder" / "results.h5";
  EXPECT_THAT(InputErrorOf([&] { CampaignStore::Create(orphan, TestIdentity(), 5); }),
              AllOf(HasSubstr(orphan.string()), HasSubstr("does not exist")));
  EXPECT_FALSE(fs::exists(orphan.parent_path()));
  EXPECT_EQ(std::distance(fs::directory_iterator(folder), fs::directory_iterator()), 1);  // no temporary left
}

TEST(CampaignStore, ResumesTheSameCampaignKeepingItsSamples) {
  const fs::path path = TestFolder() / "results.h5";
  {
    CampaignStore store = CampaignStore::Create(path, TestIdentity(), 10);
    store.Add(DeterministicRecord(2));
  }
  CampaignIdentity moved = TestIdentity();
  moved.campaign_path = "elsewhere/demo.toml";  // provenance only
  {
    CampaignStore store = CampaignStore::Resume(path, moved, 10);
    EXPECT_EQ(store.samples(), 10);
    EXPECT_EQ(Indices(store.Pending(0, 3)), (std::vector<std::int64_t>{0, 1}));
    store.Add(DeterministicRecord(7));
  }
  const CampaignReader reader(path);
  ExpectStored(reader.ReadSample(2), DeterministicRecord(2));
  ExpectStored(reader.ReadSample(7), DeterministicRecord(7));
  EXPECT_EQ(reader.identity().campaign_path, "campaigns/demo.toml");
}

TEST(CampaignStore, ResumeGrowsTheCampaignWithTheNewSamplesPending) {
  const fs::path path = TestFolder() / "results.h5";
  {
    CampaignStore store = CampaignStore::Create(path, TestIdentity(), 5);
    for (std::int64_t index = 0; index < 5; ++index) store.Add(DeterministicRecord(index));
  }
  {
    CampaignStore store = CampaignStore::Resume(path, TestIdentity(), 12);
    EXPECT_EQ(store.samples(), 12);
    EXPECT_EQ(Indices(store.Pending(0, 12)), (std::vector<std::int64_t>{5, 6, 7, 8, 9, 10, 11}));
    store.Add(DeterministicRecord(11));
  }
  const CampaignReader reader(path);
  EXPECT_EQ(reader.samples(), 12);
  for (std::int64_t index = 0; index < 5; ++index) ExpectStored(reader.ReadSample(index), DeterministicRecord(index));
  for (std::int64_t index = 5; index < 11; ++index) ExpectPendingRow(reader.ReadSample(index));
  ExpectStored(reader.ReadSample(11), DeterministicRecord(11));
}

TEST(CampaignStore, ResumeRefusesToShrinkTheCampaign) {
  const fs::path path = TestFolder() / "results.h5";
  CampaignStore::Create(path, TestIdentity(), 8);
  const std::string before = ReadBytes(path);
  EXPECT_THAT(InputErrorOf([&] { CampaignStore::Resume(path, TestIdentity(), 7); }),
              AllOf(HasSubstr(path.string()), HasSubstr("holds 8 samples"), HasSubstr("7")));
  EXPECT_EQ(ReadBytes(path), before);
}

// A Latin hypercube of 8 is not the first 8 of one of 12: growing it would leave a file
// stratified in neither. The same size resumes.
TEST(CampaignStore, ResumeRefusesToGrowALatinHypercube) {
  const fs::path path = TestFolder() / "results.h5";
  CampaignIdentity latin = TestIdentity();
  latin.design = "latin_hypercube";
  CampaignStore::Create(path, latin, 8);
  const std::string before = ReadBytes(path);
  EXPECT_THAT(InputErrorOf([&] { CampaignStore::Resume(path, latin, 12); }),
              AllOf(HasSubstr(path.string()), HasSubstr("Latin hypercube of 8 samples"), HasSubstr("cannot grow to 12"),
                    HasSubstr("--samples 12")));
  EXPECT_EQ(ReadBytes(path), before);
  EXPECT_NO_THROW(CampaignStore::Resume(path, latin, 8));
}

TEST(CampaignStore, ResumeRefusesAnotherCampaignNamingWhatDiffers) {
  const fs::path path = TestFolder() / "results.h5";
  CampaignStore::Create(path, TestIdentity(), 8);
  const std::string before = ReadBytes(path);
  struct Change {
    const char* expected;
    std::function<void(CampaignIdentity&)> apply;
  };
  const std::vector<Change> changes = {
      {"ringtol_version differs ('0.1.0' in the file, '0.2.0' now)", [](auto& id) { id.ringtol_version = "0.2.0"; }},
      {"catalogue_version differs", [](auto& id) { id.catalogue_version = "iso-2025.1"; }},
      {"campaign_file differs (first at line 2)", [](auto& id) { id.campaign_file.replace(21, 3, "200"); }},
      {"base_scene differs", [](auto& id) { id.base_scene += "\n"; }},
      {"design differs ('sobol' in the file, 'lhs' now)", [](auto& id) { id.design = "lhs"; }},
      {"solver differs", [](auto& id) { id.solver = "dynamic"; }},
      {"seed differs (11400714819323198485 in the file, 1 now)", [](auto& id) { id.seed = 1; }},
      {"inputs differ (the file has 4 inputs, this campaign 3)", [](auto& id) { id.inputs.pop_back(); }},
      {"inputs differ (input 1: 'ring.order3.amplitude_um' in the file, 'ring.order3.phase_rad' now)",
       [](auto& id) { id.inputs[1].name = "ring.order3.phase_rad"; }},
      {"inputs differ (input 3", [](auto& id) { id.inputs[3].roller = 2; }},
      {"spec differs (upper_spec_limit of runout_mm: 0.012 in the file, 0.02 now)",
       [](auto& id) { id.spec[0].upper = 0.02; }},
      {"outputs.life differs ('true' in the file, 'false' now)", [](auto& id) { id.life = false; }},
      {"solver.accuracy differs ('full' in the file, 'fast' now)",
       [](auto& id) { id.accuracy = solvers::Accuracy::kFast; }},
      {"population differs (first at line 1)", [](auto& id) { id.population = "ring_01.csv 1a2b3c4d"; }},
      {"spec differs (upper_spec_limit of swing_mm: not set in the file, 0.03 now)",
       [](auto& id) {
         id.spec.push_back({"swing_mm", 0.03});
       }},
  };
  for (const Change& change : changes) {
    CampaignIdentity identity = TestIdentity();
    change.apply(identity);
    EXPECT_THAT(
        InputErrorOf([&] { CampaignStore::Resume(path, identity, 8); }),
        AllOf(HasSubstr(path.string()), HasSubstr("was written by another campaign"), HasSubstr(change.expected)));
  }
  EXPECT_EQ(ReadBytes(path), before);
}

// Rewrites the string attribute `name` of the file's root, or removes it (nullopt).
void SetRootText(const fs::path& path, const char* name, std::optional<std::string> text) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  H5Adelete(file, name);
  if (text) {
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, H5T_VARIABLE);
    const hid_t space = H5Screate(H5S_SCALAR);
    const hid_t attribute = H5Acreate2(file, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
    const char* value = text->c_str();
    H5Awrite(attribute, type, &value);
    H5Aclose(attribute);
    H5Sclose(space);
    H5Tclose(type);
  }
  H5Fclose(file);
}

// life, accuracy and population are younger than the file format: a file without them is
// one of a campaign that computed the life at full accuracy from tolerance classes, and a
// word that names no value is refused with the words that do.
TEST(CampaignReader, ReadsTheYoungerIdentityAttributesAsTheirDefaultsAndRefusesAnUnknownWord) {
  const fs::path path = TestFolder() / "results.h5";
  CampaignIdentity written = TestIdentity();
  written.life = false;
  written.accuracy = solvers::Accuracy::kFast;
  written.population = "ring_01.csv 1a2b3c4d";
  CampaignStore::Create(path, written, 2);
  {
    const CampaignReader reader(path);
    EXPECT_FALSE(reader.identity().life);
    EXPECT_EQ(reader.identity().accuracy, solvers::Accuracy::kFast);
    EXPECT_EQ(reader.identity().population, written.population);
  }
  const fs::path older = TestFolder() / "older.h5";
  CampaignStore::Create(older, TestIdentity(), 2);
  for (const char* name : {"life", "accuracy", "population"}) SetRootText(older, name, std::nullopt);
  {
    const CampaignReader reader(older);
    EXPECT_TRUE(reader.identity().life);
    EXPECT_EQ(reader.identity().accuracy, solvers::Accuracy::kFull);
    EXPECT_EQ(reader.identity().population, "");
  }
  SetRootText(older, "life", "maybe");
  EXPECT_THAT(InputErrorOf([&] { CampaignReader reader(older); }),
              AllOf(HasSubstr(older.string()), HasSubstr("attribute life = \"maybe\" is not one of \"computed\", "
                                                        "\"not computed\"")));
  SetRootText(older, "life", "computed");
  SetRootText(older, "accuracy", "rough");
  EXPECT_THAT(InputErrorOf([&] { CampaignReader reader(older); }),
              AllOf(HasSubstr("attribute accuracy = \"rough\" is not one of"), HasSubstr("\"fast\"")));
}

// A plain HDF5 file, as another program would write it.
void WriteForeignHdf5(const fs::path& path) {
  const hid_t file = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  const hsize_t dims[1] = {3};
  const hid_t space = H5Screate_simple(1, dims, nullptr);
  const hid_t dataset = H5Dcreate2(file, "temperature", H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  const double values[3] = {20.5, 21.0, 21.5};
  H5Dwrite(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values);
  H5Dclose(dataset);
  H5Sclose(space);
  H5Fclose(file);
}

TEST(CampaignStore, ResumeAndReaderRefuseFilesThatAreNoCampaignLeavingThemUntouched) {
  const fs::path folder = TestFolder();
  const fs::path valid = folder / "valid.h5";
  {
    CampaignStore store = CampaignStore::Create(valid, TestIdentity(), 500);
    for (std::int64_t index = 0; index < 500; ++index) store.Add(DeterministicRecord(index));
  }
  const fs::path truncated = folder / "truncated.h5";
  fs::copy_file(valid, truncated);
  fs::resize_file(truncated, fs::file_size(valid) / 2);
  const fs::path text = folder / "notes.txt";
  std::ofstream(text) << "not a results file\n";
  const fs::path foreign = folder / "foreign.h5";
  WriteForeignHdf5(foreign);
  const fs::path missing = folder / "missing.h5";

  struct Case {
    fs::path path;
    const char* expected;
  };
  for (const Case& c :
       {Case{missing, "does not exist"}, Case{truncated, "is not an HDF5 file or is truncated"},
        Case{text, "is not an HDF5 file or is truncated"}, Case{foreign, "is not a ringtol campaign file"}}) {
    SCOPED_TRACE(c.path.string());
    const std::string before = fs::exists(c.path) ? ReadBytes(c.path) : "";
    EXPECT_THAT(InputErrorOf([&] { CampaignStore::Resume(c.path, TestIdentity(), 500); }),
                AllOf(HasSubstr(c.path.string()), HasSubstr(c.expected)));
    EXPECT_THAT(InputErrorOf([&] { CampaignReader reader(c.path); }),
                AllOf(HasSubstr(c.path.string()), HasSubstr(c.expected)));
    if (c.path == missing) {
      EXPECT_FALSE(fs::exists(missing));
    } else {
      EXPECT_EQ(ReadBytes(c.path), before);
    }
  }
}

TEST(CampaignStore, ResumeRefusesAFileThatAnotherStoreIsWriting) {
  const fs::path path = TestFolder() / "results.h5";
  CampaignStore writing = CampaignStore::Create(path, TestIdentity(), 4);
  writing.Add(DeterministicRecord(0));
  EXPECT_THAT(InputErrorOf([&] { CampaignStore::Resume(path, TestIdentity(), 4); }),
              AllOf(HasSubstr(path.string()), HasSubstr("is being written by another ringtol run")));
  writing.Commit();
  EXPECT_EQ(Indices(writing.Pending(0, 4)), (std::vector<std::int64_t>{1, 2, 3}));
}

TEST(CampaignReader, RefusesAFileOfANewerSchema) {
  const fs::path path = TestFolder() / "results.h5";
  CampaignStore::Create(path, TestIdentity(), 2);
  {
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    const hid_t attribute = H5Aopen(file, "schema_version", H5P_DEFAULT);
    const int newer = kShardIndexSchemaVersion + 1;
    H5Awrite(attribute, H5T_NATIVE_INT, &newer);
    H5Aclose(attribute);
    H5Fclose(file);
  }
  const std::string expected = "written by a newer ringtol (schema " + std::to_string(kShardIndexSchemaVersion + 1) + ")";
  EXPECT_THAT(InputErrorOf([&] { CampaignReader reader(path); }), HasSubstr(expected));
  EXPECT_THAT(InputErrorOf([&] { CampaignStore::Resume(path, TestIdentity(), 2); }), HasSubstr(expected));
}

// A file of an older `schema` made from a current one of `samples` deterministic records
// (testing::AsOlderSchema).
fs::path OlderFile(std::int64_t samples, int schema, const std::function<void(hid_t)>& edit) {
  const fs::path path = TestFolder() / "results.h5";
  {
    CampaignStore store = CampaignStore::Create(path, TestIdentity(), samples);
    for (std::int64_t i = 0; i < samples; ++i) store.Add(DeterministicRecord(i));
  }
  testing::AsOlderSchema(path, schema, edit);
  return path;
}



// Keeping the inputs of the first samples only, the reader replays the others from (campaign,
// index) to the bits the run drew, and refuses a replay whose draw checksum differs.
TEST(CampaignReader, ReplaysTheInputsAFileDoesNotKeepAndRefusesADrawThatChanged) {
  constexpr std::int64_t kKept = 5;
  const fs::path folder = TestFolder();
  testing::WriteText(folder / "campaign.toml",
                     ringtol::testing::SmallCampaign((fs::path(RINGTOL_SOURCE_DIR) / "examples/paper/scene.toml").string(), 11,
                                            16));
  const Campaign campaign(folder / "campaign.toml", std::nullopt, std::nullopt);
  const fs::path path = folder / "results.h5";
  std::vector<SampleRecord> evaluated;
  {
    CampaignStoreOptions options;
    options.inputs_stored_below = kKept;
    CampaignStore store = CampaignStore::Create(path, campaign.identity(), campaign.samples(), options);
    SampleEvaluator evaluator(campaign);
    for (std::int64_t i = 0; i < campaign.samples(); ++i) {
      evaluated.push_back(evaluator.Evaluate(i));
      store.Add(evaluated.back());
    }
  }
  {
    // The file keeps u and values of the first kKept samples and nothing of the others.
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const hid_t u = H5Dopen2(file, "/inputs/u", H5P_DEFAULT);
    const hid_t space = H5Dget_space(u);
    hsize_t dims[2] = {0, 0};
    H5Sget_simple_extent_dims(space, dims, nullptr);
    EXPECT_EQ(dims[0], static_cast<hsize_t>(kKept));
    H5Sclose(space);
    H5Dclose(u);
    H5Fclose(file);
  }
  {
    const CampaignReader reader(path);
    const std::size_t d = campaign.identity().inputs.size();
    const std::vector<double> values = reader.ReadValues(0, campaign.samples());
    for (std::int64_t i = 0; i < campaign.samples(); ++i) {
      SCOPED_TRACE("sample " + std::to_string(i));
      ExpectStored(reader.ReadSample(i), evaluated[static_cast<std::size_t>(i)]);
      for (std::size_t j = 0; j < d; ++j) {
        EXPECT_EQ(values[static_cast<std::size_t>(i) * d + j],
                  static_cast<double>(static_cast<float>(evaluated[static_cast<std::size_t>(i)].values[j])));
      }
    }
  }
  EXPECT_TRUE(CheckResults(path).intact());

  // Another sampler would draw sample 9 differently: its checksum no longer matches.
  {
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    const hid_t checksums = H5Dopen2(file, "/inputs/draw_checksum", H5P_DEFAULT);
    const hid_t space = H5Dget_space(checksums);
    const hsize_t at[1] = {9};
    const hsize_t one[1] = {1};
    H5Sselect_hyperslab(space, H5S_SELECT_SET, at, nullptr, one, nullptr);
    const hid_t memory = H5Screate_simple(1, one, nullptr);
    const std::uint32_t other = DrawChecksum(evaluated[9]) ^ 1u;
    EXPECT_GE(H5Dwrite(checksums, H5T_NATIVE_UINT32, memory, space, H5P_DEFAULT, &other), 0);
    H5Sclose(memory);
    H5Sclose(space);
    H5Dclose(checksums);
    H5Fclose(file);
  }
  const CampaignReader changed(path);
  EXPECT_NO_THROW(changed.ReadSample(4));  // kept: nothing to replay
  EXPECT_THAT(InputErrorOf([&] { changed.ReadSample(9); }),
              AllOf(HasSubstr(path.string()), HasSubstr("sample 9"), HasSubstr("draws them differently")));
}

// What a finished sample costs on disk once its inputs are not kept (the target for
// a pool of 1,000 ranks): the bytes two files of different sizes differ by, per sample, so
// that the file's fixed metadata cancels. 14 float64 outputs, the error bound and the
// solve time are 128 bytes; steps, redraws, the checksum, rung and status add 14.
TEST(CampaignStore, ASlimRowTakesAtMost150BytesBeyondTheStoredInputs) {
  constexpr double kMostBytesPerRow = 150.0;
  const auto size = [](std::int64_t samples) {
    const fs::path path = TestFolder() / ("slim" + std::to_string(samples) + ".h5");
    {
      CampaignStoreOptions options;
      options.inputs_stored_below = 0;
      CampaignStore store = CampaignStore::Create(path, TestIdentity(), samples, options);
      for (std::int64_t i = 0; i < samples; ++i) {
        SampleRecord record = DeterministicRecord(i);
        record.status = SampleStatus::kOk;
        record.message.clear();
        record.off_bore.assign(TestIdentity().rollers.size(), 0.0);
        for (std::size_t k = 0; k < kOutputCount; ++k) record.outputs[k] = 1e-3 * static_cast<double>(i) + static_cast<double>(k);
        store.Add(std::move(record));
        if (i % 1000 == 999) store.Commit();
      }
    }
    return static_cast<double>(fs::file_size(path));
  };
  constexpr std::int64_t kSmall = 4096;
  constexpr std::int64_t kLarge = 3 * kSmall;
  const double per_row = (size(kLarge) - size(kSmall)) / static_cast<double>(kLarge - kSmall);
  RecordProperty("bytes_per_row", std::to_string(per_row));
  EXPECT_LE(per_row, kMostBytesPerRow);
  EXPECT_GE(per_row, 128.0);  // the float64 columns alone: nothing was left out
}

// What a file of schema 5 or before holds for a record: no off-bore shares.
SampleRecord WithoutOffBore(SampleRecord record) {
  record.off_bore.clear();
  return record;
}

// A schema-4 file (a message per sample, every sample's inputs, no draw checksums) and a
// schema-5 file (no off-bore shares, no roller names) are resumed in their own schema:
// each grows, and what the resume adds reads back as that schema keeps it.
TEST(CampaignStore, ResumesASchemaFourOrFiveFileInItsOwnSchema) {
  constexpr std::int64_t kSamples = 20;
  constexpr std::int64_t kGrown = 40;
  for (const int schema : {4, 5}) {
    SCOPED_TRACE("schema " + std::to_string(schema));
    const fs::path path = OlderFile(kSamples, schema, {});
    {
      CampaignStore store = CampaignStore::Resume(path, TestIdentity(), kGrown);
      EXPECT_EQ(store.schema(), schema);
      for (const std::int64_t index : Indices(store.Pending(0, kGrown))) store.Add(DeterministicRecord(index));
    }
    const CampaignReader reader(path);
    EXPECT_EQ(reader.schema_version(), schema);
    EXPECT_EQ(reader.samples(), kGrown);
    EXPECT_FALSE(reader.HasOffBore());
    EXPECT_TRUE(reader.identity().rollers.empty());
    EXPECT_TRUE(reader.ReadOffBore(0, kGrown).empty());
    for (std::int64_t index = 0; index < kGrown; ++index) {
      ExpectStored(reader.ReadSample(index), WithoutOffBore(DeterministicRecord(index)));
    }
    EXPECT_TRUE(CheckResults(path).intact());
  }
}

// Each roller's share of the turn off the bore reads back per sample, rounded to float32,
// NaN for the samples that failed, with the rollers' names in their order.
TEST(CampaignReader, ReadsEachRollersShareOfTheTurnOffTheBore) {
  constexpr std::int64_t kSamples = 24;
  const fs::path path = TestFolder() / "results.h5";
  {
    CampaignStore store = CampaignStore::Create(path, TestIdentity(), kSamples);
    for (std::int64_t i = 0; i < kSamples; ++i) store.Add(DeterministicRecord(i));
  }
  const CampaignReader reader(path);
  ASSERT_TRUE(reader.HasOffBore());
  EXPECT_EQ(reader.identity().rollers, TestIdentity().rollers);
  const std::vector<float> shares = reader.ReadOffBore(0, kSamples);
  const std::size_t z = TestIdentity().rollers.size();
  ASSERT_EQ(shares.size(), static_cast<std::size_t>(kSamples) * z);
  for (std::int64_t i = 0; i < kSamples; ++i) {
    const SampleRecord written = AsStored(DeterministicRecord(i));
    for (std::size_t r = 0; r < z; ++r) {
      const float share = shares[static_cast<std::size_t>(i) * z + r];
      if (written.status == SampleStatus::kOk) {
        EXPECT_EQ(share, static_cast<float>(written.off_bore[r])) << "sample " << i << ", roller " << r;
      } else {
        EXPECT_TRUE(std::isnan(share)) << "sample " << i << ", roller " << r;
      }
    }
  }
}

// An ok sample must say, for every roller, whether it left the bore: a record without
// (a caller that forgot) is refused, not stored as NaN that would later read as damage.
TEST(CampaignStore, RefusesAnOkSampleWithoutAShareForEveryRoller) {
  CampaignStore store = CampaignStore::Create(TestFolder() / "results.h5", TestIdentity(), 4);
  SampleRecord record = DeterministicRecord(0);
  ASSERT_EQ(record.status, SampleStatus::kOk);
  record.off_bore.pop_back();
  EXPECT_THROW(store.Add(record), std::invalid_argument);
}

// A schema-1 file as ringtol 0.3 wrote it, made from a current one: its max - min sat in
// runout_total_mm, its runout_mm held the ill-posed peak to nearest valley, and it had no
// swing and no per-revolution diameters.
TEST(CampaignReader, ReadsASchemaOneFileWithItsColumnsForWhatTheyAre) {
  constexpr std::int64_t kSamples = 8;
  const fs::path path = OlderFile(kSamples, 1, [](hid_t file) {
    ASSERT_GE(H5Lmove(file, "/outputs/runout_mm", file, "/outputs/runout_total_mm", H5P_DEFAULT, H5P_DEFAULT), 0);
    ASSERT_GE(H5Lmove(file, "/outputs/swing_mm", file, "/outputs/runout_mm", H5P_DEFAULT, H5P_DEFAULT), 0);
    ASSERT_GE(H5Ldelete(file, "/outputs/d_trajectory_first_mm", H5P_DEFAULT), 0);
    ASSERT_GE(H5Ldelete(file, "/outputs/d_trajectory_steady_mm", H5P_DEFAULT), 0);
  });
  const auto column = [](const char* name) {
    return static_cast<std::size_t>(std::find(kOutputNames.begin(), kOutputNames.end(), std::string_view(name)) -
                                    kOutputNames.begin());
  };
  const CampaignReader reader(path);
  EXPECT_EQ(reader.schema_version(), 1);
  EXPECT_TRUE(reader.HasOutput("runout_mm"));
  EXPECT_FALSE(reader.HasOutput("swing_mm"));
  EXPECT_FALSE(reader.HasOutput("d_trajectory_first_mm"));
  const std::vector<double> runout = reader.ReadOutput("runout_mm", 0, kSamples);
  const std::vector<double> swing = reader.ReadOutput("swing_mm", 0, kSamples);
  for (std::int64_t i = 0; i < kSamples; ++i) {
    const SampleRecord written = DeterministicRecord(i);
    const auto row = static_cast<std::size_t>(i);
    // runout_mm comes from the old runout_total_mm, which holds what was written as runout.
    EXPECT_TRUE(std::isnan(runout[row]) ? std::isnan(written.outputs[column("runout_mm")])
                                        : runout[row] == written.outputs[column("runout_mm")])
        << "sample " << i;
    EXPECT_TRUE(std::isnan(swing[row])) << "sample " << i;
    const SampleRecord read = reader.ReadSample(i);
    EXPECT_TRUE(std::isnan(read.outputs[column("d_trajectory_steady_mm")])) << "sample " << i;
  }
  EXPECT_TRUE(CheckResults(path).intact());
  EXPECT_THAT(InputErrorOf([&] { CampaignStore::Resume(path, TestIdentity(), kSamples); }),
              HasSubstr("written by an older ringtol (schema 1); it can be reported but not resumed"));
}

// A schema-2 file (ringtol 0.4) had no rung and no error bound: they read as kNoRung and NaN.
TEST(CampaignReader, ReadsASchemaTwoFileWithoutRungsAsNoRungRan) {
  constexpr std::int64_t kSamples = 6;
  const fs::path path = OlderFile(kSamples, 2, [](hid_t file) {
    ASSERT_GE(H5Ldelete(file, "/outputs/rung", H5P_DEFAULT), 0);
    ASSERT_GE(H5Ldelete(file, "/outputs/d_trajectory_error_mm", H5P_DEFAULT), 0);
  });
  const CampaignReader reader(path);
  EXPECT_EQ(reader.schema_version(), 2);
  const std::vector<std::int8_t> rungs = reader.ReadRungs(0, kSamples);
  EXPECT_TRUE(std::all_of(rungs.begin(), rungs.end(), [](std::int8_t rung) { return rung == kNoRung; }));
  for (std::int64_t i = 0; i < kSamples; ++i) {
    const SampleRecord read = reader.ReadSample(i);
    EXPECT_EQ(read.rung, kNoRung) << "sample " << i;
    EXPECT_TRUE(std::isnan(read.d_trajectory_error)) << "sample " << i;
    EXPECT_EQ(Bits(read.outputs), Bits(WithoutLife(AsStored(DeterministicRecord(i))).outputs)) << "sample " << i;
  }
  EXPECT_TRUE(CheckResults(path).intact());
}

// A schema-3 file had no life outputs: they read as NaN, HasOutput says they are absent,
// and the file verifies but is not resumed.
TEST(CampaignReader, ReadsASchemaThreeFileWithoutLifeOutputsAsNaN) {
  constexpr std::int64_t kSamples = 6;
  const fs::path path = OlderFile(kSamples, 3, [](hid_t) {});
  const CampaignReader reader(path);
  EXPECT_EQ(reader.schema_version(), 3);
  EXPECT_TRUE(reader.HasOutput("d_trajectory_steady_mm"));
  for (std::size_t k = 0; k < kOutputCount; ++k) EXPECT_EQ(reader.HasOutput(kOutputNames[k]), !IsLifeOutput(k)) << k;
  for (std::int64_t i = 0; i < kSamples; ++i) {
    const SampleRecord read = reader.ReadSample(i);
    EXPECT_EQ(Bits(read.outputs), Bits(WithoutLife(AsStored(DeterministicRecord(i))).outputs)) << "sample " << i;
  }
  EXPECT_TRUE(std::isnan(reader.ReadOutput("life_d_trajectory_mm", 0, kSamples)[2]));
  EXPECT_TRUE(CheckResults(path).intact());
  EXPECT_THAT(InputErrorOf([&] { CampaignStore::Resume(path, TestIdentity(), kSamples); }),
              HasSubstr("schema 3"));
}

// A schema-3 file kept the rung as plain int8: it reads as it is.
TEST(CampaignReader, ReadsASchemaThreeRungColumnOfPlainIntegers) {
  constexpr std::int64_t kSamples = 5;
  const fs::path path = OlderFile(kSamples, 3, [](hid_t file) {
    std::vector<std::int8_t> rungs(kSamples);
    const hid_t old_rungs = H5Dopen2(file, "/outputs/rung", H5P_DEFAULT);
    const hid_t memory = H5Dget_type(old_rungs);
    ASSERT_GE(H5Dread(old_rungs, memory, H5S_ALL, H5S_ALL, H5P_DEFAULT, rungs.data()), 0);
    H5Tclose(memory);
    H5Dclose(old_rungs);
    ASSERT_GE(H5Ldelete(file, "/outputs/rung", H5P_DEFAULT), 0);
    const hsize_t size = kSamples;
    const hid_t space = H5Screate_simple(1, &size, nullptr);
    const hid_t plain = H5Dcreate2(file, "/outputs/rung", H5T_STD_I8LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    ASSERT_GE(H5Dwrite(plain, H5T_NATIVE_INT8, H5S_ALL, H5S_ALL, H5P_DEFAULT, rungs.data()), 0);
    H5Dclose(plain);
    H5Sclose(space);
  });
  const CampaignReader reader(path);
  const std::vector<std::int8_t> rungs = reader.ReadRungs(0, kSamples);
  for (std::int64_t i = 0; i < kSamples; ++i) {
    EXPECT_EQ(rungs[static_cast<std::size_t>(i)], DeterministicRecord(i).rung) << i;
    EXPECT_EQ(reader.ReadSample(i).rung, DeterministicRecord(i).rung) << i;
  }
}

// ---------------------------------------------------------------------------------------
// Damage: copies of a finished file with bytes flipped inside one chosen chunk, found
// through HDF5's own chunk index, so that the damage lands where the test says.

constexpr std::int64_t kDamageSamples = 64;
constexpr std::int64_t kDamageChunk = 16;  // samples per chunk: four chunks
constexpr std::int64_t kDamagedSample = 20;  // in the second chunk, samples 16 to 31
constexpr std::size_t kFlippedBytes = 8;

fs::path WriteFinished(const fs::path& path, bool checksums = true) {
  CampaignStoreOptions options;
  options.chunk_samples = kDamageChunk;
  options.checksums = checksums;
  CampaignStore store = CampaignStore::Create(path, TestIdentity(), kDamageSamples, options);
  for (std::int64_t index = 0; index < kDamageSamples; ++index) store.Add(DeterministicRecord(index));
  return path;
}

struct ChunkPlace {
  haddr_t address = 0;
  hsize_t bytes = 0;
};

// Where the chunk of `dataset` that holds `sample` lies in the file.
ChunkPlace ChunkOf(const fs::path& path, const std::string& dataset, std::int64_t sample) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t data = H5Dopen2(file, dataset.c_str(), H5P_DEFAULT);
  const hid_t dcpl = H5Dget_create_plist(data);
  hsize_t chunk[2] = {0, 0};
  H5Pget_chunk(dcpl, 2, chunk);
  const hsize_t offset[2] = {static_cast<hsize_t>(sample) / chunk[0] * chunk[0], 0};
  ChunkPlace place;
  unsigned mask = 0;
  EXPECT_GE(H5Dget_chunk_info_by_coord(data, offset, &mask, &place.address, &place.bytes), 0) << dataset;
  H5Pclose(dcpl);
  H5Dclose(data);
  H5Fclose(file);
  return place;
}

// A copy of `intact` with 8 bytes flipped in the middle of the chunk of `dataset` holding kDamagedSample.
fs::path DamagedCopy(const fs::path& intact, const std::string& dataset) {
  fs::path copy = intact;
  copy.replace_filename("damaged" + std::to_string(std::hash<std::string>{}(dataset) % 100000) + ".h5");
  fs::copy_file(intact, copy, fs::copy_options::overwrite_existing);
  const ChunkPlace chunk = ChunkOf(copy, dataset, kDamagedSample);
  FlipBytes(copy, chunk.address + chunk.bytes / 2 - kFlippedBytes / 2, kFlippedBytes);
  return copy;
}

const DatasetCheck& Dataset(const ResultsCheck& check, const std::string& path) {
  const auto found = std::find_if(check.datasets.begin(), check.datasets.end(),
                                  [&](const DatasetCheck& dataset) { return dataset.path == path; });
  if (found == check.datasets.end()) throw std::out_of_range("no dataset " + path);
  return *found;
}

const std::vector<std::string> kDamagedDatasets = {"/inputs/u",           "/inputs/values",
                                                   "/inputs/draw_checksum", "/outputs/d_trajectory_mm",
                                                   "/outputs/status",     "/timing/solve_time_s"};

TEST(CampaignStore, EveryDatasetEndsItsFiltersWithTheFletcher32Checksum) {
  const fs::path path = WriteFinished(TestFolder() / "results.h5");
  const ResultsCheck check = CheckResults(path);
  // Descriptions (the rollers' names among them), the failure rows, per-sample columns (rung,
  // error bound and off-bore shares among them), outputs.
  EXPECT_EQ(check.datasets.size(), 7 + 2 + 10 + kOutputCount);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  for (const DatasetCheck& dataset : check.datasets) {
    SCOPED_TRACE(dataset.path);
    EXPECT_TRUE(dataset.checksummed);
    const hid_t data = H5Dopen2(file, dataset.path.c_str(), H5P_DEFAULT);
    const hid_t dcpl = H5Dget_create_plist(data);
    const int filters = H5Pget_nfilters(dcpl);
    ASSERT_GE(filters, 1);
    unsigned flags = 0;
    std::size_t values = 0;
    EXPECT_EQ(H5Pget_filter2(dcpl, static_cast<unsigned>(filters - 1), &flags, &values, nullptr, 0, nullptr, nullptr),
              H5Z_FILTER_FLETCHER32);
    H5Pclose(dcpl);
    H5Dclose(data);
  }
  H5Fclose(file);
}

TEST(CheckResults, FindsAFreshFileIntactWithWhatIsDoneAndPending) {
  const fs::path path = TestFolder() / "results.h5";
  {
    CampaignStoreOptions options;
    options.chunk_samples = kDamageChunk;
    CampaignStore store = CampaignStore::Create(path, TestIdentity(), kDamageSamples, options);
    for (std::int64_t index = 0; index < kDamageSamples; ++index) {
      if (index < 10 || index >= 40) store.Add(DeterministicRecord(index));
    }
  }
  const ResultsCheck check = CheckResults(path);
  EXPECT_TRUE(check.intact());
  EXPECT_TRUE(check.checksummed());
  EXPECT_EQ(check.samples, kDamageSamples);
  EXPECT_EQ(check.done, 10 + (kDamageSamples - 40));
  EXPECT_EQ(check.pending, (std::vector<SampleRange>{{10, 40}}));
  EXPECT_EQ(check.recompute, check.pending);
}

TEST(CheckResults, NamesTheOneDamagedDatasetAndTheSamplesOfItsChunk) {
  const fs::path intact = WriteFinished(TestFolder() / "results.h5");
  for (const std::string& damaged : kDamagedDatasets) {
    SCOPED_TRACE(damaged);
    const ResultsCheck check = CheckResults(DamagedCopy(intact, damaged));
    EXPECT_FALSE(check.intact());
    for (const DatasetCheck& dataset : check.datasets) {
      if (dataset.path == damaged) {
        EXPECT_EQ(dataset.damaged, (std::vector<SampleRange>{{16, 32}}));
        EXPECT_THAT(dataset.first_problem, HasSubstr("Fletcher32"));
      } else {
        EXPECT_TRUE(dataset.damaged.empty()) << dataset.path;
      }
    }
    EXPECT_EQ(check.recompute, (std::vector<SampleRange>{{16, 32}}));
    // A damaged status chunk loses whether its samples were done.
    EXPECT_EQ(check.done, damaged == "/outputs/status" ? kDamageSamples - kDamageChunk : kDamageSamples);
  }
}

// The failure rows hold the failed samples' messages: a damaged chunk of them loses those
// messages, which verify names by sample and a resume computes again with their samples.
TEST(CampaignStore, AResumeComputesAgainTheFailedSamplesWhoseMessagesADamagedChunkHeld) {
  const fs::path intact = WriteFinished(TestFolder() / "results.h5");
  std::vector<SampleRange> failed;  // one chunk of 64 rows holds every failure row
  for (std::int64_t index = 0; index < kDamageSamples; ++index) {
    if (DeterministicRecord(index).status == SampleStatus::kOk) continue;
    if (!failed.empty() && failed.back().end == index) {
      ++failed.back().end;
    } else {
      failed.push_back({index, index + 1});
    }
  }
  ASSERT_FALSE(failed.empty());
  for (const char* damaged : {"/failures/message", "/failures/sample"}) {
    SCOPED_TRACE(damaged);
    // Bytes of written rows: the chunk's unwritten rest is zeros, and Fletcher-32 cannot
    // tell 0x0000 from 0xffff (sums modulo 65535), so flipping zeros would go unseen.
    fs::path path = intact;
    path.replace_filename(std::string("damaged_") + (damaged + 10) + ".h5");
    fs::copy_file(intact, path, fs::copy_options::overwrite_existing);
    constexpr std::uint64_t kIntoTheFirstRows = 16;
    FlipBytes(path, ChunkOf(path, damaged, 0).address + kIntoTheFirstRows, kFlippedBytes);
    const ResultsCheck check = CheckResults(path);
    EXPECT_FALSE(check.intact());
    EXPECT_EQ(Dataset(check, damaged).damaged, failed);
    EXPECT_EQ(check.recompute, failed);
    EXPECT_THAT(InputErrorOf([&] { CampaignReader(path).ReadSample(failed.front().begin); }),
                AllOf(HasSubstr(path.string()), HasSubstr("damaged")));
    {
      CampaignStore store = CampaignStore::Resume(path, TestIdentity(), kDamageSamples);
      const std::vector<std::int64_t> pending = Indices(store.Pending(0, kDamageSamples));
      std::vector<std::int64_t> expected;
      for (const SampleRange& range : failed) {
        for (std::int64_t index = range.begin; index < range.end; ++index) expected.push_back(index);
      }
      ASSERT_EQ(pending, expected);
      for (const std::int64_t index : pending) store.Add(DeterministicRecord(index));
    }
    EXPECT_TRUE(CheckResults(path).intact());
    const CampaignReader reader(path);
    for (std::int64_t index = 0; index < kDamageSamples; ++index) {
      ExpectStored(reader.ReadSample(index), DeterministicRecord(index));
    }
  }
}

TEST(CampaignReader, ADamagedChunkIsAnInputErrorNamingFileDatasetAndSamples) {
  const fs::path intact = WriteFinished(TestFolder() / "results.h5");
  const fs::path u = DamagedCopy(intact, "/inputs/u");
  const CampaignReader reader(u);
  EXPECT_THAT(InputErrorOf([&] { reader.ReadSample(kDamagedSample); }),
              AllOf(HasSubstr(u.string()), HasSubstr("dataset /inputs/u is damaged"), HasSubstr("sample 20 cannot be read"),
                    HasSubstr("ringtol verify")));
  EXPECT_NO_THROW(reader.ReadSample(kDamagedSample + kDamageChunk));  // the next chunk is intact
  const fs::path status = DamagedCopy(intact, "/outputs/status");
  EXPECT_THAT(InputErrorOf([&] { CampaignReader(status).ReadStatus(0, kDamageSamples); }),
              AllOf(HasSubstr(status.string()), HasSubstr("dataset /outputs/status is damaged")));
  const fs::path output = DamagedCopy(intact, "/outputs/d_trajectory_mm");
  EXPECT_THAT(InputErrorOf([&] { CampaignReader(output).ReadOutput("d_trajectory_mm", 0, kDamageSamples); }),
              AllOf(HasSubstr(output.string()), HasSubstr("dataset /outputs/d_trajectory_mm is damaged")));
  EXPECT_THAT(DamageMessage(output, CheckResults(output)),
              AllOf(HasSubstr(output.string()), HasSubstr("/outputs/d_trajectory_mm is damaged at samples 16 to 31"),
                    HasSubstr("--resume")));
}

TEST(CampaignStore, ResumeComputesTheSamplesOfADamagedChunkAgainToTheSameBits) {
  const fs::path intact = WriteFinished(TestFolder() / "results.h5");
  for (const std::string& damaged : kDamagedDatasets) {
    SCOPED_TRACE(damaged);
    const fs::path path = DamagedCopy(intact, damaged);
    {
      CampaignStoreOptions options;
      CampaignStore store = CampaignStore::Resume(path, TestIdentity(), kDamageSamples, options);
      const std::vector<std::int64_t> pending = Indices(store.Pending(0, kDamageSamples));
      ASSERT_EQ(pending.size(), static_cast<std::size_t>(kDamageChunk));
      EXPECT_EQ(pending.front(), 16);
      for (const std::int64_t index : pending) store.Add(DeterministicRecord(index));
    }
    const ResultsCheck check = CheckResults(path);
    EXPECT_TRUE(check.intact());
    EXPECT_TRUE(check.checksummed());  // the rewritten chunk's filters ran again at its commit
    EXPECT_EQ(check.done, kDamageSamples);
    const CampaignReader reader(path);
    for (std::int64_t index = 0; index < kDamageSamples; ++index) {
      ExpectStored(reader.ReadSample(index), DeterministicRecord(index));
    }
  }
}

TEST(CheckResults, AFileWithoutChecksumsReadsButIsNotCalledChecked) {
  const fs::path path = WriteFinished(TestFolder() / "results.h5", false);
  const ResultsCheck check = CheckResults(path);
  EXPECT_TRUE(check.intact());
  EXPECT_FALSE(check.checksummed());
  for (const DatasetCheck& dataset : check.datasets) EXPECT_FALSE(dataset.checksummed) << dataset.path;
  const CampaignReader reader(path);
  ExpectStored(reader.ReadSample(kDamagedSample), DeterministicRecord(kDamagedSample));
}

// Without checksums a damaged number reads; when it reads as NaN or infinity where a
// finished sample cannot hold one, it is still found, and named as damage.
TEST(CheckResults, WithoutChecksumsANonFiniteNumberOfAFinishedSampleIsDamage) {
  const fs::path folder = TestFolder();
  const fs::path intact = WriteFinished(folder / "results.h5", false);
  const fs::path path = folder / "nan.h5";
  fs::copy_file(intact, path);
  // Sample 20's first drawn value (float32, row-major [N, d]) becomes all ones: a NaN.
  const ChunkPlace chunk = ChunkOf(path, "/inputs/values", kDamagedSample);
  const std::uint64_t at = chunk.address + (kDamagedSample % kDamageChunk) * kInputs * sizeof(float);
  testing::OverwriteBytes(path, at, "\xff\xff\xff\xff");
  const ResultsCheck check = CheckResults(path);
  EXPECT_EQ(Dataset(check, "/inputs/values").damaged, (std::vector<SampleRange>{{16, 32}}));
  EXPECT_THAT(Dataset(check, "/inputs/values").first_problem, HasSubstr("sample 20 is exception but holds a non-finite"));
  EXPECT_THAT(InputErrorOf([&] { CampaignReader(path).ReadValues(0, kDamageSamples); }),
              AllOf(HasSubstr(path.string()), HasSubstr("dataset /inputs/values is damaged"),
                    HasSubstr("sample 20 is exception but holds a non-finite number at input 0")));
}

TEST(CheckResults, DamagedMetadataIsAnInputErrorNamingTheFile) {
  const fs::path folder = TestFolder();
  const fs::path intact = WriteFinished(folder / "results.h5");
  haddr_t header = 0;
  {
    const hid_t file = H5Fopen(intact.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    H5O_info_t info;
    EXPECT_GE(H5Oget_info_by_name2(file, "/inputs/u", &info, H5O_INFO_BASIC, H5P_DEFAULT), 0);
    header = info.addr;
    H5Fclose(file);
  }
  struct Case {
    std::uint64_t at;
    const char* what;
  };
  // The superblock's signature, its body (checksummed from version 2 on), and the object
  // header of /inputs/u (checksummed from version 2 on).
  for (const Case& c : {Case{0, "superblock signature"}, Case{12, "superblock"}, Case{header + 8, "object header"}}) {
    SCOPED_TRACE(c.what);
    const fs::path path = folder / ("metadata" + std::to_string(c.at) + ".h5");
    fs::copy_file(intact, path);
    FlipBytes(path, c.at, kFlippedBytes);
    EXPECT_THAT(InputErrorOf([&] { CheckResults(path); }), HasSubstr(path.string()));
    EXPECT_THAT(InputErrorOf([&] { CampaignReader reader(path); }), HasSubstr(path.string()));
    EXPECT_THAT(InputErrorOf([&] { CampaignStore::Resume(path, TestIdentity(), kDamageSamples); }),
                HasSubstr(path.string()));
  }
}

// ---------------------------------------------------------------------------------------
// Crash safety: a child process writes the deterministic campaign as fast as it can and is
// killed with SIGKILL at a different moment each round, on the file the previous round's
// kill left. Even rounds count the delay from the fork, so that early kills land while the
// store is created or resumed; odd rounds count it from the moment the store is open, so
// that the kills land in the commits however fast the build is (ASan). After every kill
// the file must open and every sample it calls done must be exact; at the end a resume
// completes it to exactly the deterministic campaign.

constexpr std::int64_t kKillSamples = 20000;
constexpr std::size_t kKillBatch = 37;
constexpr int kKillRounds = 16;
constexpr auto kFirstKill = std::chrono::milliseconds(1);
constexpr auto kLastKill = std::chrono::milliseconds(60);

// A kill in the middle of rewriting a chunk in place (the kernel stops a write between
// pages) leaves it torn: it fails its checksum, and the next resume computes its samples
// again. Every sample outside such chunks that the file calls done must be exact.
std::int64_t ExpectCommittedSamplesExact(const fs::path& path, int& torn) {
  const ResultsCheck check = CheckResults(path);
  std::vector<SampleRange> damaged;
  for (const DatasetCheck& dataset : check.datasets) {
    damaged.insert(damaged.end(), dataset.damaged.begin(), dataset.damaged.end());
  }
  torn += damaged.empty() ? 0 : 1;
  const auto in_damaged_chunk = [&](std::int64_t index) {
    return std::any_of(damaged.begin(), damaged.end(),
                       [&](const SampleRange& range) { return range.begin <= index && index < range.end; });
  };
  const CampaignReader reader(path);
  EXPECT_EQ(reader.samples(), kKillSamples);
  std::int64_t done = 0;
  for (std::int64_t index = 0; index < reader.samples(); ++index) {
    if (in_damaged_chunk(index)) continue;
    const SampleRecord record = reader.ReadSample(index);
    if (record.status == SampleStatus::kPending) continue;
    ++done;
    ExpectStored(record, DeterministicRecord(index));
    if (::testing::Test::HasFailure()) break;  // one broken sample is enough to read
  }
  return done;
}

// Forks a child that writes the campaign, kills it `delay` after the fork or after its
// store opened, and says whether the kill came before the child finished.
bool WriteAndKill(const fs::path& path, bool from_open, std::chrono::microseconds delay) {
  int ready[2];
  if (::pipe(ready) != 0) {
    ADD_FAILURE() << "pipe failed";
    return false;
  }
  std::fflush(nullptr);
  const pid_t child = ::fork();
  if (child < 0) {  // never kill(-1): that would signal every process we may signal
    ADD_FAILURE() << "fork failed";
    ::close(ready[0]);
    ::close(ready[1]);
    return false;
  }
  if (child == 0) {
    ::close(ready[0]);
    int code = 0;
    try {
      WriteDeterministic(path, kKillSamples, kKillBatch, [&] {
        const char byte = 1;
        if (::write(ready[1], &byte, 1) != 1) std::fprintf(stderr, "child: cannot signal\n");
      });
    } catch (const std::exception& error) {
      std::fprintf(stderr, "child: %s\n", error.what());
      code = 1;
    }
    ::_exit(code);  // never back into the test framework
  }
  ::close(ready[1]);
  char byte = 0;
  // Nothing to read: the child ended (or failed) before its store opened.
  if (from_open && ::read(ready[0], &byte, 1) != 1) delay = {};
  std::this_thread::sleep_for(delay);
  ::kill(child, SIGKILL);
  int status = 0;
  EXPECT_EQ(::waitpid(child, &status, 0), child);
  ::close(ready[0]);  // only now: the child's signal to a closed pipe would kill it (SIGPIPE)
  if (WIFEXITED(status)) {
    EXPECT_EQ(WEXITSTATUS(status), 0) << "the child failed (see its message above)";
  }
  return WIFSIGNALED(status);
}

TEST(CampaignStore, SurvivesSigkillAtAnyMomentAndResumesToTheSameBits) {
  const fs::path folder = TestFolder();
  const fs::path path = folder / "results.h5";
  int killed = 0;
  int torn = 0;
  std::ostringstream progress;
  for (int round = 0; round < kKillRounds; ++round) {
    const bool from_open = round % 2 == 1;
    const auto delay = std::chrono::duration_cast<std::chrono::microseconds>(
        kFirstKill + (kLastKill - kFirstKill) * (round / 2) / (kKillRounds / 2 - 1));
    SCOPED_TRACE("round " + std::to_string(round) + ": kill " + std::to_string(delay.count()) + " us after " +
                 (from_open ? "the store opened" : "the fork"));
    killed += WriteAndKill(path, from_open, delay) ? 1 : 0;
    ASSERT_FALSE(HasFailure());
    // A kill while creating leaves only the temporary, never a half-made results file.
    for (const auto& entry : fs::directory_iterator(folder)) {
      if (entry.path() != path) fs::remove(entry.path());
    }
    const std::int64_t done = fs::exists(path) ? ExpectCommittedSamplesExact(path, torn) : -1;
    ASSERT_FALSE(HasFailure());
    progress << ' ' << done;
  }
  RecordProperty("samples_done_after_each_kill", progress.str());
  std::printf("%d of %d rounds killed, %d left a torn chunk; samples done after each round (-1: no file yet):%s\n",
              killed, kKillRounds, torn, progress.str().c_str());
  EXPECT_GE(killed, kKillRounds / 2) << "the kills came too late to test anything";

  WriteDeterministic(path, kKillSamples, kKillBatch);
  const CampaignReader reader(path);
  const std::vector<SampleStatus> statuses = reader.ReadStatus(0, kKillSamples);
  EXPECT_EQ(std::count(statuses.begin(), statuses.end(), SampleStatus::kPending), 0);
  for (std::int64_t index = 0; index < kKillSamples && !HasFailure(); ++index) {
    ExpectStored(reader.ReadSample(index), DeterministicRecord(index));
  }
}

// ---------------------------------------------------------------------------------------
// Shard indexes: three shards of a 40-sample campaign in chunks of 8, as the pool leaves
// them: blocks 0 and 3 (shard 0), 1 and 4 (shard 1), 2 (shard 2) block-cyclically, the
// second half of block 3 adopted by shard 2, which also holds another record of sample 0:
// the index takes that from shard 0, listed first.

std::vector<fs::path> BlockCyclicShards(const fs::path& path) {
  const auto write = [&](int rank, std::vector<std::pair<std::int64_t, std::int64_t>> ranges) {
    CampaignStore shard = CampaignStore::Create(ShardPath(path, rank), TestIdentity(), kShardedSamples, ShardChunks());
    for (const auto& [begin, end] : ranges) WriteRange(shard, begin, end);
    return ShardPath(path, rank);
  };
  std::vector<fs::path> shards = {write(0, {{0, 8}, {24, 28}}), write(1, {{8, 16}, {32, 40}}),
                                  write(2, {{16, 24}, {28, 32}})};
  {
    CampaignStore shard = CampaignStore::Resume(shards[2], TestIdentity(), kShardedSamples);
    SampleRecord other = DeterministicRecord(1);
    other.index = 0;
    shard.Add(other);
  }
  return shards;
}

TEST(ShardIndex, ReadsEverySampleFromTheShardThatFinishedIt) {
  const fs::path path = TestFolder() / "results.h5";
  const std::vector<fs::path> shards = BlockCyclicShards(path);
  const ShardIndexSummary summary = WriteShardIndex(path, TestIdentity(), kShardedSamples, shards);
  EXPECT_EQ(summary.shards, 3);
  EXPECT_EQ(summary.samples, kShardedSamples);
  // Shard 1 is one strided run; shards 0 and 2 a run of blocks and a half block each.
  EXPECT_EQ(summary.most_mappings, 2);
  EXPECT_EQ(summary.mappings, 2 + 1 + 2);
  EXPECT_EQ(IndexedShards(path), shards);
  const CampaignReader reader(path);
  EXPECT_EQ(reader.samples(), kShardedSamples);
  EXPECT_EQ(reader.identity().seed, TestIdentity().seed);
  for (std::int64_t index = 0; index < kShardedSamples; ++index) {
    ExpectStored(reader.ReadSample(index), DeterministicRecord(index));
  }
  std::vector<double> expected;
  for (std::int64_t index = 0; index < kShardedSamples; ++index) {
    expected.push_back(AsStored(DeterministicRecord(index)).outputs[0]);
  }
  EXPECT_EQ(Bits(reader.ReadOutput(kOutputNames[0], 0, kShardedSamples)), Bits(expected));
  const ResultsCheck check = CheckResults(path);
  EXPECT_TRUE(check.intact());
  EXPECT_TRUE(check.checksummed());
  EXPECT_EQ(check.done, kShardedSamples);
  EXPECT_TRUE(check.recompute.empty());
}

TEST(ShardIndex, ShowsRowsNoShardFinishedAsPending) {
  const fs::path path = TestFolder() / "results.h5";
  {
    CampaignStore shard = CampaignStore::Create(ShardPath(path, 0), TestIdentity(), kShardedSamples, ShardChunks());
    WriteRange(shard, 0, 10);
  }
  WriteShardIndex(path, TestIdentity(), kShardedSamples, {ShardPath(path, 0)});
  const CampaignReader reader(path);
  for (std::int64_t index = 10; index < kShardedSamples; ++index) ExpectPendingRow(reader.ReadSample(index));
  const ResultsCheck check = CheckResults(path);
  EXPECT_EQ(check.done, 10);
  EXPECT_EQ(check.pending, (std::vector<SampleRange>{{10, kShardedSamples}}));
  EXPECT_EQ(check.recompute, check.pending);
}

// The root attribute `layout` says whether a file keeps its samples or indexes shards, so
// that a file of the next schema (6, the number an index carries) reads as a file.
std::optional<std::string> RootText(const fs::path& path, const char* name) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  std::optional<std::string> value;
  if (H5Aexists(file, name) > 0) {
    const hid_t attribute = H5Aopen(file, name, H5P_DEFAULT);
    const hid_t type = H5Aget_type(attribute);
    char* text = nullptr;
    if (H5Tis_variable_str(type) > 0 && H5Aread(attribute, type, &text) >= 0 && text != nullptr) {
      value = text;
      H5free_memory(text);
    }
    H5Tclose(type);
    H5Aclose(attribute);
  }
  H5Fclose(file);
  return value;
}

TEST(ShardIndex, SaysWhatItIsAndItsRowsSchemaInItsRootAttributes) {
  const fs::path path = TestFolder() / "results.h5";
  WriteShardIndex(path, TestIdentity(), kShardedSamples, BlockCyclicShards(path));
  EXPECT_EQ(RootText(path, "layout"), std::optional<std::string>("shard index"));
  EXPECT_EQ(RootText(ShardPath(path, 0), "layout"), std::optional<std::string>("file"));
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  int rows = 0;
  const hid_t attribute = H5Aopen(file, "rows_schema", H5P_DEFAULT);
  H5Aread(attribute, H5T_NATIVE_INT, &rows);
  H5Aclose(attribute);
  H5Fclose(file);
  EXPECT_EQ(rows, kCampaignSchemaVersion);
}

// A file whose schema_version is the index's number but whose layout says "file" is a
// file of schema-6 rows, not an index.
TEST(CampaignReader, ReadsAFileOfTheIndexsSchemaNumberByItsLayout) {
  const fs::path path = TestFolder() / "results.h5";
  { CampaignStore store = CampaignStore::Create(path, TestIdentity(), 2); store.Add(DeterministicRecord(0)); }
  ASSERT_EQ(kCampaignSchemaVersion, kShardIndexSchemaVersion);
  const CampaignReader reader(path);
  EXPECT_EQ(reader.schema_version(), kCampaignSchemaVersion);
  ExpectStored(reader.ReadSample(0), DeterministicRecord(0));
  EXPECT_TRUE(IndexedShards(path).empty());
}

// Indexes written before the attribute existed (their shards schema 5) are recognised by
// their schema number; such an index, and one of schema-5 shards written today, reads and
// joins in its shards' schema.
TEST(ShardIndex, AnIndexOfSchemaFiveShardsReadsAndJoinsInTheirSchemaWithOrWithoutALayout) {
  const fs::path path = TestFolder() / "results.h5";
  const std::vector<fs::path> shards = BlockCyclicShards(path);
  for (const fs::path& shard : shards) testing::AsOlderSchema(shard, 5);
  WriteShardIndex(path, TestIdentity(), kShardedSamples, shards);
  const auto expect_every_sample = [&](const fs::path& file) {
    const CampaignReader reader(file);
    EXPECT_EQ(reader.schema_version(), 5);
    EXPECT_FALSE(reader.HasOffBore());
    for (std::int64_t index = 0; index < kShardedSamples; ++index) {
      ExpectStored(reader.ReadSample(index), WithoutOffBore(DeterministicRecord(index)));
    }
    EXPECT_EQ(CheckResults(file).done, kShardedSamples);
  };
  expect_every_sample(path);
  {
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    H5Adelete(file, "layout");
    H5Adelete(file, "rows_schema");
    H5Fclose(file);
  }
  ASSERT_EQ(RootText(path, "layout"), std::nullopt);
  expect_every_sample(path);
  const fs::path joined = path.parent_path() / "joined.h5";
  JoinShards(path, joined);
  expect_every_sample(joined);
  EXPECT_EQ(RootText(joined, "layout"), std::optional<std::string>("file"));
}

// A campaign of 2^40 samples stopped early, as mpirun leaves it: its index is read and
// checked in runs, in the time of what its shards hold.
TEST(ShardIndex, AnIndexOfTwoToTheFortySamplesIsReadAndCheckedInTheTimeOfWhatItHolds) {
  const fs::path path = TestFolder() / "results.h5";
  constexpr std::int64_t kHuge = std::int64_t{1} << 40;
  {
    CampaignStore shard = CampaignStore::Create(ShardPath(path, 0), TestIdentity(), kHuge, ShardChunks());
    WriteRange(shard, 0, 10);
  }
  WriteShardIndex(path, TestIdentity(), kHuge, {ShardPath(path, 0)});
  EXPECT_EQ(CampaignReader(path).Finished(), (std::vector<SampleRange>{{0, 10}}));
  const ResultsCheck check = CheckResults(path);
  EXPECT_TRUE(check.intact());
  EXPECT_EQ(check.done, 10);
  EXPECT_EQ(check.pending, (std::vector<SampleRange>{{10, kHuge}}));
  EXPECT_EQ(check.recompute, check.pending);
}

TEST(ShardIndex, ReadersRefuseAnIndexWhoseShardIsMissingInsteadOfReadingItsRowsAsPending) {
  const fs::path path = TestFolder() / "results.h5";
  WriteShardIndex(path, TestIdentity(), kShardedSamples, BlockCyclicShards(path));
  fs::rename(ShardPath(path, 1), path.parent_path() / "moved.h5");
  const auto names_the_shard = AllOf(HasSubstr("results.h5.shard-1"), HasSubstr("missing"));
  EXPECT_THAT(InputErrorOf([&] { CampaignReader reader(path); }), names_the_shard);
  EXPECT_THAT(InputErrorOf([&] { CheckResults(path); }), names_the_shard);
  EXPECT_THAT(InputErrorOf([&] { JoinShards(path, path.parent_path() / "joined.h5"); }), names_the_shard);
}

TEST(ShardIndex, RefusesToReplaceAFileThatKeepsItsOwnSamples) {
  const fs::path path = TestFolder() / "results.h5";
  const std::vector<fs::path> shards = BlockCyclicShards(path);
  { CampaignStore::Create(path, TestIdentity(), kShardedSamples, ShardChunks()); }
  const std::string before = ReadBytes(path);
  EXPECT_THAT(InputErrorOf([&] { WriteShardIndex(path, TestIdentity(), kShardedSamples, shards); }),
              AllOf(HasSubstr("results.h5"), HasSubstr("samples of its own")));
  EXPECT_EQ(ReadBytes(path), before);
}

TEST(ShardIndex, VerifyFindsADamagedShardChunkOnlyWhereThatShardHoldsSamples) {
  const fs::path path = TestFolder() / "results.h5";
  const std::vector<fs::path> shards = BlockCyclicShards(path);
  WriteShardIndex(path, TestIdentity(), kShardedSamples, shards);
  // Shard 1's chunk of samples 8 to 15, all its own, and shard 0's of 24 to 31, of which
  // it holds 24 to 27 and shard 2 the rest.
  for (const auto& [shard, sample] : {std::pair{shards[1], 9}, std::pair{shards[0], 25}}) {
    const ChunkPlace chunk = ChunkOf(shard, "/outputs/d_trajectory_mm", sample);
    FlipBytes(shard, chunk.address + chunk.bytes / 2 - kFlippedBytes / 2, kFlippedBytes);
  }
  const ResultsCheck check = CheckResults(path);
  EXPECT_FALSE(check.intact());
  const DatasetCheck& damaged = Dataset(check, "/outputs/d_trajectory_mm");
  EXPECT_EQ(damaged.damaged, (std::vector<SampleRange>{{8, 16}, {24, 28}}));
  EXPECT_THAT(damaged.first_problem, HasSubstr("results.h5.shard-"));
  EXPECT_EQ(check.recompute, damaged.damaged);
  EXPECT_EQ(check.done, kShardedSamples);
}

// A join copies whole chunks as stored: a damaged one would be carried into the joined
// file, and the shards that --resume repairs it from removed.
TEST(ShardIndex, JoinRefusesADamagedShardChunkNamingItsRowsAndResumeAndKeepsEveryFile) {
  const fs::path path = TestFolder() / "results.h5";
  const std::vector<fs::path> shards = BlockCyclicShards(path);
  WriteShardIndex(path, TestIdentity(), kShardedSamples, shards);
  const ChunkPlace chunk = ChunkOf(shards[1], "/outputs/d_trajectory_mm", 9);
  FlipBytes(shards[1], chunk.address + chunk.bytes / 2 - kFlippedBytes / 2, kFlippedBytes);
  std::vector<std::string> before;
  for (const fs::path& file : {path, shards[0], shards[1], shards[2]}) before.push_back(ReadBytes(file));
  for (const fs::path& out : {path, path.parent_path() / "copy.h5"}) {
    EXPECT_THAT(InputErrorOf([&] { JoinShards(path, out); }),
                AllOf(HasSubstr("cannot be joined"), HasSubstr("/outputs/d_trajectory_mm"), HasSubstr("8 to 15"),
                      HasSubstr("results.h5.shard-1"),
                      HasSubstr("ringtol campaign campaigns/demo.toml --out " + path.string() + " --resume")));
    EXPECT_FALSE(fs::exists(path.parent_path() / "copy.h5"));
  }
  std::size_t k = 0;
  for (const fs::path& file : {path, shards[0], shards[1], shards[2]}) EXPECT_EQ(ReadBytes(file), before[k++]) << file;
}

// A truncated shard: every reader names it and the resume that recovers its samples, and
// that resume sets it aside under a new name (nothing is deleted) before it starts.
TEST(ShardIndex, ATruncatedShardIsNamedByEveryReaderAndSetAsideBeforeAResume) {
  const fs::path path = TestFolder() / "results.h5";
  const std::vector<fs::path> shards = BlockCyclicShards(path);
  WriteShardIndex(path, TestIdentity(), kShardedSamples, shards);
  const auto half = fs::file_size(shards[1]) / 2;
  ASSERT_EQ(std::system(("truncate -s " + std::to_string(half) + " " + shards[1].string()).c_str()), 0);
  const auto names_it = AllOf(HasSubstr("results.h5.shard-1 cannot be read"),
                              HasSubstr("ringtol campaign campaigns/demo.toml --out " + path.string() + " --resume"),
                              HasSubstr("results.h5.shard-1.unreadable"));
  EXPECT_THAT(InputErrorOf([&] { CampaignReader reader(path); }), names_it);
  EXPECT_THAT(InputErrorOf([&] { CheckResults(path); }), names_it);
  EXPECT_THAT(InputErrorOf([&] { JoinShards(path, path); }), names_it);
  EXPECT_EQ(FindShards(path).size(), 3u);

  const std::string truncated = ReadBytes(shards[1]);
  const std::vector<UnreadableShard> aside = SetAsideUnreadableShards(path);
  ASSERT_EQ(aside.size(), 1u);
  EXPECT_EQ(aside[0].shard, shards[1]);
  EXPECT_EQ(aside[0].aside, path.parent_path() / "results.h5.shard-1.unreadable");
  EXPECT_EQ(ReadBytes(aside[0].aside), truncated);
  EXPECT_EQ(FindShards(path), (std::vector<fs::path>{shards[0], shards[2]}));
  // Set aside once, it is not taken for a shard that went missing; the next name is free.
  EXPECT_TRUE(SetAsideUnreadableShards(path).empty());
  EXPECT_EQ(SetAsidePath(shards[1]), path.parent_path() / "results.h5.shard-1.unreadable-2");
  // A shard that went missing without being set aside is still refused.
  fs::rename(shards[2], path.parent_path() / "moved.h5");
  EXPECT_THAT(InputErrorOf([&] { SetAsideUnreadableShards(path); }),
              AllOf(HasSubstr("results.h5.shard-2"), HasSubstr("missing")));
}

TEST(ShardIndex, JoinWritesOneSelfContainedFileOfTheSameSamples) {
  const fs::path folder = TestFolder();
  const fs::path path = folder / "results.h5";
  const std::vector<fs::path> shards = BlockCyclicShards(path);
  WriteShardIndex(path, TestIdentity(), kShardedSamples, shards);
  const CampaignStore::Absorbed copy = JoinShards(path, folder / "copy.h5");
  EXPECT_EQ(copy.samples, kShardedSamples);
  // Blocks 0, 1, 2 and 4, and shard 0's half of block 3, whose chunk comes first.
  EXPECT_EQ(copy.chunk_samples, 36);
  EXPECT_EQ(IndexedShards(path), shards);  // the index and its shards stay
  EXPECT_TRUE(IndexedShards(folder / "copy.h5").empty());

  JoinShards(path, path);  // in place: the shards go
  EXPECT_TRUE(FindShards(path).empty());
  EXPECT_TRUE(IndexedShards(path).empty());
  for (const fs::path& joined : {path, folder / "copy.h5"}) {
    const CampaignReader reader(joined);
    for (std::int64_t index = 0; index < kShardedSamples; ++index) {
      ExpectStored(reader.ReadSample(index), DeterministicRecord(index));
    }
    EXPECT_TRUE(CheckResults(joined).intact());
  }
}

}  // namespace
}  // namespace ringtol::jobs
