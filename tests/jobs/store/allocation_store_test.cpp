#include "jobs/store/allocation_store.h"

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
#include <filesystem>
#include <functional>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "jobs/campaign/sample_record.h"
#include "jobs/inputs/input_error.h"
#include "jobs/store/campaign_store.h"
#include "tests/support/damage.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr std::int64_t kSamples = 64;
constexpr std::int64_t kFirstSamples = 16;
constexpr std::size_t kInputs = 3;
constexpr std::int64_t kChunkSamples = 16;  // four chunks along N: damage stays in one of them
const double kNaN = std::numeric_limits<double>::quiet_NaN();

fs::path TestFolder() { return ringtol::testing::FreshTestFolder("allocation_store_test"); }

std::string InputErrorOf(const std::function<void()>& action) {
  return ringtol::testing::MessageOf<InputError>(action);
}

// Three components of 3, 2 and 2 options: 12 candidates. Two constraints on runout_mm and
// one on max_contact_force_N, so two outputs are stored.
AllocationIdentity TestIdentity() {
  AllocationIdentity identity;
  identity.ringtol_version = "0.5.0";
  identity.catalogue_version = "iso-2024.1";
  identity.allocation_path = "allocations/demo.toml";
  identity.allocation_file = "[allocation]\nsamples = 64\nseed = 7\n\n[[constraints]]\noutput = \"runout_mm\"\n";
  identity.base_scene = "[ring]\nradius_mm = 302\n";
  identity.design = "sobol";
  identity.solver = "quasistatic";
  identity.screen = "linear";
  identity.search = "branch_and_bound";
  identity.seed = 0x9E3779B97F4A7C15u;
  identity.samples = kSamples;
  identity.first_samples = kFirstSamples;
  identity.confidence = 0.95;
  for (std::size_t i = 0; i < kInputs; ++i) {
    const int order = static_cast<int>(i) + 2;
    identity.inputs.push_back({"ring.order" + std::to_string(order) + ".amplitude_um",
                               sampling::ErrorSource::kRingShape, -1, order, "ring.order" + std::to_string(order),
                               "ring"});
  }
  identity.components = {"ring", "rollers", "springs"};
  identity.options = {{{"P3", "turned", 40.0, 1.0}, {"P2", "ground", 20.0, 2.0}, {"P1", "lapped", 10.0, 4.0}},
                      {{"Normal", "kea", 15.0, 1.0}, {"P5", "kea", 5.0, 3.0}},
                      {{"S20", "", 20.0, 0.5}, {"S5", "", 5.0, 1.5}}};
  identity.constraints = {{"runout_mm", analysis::ConstraintKind::kQuantile, 0.99, 0.02},
                          {"max_contact_force_N", analysis::ConstraintKind::kYield, 0.9, 2500.0},
                          {"runout_mm", analysis::ConstraintKind::kYield, 0.95, 0.03}};
  identity.reference = 5;
  return identity;
}

constexpr std::int64_t kCandidates = 12;

std::vector<double> DesignPoints() {
  std::vector<double> u;
  for (std::int64_t i = 0; i < kSamples; ++i) {
    for (std::size_t j = 0; j < kInputs; ++j) {
      u.push_back(std::fmod(0.5 + static_cast<double>(i) * 0.6180339887498949 + static_cast<double>(j) * 0.7548776662,
                            1.0));
    }
  }
  return u;
}

AllocationStoreOptions TestOptions() {
  AllocationStoreOptions options;
  options.chunk_samples = kChunkSamples;
  return options;
}

// A sample whose every field is a pure function of (role, candidate, index), so that any
// run, killed or not, must store the same bits. Every 11th fails in the solver.
SampleRecord DeterministicRecord(EvaluationRole role, std::int64_t candidate, std::int64_t index) {
  const double x = static_cast<double>(index) + 1000.0 * static_cast<double>(candidate) +
                   (role == EvaluationRole::kScreen ? 0.5 : 0.0);
  SampleRecord record;
  record.index = index;
  record.steps = 360 + static_cast<std::int32_t>(index % 7);
  record.solve_time = 1e-3 * std::sqrt(x + 1.0);
  if (index % 11 == 5) {
    record.status = FromSolverStatus(solvers::Status::kNotConverged);
    record.outputs.fill(kNaN);
    record.d_trajectory_error = kNaN;
  } else {
    record.status = SampleStatus::kOk;
    for (std::size_t k = 0; k < kOutputCount; ++k) record.outputs[k] = x * 1e-5 + static_cast<double>(k) / 7.0;
    record.d_trajectory_error = x * 1e-7;
  }
  return record;
}

double StoredOutput(const SampleRecord& record, std::string_view output) {
  if (record.status != SampleStatus::kOk) return kNaN;
  const auto* found = std::find(kOutputNames.begin(), kOutputNames.end(), output);
  return record.outputs[static_cast<std::size_t>(found - kOutputNames.begin())];
}

std::vector<std::uint64_t> Bits(const std::vector<double>& values) {
  std::vector<std::uint64_t> bits;
  for (const double value : values) bits.push_back(std::bit_cast<std::uint64_t>(value));
  return bits;
}

// What a store or reader must hold for samples [begin, end) of a candidate written as DeterministicRecord.
template <typename Source>
void ExpectDeterministic(const Source& source, EvaluationRole role, std::int64_t candidate, std::int64_t begin,
                         std::int64_t end) {
  SCOPED_TRACE(std::string(NameOf(kEvaluationRoleNames, role)) + " candidate " + std::to_string(candidate) +
               " samples [" + std::to_string(begin) + ", " + std::to_string(end) + ")");
  std::vector<SampleStatus> statuses;
  std::vector<double> runout;
  std::vector<double> force;
  for (std::int64_t i = begin; i < end; ++i) {
    const SampleRecord record = DeterministicRecord(role, candidate, i);
    statuses.push_back(record.status);
    runout.push_back(StoredOutput(record, "runout_mm"));
    force.push_back(StoredOutput(record, "max_contact_force_N"));
  }
  EXPECT_EQ(source.ReadStatus(role, candidate, begin, end), statuses);
  EXPECT_EQ(Bits(source.ReadOutput(role, "runout_mm", candidate, begin, end)), Bits(runout));
  EXPECT_EQ(Bits(source.ReadOutput(role, "max_contact_force_N", candidate, begin, end)), Bits(force));
}

void AddDeterministic(AllocationStore& store, EvaluationRole role, std::int64_t candidate, std::int64_t begin,
                      std::int64_t end) {
  for (std::int64_t i = end; i-- > begin;) store.Add(role, candidate, DeterministicRecord(role, candidate, i));
}

// An outcome with every field set to something other than its default.
AllocationOutcome TestOutcome() {
  AllocationOutcome outcome;
  outcome.candidates.resize(kCandidates);
  for (std::int64_t c = 0; c < kCandidates; ++c) {
    CandidateOutcome& candidate = outcome.candidates[static_cast<std::size_t>(c)];
    candidate.settlement = analysis::Settlement::kNotVisited;
  }
  CandidateOutcome& screened = outcome.candidates[1];
  screened.settlement = analysis::Settlement::kSimulated;
  screened.verdict = analysis::Verdict::kInfeasible;
  screened.settled_by = EvaluationRole::kScreen;
  screened.samples = kFirstSamples;
  screened.constraints = {{analysis::Verdict::kInfeasible, 0.031, {0.025, 0.04}, kFirstSamples, 0},
                          {analysis::Verdict::kUndecided, 0.8, {0.5, 0.95}, kFirstSamples, 120},
                          {analysis::Verdict::kInfeasible, 0.5, {0.3, 0.7}, kFirstSamples, 0}};
  screened.yield = {8, kFirstSamples, 0.5, {0.25, 0.75}, 0.95};
  CandidateOutcome& confirmed = outcome.candidates[7];
  confirmed.settlement = analysis::Settlement::kSimulated;
  confirmed.verdict = analysis::Verdict::kFeasible;
  confirmed.settled_by = EvaluationRole::kConfirm;
  confirmed.samples = kSamples;
  confirmed.constraints = {
      {analysis::Verdict::kFeasible, 0.011, {0.009, -std::numeric_limits<double>::infinity()}, kSamples, 0},
      {analysis::Verdict::kFeasible, 1.0, {0.95, 1.0}, kSamples, 0},
      {analysis::Verdict::kFeasible, 1.0, {0.96, 1.0}, kSamples, 0}};
  confirmed.yield = {64, kSamples, 1.0, {0.944, 1.0}, 0.95};
  CandidateOutcome& implied = outcome.candidates[11];
  implied.settlement = analysis::Settlement::kImplied;
  implied.verdict = analysis::Verdict::kFeasible;
  implied.implied_by = 7;
  outcome.candidates[9].settlement = analysis::Settlement::kCostlier;
  outcome.complete = true;
  outcome.recommendation = 7;
  outcome.alternatives = {11, 9};
  outcome.undecided_cheaper = {3};
  outcome.front = {1, 7};
  outcome.binding = {2, 0};
  outcome.common_random_numbers_gain = 3.25;
  outcome.simulated = 2;
  outcome.settled_by_screen = 1;
  outcome.samples_screen = kFirstSamples;
  outcome.samples_confirm = kSamples;
  return outcome;
}

void ExpectSameOutcome(const AllocationOutcome& actual, const AllocationOutcome& expected) {
  ASSERT_EQ(actual.candidates.size(), expected.candidates.size());
  for (std::size_t c = 0; c < expected.candidates.size(); ++c) {
    SCOPED_TRACE("candidate " + std::to_string(c));
    const CandidateOutcome& a = actual.candidates[c];
    const CandidateOutcome& e = expected.candidates[c];
    EXPECT_EQ(a.verdict, e.verdict);
    EXPECT_EQ(a.settlement, e.settlement);
    EXPECT_EQ(a.settled_by, e.settled_by);
    EXPECT_EQ(a.samples, e.samples);
    EXPECT_EQ(a.implied_by, e.implied_by);
    ASSERT_EQ(a.constraints.size(), e.constraints.size());
    for (std::size_t j = 0; j < e.constraints.size(); ++j) {
      EXPECT_EQ(a.constraints[j].verdict, e.constraints[j].verdict);
      EXPECT_EQ(std::bit_cast<std::uint64_t>(a.constraints[j].estimate),
                std::bit_cast<std::uint64_t>(e.constraints[j].estimate));
      EXPECT_EQ(Bits({a.constraints[j].interval.lower, a.constraints[j].interval.upper}),
                Bits({e.constraints[j].interval.lower, e.constraints[j].interval.upper}));
      EXPECT_EQ(a.constraints[j].samples, e.constraints[j].samples);
      EXPECT_EQ(a.constraints[j].samples_to_decide, e.constraints[j].samples_to_decide);
    }
    EXPECT_EQ(a.yield.trials, e.yield.trials);
    EXPECT_EQ(a.yield.successes, e.yield.successes);
    if (e.yield.trials > 0) {
      EXPECT_EQ(Bits({a.yield.value, a.yield.interval.lower, a.yield.interval.upper}),
                Bits({e.yield.value, e.yield.interval.lower, e.yield.interval.upper}));
    }
  }
  EXPECT_EQ(actual.complete, expected.complete);
  EXPECT_EQ(actual.recommendation, expected.recommendation);
  EXPECT_EQ(actual.alternatives, expected.alternatives);
  EXPECT_EQ(actual.undecided_cheaper, expected.undecided_cheaper);
  EXPECT_EQ(actual.front, expected.front);
  EXPECT_EQ(actual.binding, expected.binding);
  EXPECT_EQ(actual.common_random_numbers_gain, expected.common_random_numbers_gain);
  EXPECT_EQ(actual.simulated, expected.simulated);
  EXPECT_EQ(actual.settled_by_screen, expected.settled_by_screen);
  EXPECT_EQ(actual.samples_screen, expected.samples_screen);
  EXPECT_EQ(actual.samples_confirm, expected.samples_confirm);
}

void ExpectSameIdentity(const AllocationIdentity& a, const AllocationIdentity& e) {
  EXPECT_EQ(a.ringtol_version, e.ringtol_version);
  EXPECT_EQ(a.catalogue_version, e.catalogue_version);
  EXPECT_EQ(a.allocation_path, e.allocation_path);
  EXPECT_EQ(a.allocation_file, e.allocation_file);
  EXPECT_EQ(a.base_scene, e.base_scene);
  EXPECT_EQ(a.design, e.design);
  EXPECT_EQ(a.solver, e.solver);
  EXPECT_EQ(a.screen, e.screen);
  EXPECT_EQ(a.search, e.search);
  EXPECT_EQ(a.seed, e.seed);
  EXPECT_EQ(a.samples, e.samples);
  EXPECT_EQ(a.first_samples, e.first_samples);
  EXPECT_EQ(a.confidence, e.confidence);
  ASSERT_EQ(a.inputs.size(), e.inputs.size());
  for (std::size_t i = 0; i < e.inputs.size(); ++i) {
    EXPECT_EQ(a.inputs[i].name, e.inputs[i].name);
    EXPECT_EQ(a.inputs[i].source, e.inputs[i].source);
    EXPECT_EQ(a.inputs[i].roller, e.inputs[i].roller);
    EXPECT_EQ(a.inputs[i].order, e.inputs[i].order);
  }
  EXPECT_EQ(a.components, e.components);
  ASSERT_EQ(a.options.size(), e.options.size());
  for (std::size_t k = 0; k < e.options.size(); ++k) {
    ASSERT_EQ(a.options[k].size(), e.options[k].size());
    for (std::size_t o = 0; o < e.options[k].size(); ++o) {
      EXPECT_EQ(a.options[k][o].class_name, e.options[k][o].class_name);
      EXPECT_EQ(a.options[k][o].mode, e.options[k][o].mode);
      EXPECT_EQ(a.options[k][o].tolerance, e.options[k][o].tolerance);
      EXPECT_EQ(a.options[k][o].cost, e.options[k][o].cost);
    }
  }
  ASSERT_EQ(a.constraints.size(), e.constraints.size());
  for (std::size_t j = 0; j < e.constraints.size(); ++j) {
    EXPECT_EQ(a.constraints[j].output, e.constraints[j].output);
    EXPECT_EQ(a.constraints[j].kind, e.constraints[j].kind);
    EXPECT_EQ(a.constraints[j].level, e.constraints[j].level);
    EXPECT_EQ(a.constraints[j].upper, e.constraints[j].upper);
  }
  EXPECT_EQ(a.reference, e.reference);
}

// ---------------------------------------------------------------------------------------

TEST(AllocationStore, RoundTripsIdentityDesignSamplesAndOutcome) {
  const fs::path path = TestFolder() / "allocation.h5";
  {
    AllocationStore store = AllocationStore::Create(path, TestIdentity(), DesignPoints(), TestOptions());
    AddDeterministic(store, EvaluationRole::kScreen, 1, 0, kFirstSamples);
    AddDeterministic(store, EvaluationRole::kConfirm, 7, 0, kSamples);
    store.Commit(TestOutcome());
  }
  const AllocationReader reader(path);
  ExpectSameIdentity(reader.identity(), TestIdentity());
  EXPECT_EQ(Bits(reader.ReadDesignPoints(0, kSamples)), Bits(DesignPoints()));
  ExpectDeterministic(reader, EvaluationRole::kScreen, 1, 0, kFirstSamples);
  ExpectDeterministic(reader, EvaluationRole::kConfirm, 7, 0, kSamples);
  EXPECT_EQ(reader.ReadStatus(EvaluationRole::kScreen, 1, kFirstSamples, kSamples),
            std::vector<SampleStatus>(kSamples - kFirstSamples, SampleStatus::kPending));
  EXPECT_EQ(reader.ReadStatus(EvaluationRole::kConfirm, 1, 0, kSamples),
            std::vector<SampleStatus>(kSamples, SampleStatus::kPending));
  const AllocationOutcome outcome = reader.ReadOutcome();
  ExpectSameOutcome(outcome, TestOutcome());
  // Options and costs come from the identity: mixed radix, the last component fastest;
  // candidate 7 = (1, 1, 1): 2 + 3 + 1.5, relative to candidate 5 = (1, 0, 1): 2 + 1 + 1.5.
  EXPECT_EQ(outcome.candidates[7].options, (std::vector<int>{1, 1, 1}));
  EXPECT_EQ(outcome.candidates[7].cost, 6.5);
  EXPECT_EQ(outcome.candidates[7].relative_cost, 6.5 / 4.5);
}

TEST(AllocationStore, AFreshFileReadsAsAnEmptyOutcomeWithEverySamplePending) {
  const fs::path path = TestFolder() / "allocation.h5";
  AllocationStore::Create(path, TestIdentity(), DesignPoints(), TestOptions());
  const AllocationReader reader(path);
  const AllocationOutcome outcome = reader.ReadOutcome();
  ASSERT_EQ(outcome.candidates.size(), static_cast<std::size_t>(kCandidates));
  EXPECT_EQ(outcome.candidates[0].settlement, analysis::Settlement::kNotVisited);
  EXPECT_EQ(outcome.candidates[0].settled_by, std::nullopt);
  EXPECT_FALSE(outcome.recommendation);
  EXPECT_FALSE(outcome.complete);
  EXPECT_TRUE(outcome.front.empty());
  EXPECT_TRUE(std::isnan(outcome.common_random_numbers_gain));
  EXPECT_EQ(reader.ReadStatus(EvaluationRole::kScreen, kCandidates - 1, 0, kSamples),
            std::vector<SampleStatus>(kSamples, SampleStatus::kPending));
}

TEST(AllocationStore, DoneAndReadSeeBufferedSamplesBeforeTheCommit) {
  const fs::path path = TestFolder() / "allocation.h5";
  AllocationStore store = AllocationStore::Create(path, TestIdentity(), DesignPoints(), TestOptions());
  AddDeterministic(store, EvaluationRole::kScreen, 4, 0, kFirstSamples);
  EXPECT_EQ(store.buffered(), static_cast<std::size_t>(kFirstSamples));
  ExpectDeterministic(store, EvaluationRole::kScreen, 4, 0, kFirstSamples);
  const std::vector<bool> done = store.Done(EvaluationRole::kScreen, 4, 0, 2 * kFirstSamples);
  EXPECT_EQ(std::count(done.begin(), done.end(), true), kFirstSamples);
  EXPECT_TRUE(done[kFirstSamples - 1]);
  EXPECT_FALSE(done[kFirstSamples]);
  // The other role of the same candidate is untouched.
  const std::vector<bool> confirm = store.Done(EvaluationRole::kConfirm, 4, 0, kFirstSamples);
  EXPECT_EQ(std::count(confirm.begin(), confirm.end(), true), 0);
  const std::vector<double> bounds = store.ReadErrorBound(4, 0, 1);
  EXPECT_EQ(bounds.front(), DeterministicRecord(EvaluationRole::kScreen, 4, 0).d_trajectory_error);
  // Nothing is on disk before the commit.
  EXPECT_EQ(AllocationReader(path).ReadStatus(EvaluationRole::kScreen, 4, 0, 1).front(), SampleStatus::kPending);
  store.Commit(TestOutcome());
  EXPECT_EQ(store.buffered(), 0u);
  ExpectDeterministic(AllocationReader(path), EvaluationRole::kScreen, 4, 0, kFirstSamples);
  ExpectDeterministic(store, EvaluationRole::kScreen, 4, 0, kFirstSamples);
}

TEST(AllocationStore, RejectsSamplesAndOutcomesThatDoNotFitTheAllocation) {
  const fs::path path = TestFolder() / "allocation.h5";
  AllocationStore store = AllocationStore::Create(path, TestIdentity(), DesignPoints(), TestOptions());
  EXPECT_THROW(store.Add(EvaluationRole::kScreen, kCandidates, DeterministicRecord(EvaluationRole::kScreen, 0, 0)),
               std::out_of_range);
  EXPECT_THROW(store.Add(EvaluationRole::kScreen, 0, DeterministicRecord(EvaluationRole::kScreen, 0, kSamples)),
               std::out_of_range);
  SampleRecord pending = DeterministicRecord(EvaluationRole::kScreen, 0, 0);
  pending.status = SampleStatus::kPending;
  EXPECT_THROW(store.Add(EvaluationRole::kScreen, 0, pending), std::invalid_argument);
  EXPECT_THROW(store.ReadOutput(EvaluationRole::kScreen, "swing_mm", 0, 0, 1), std::invalid_argument);
  AllocationOutcome short_outcome = TestOutcome();
  short_outcome.candidates.pop_back();
  EXPECT_THROW(store.Commit(short_outcome), std::invalid_argument);
  AllocationOutcome bad_judgements = TestOutcome();
  bad_judgements.candidates[7].constraints.pop_back();
  EXPECT_THROW(store.Commit(bad_judgements), std::invalid_argument);
  AllocationOutcome unknown_binding = TestOutcome();
  unknown_binding.binding = {static_cast<int>(TestIdentity().constraints.size())};
  EXPECT_THROW(store.Commit(unknown_binding), std::invalid_argument);
}

TEST(AllocationStore, CreateRefusesAnExistingPathAndAMissingDirectory) {
  const fs::path folder = TestFolder();
  const fs::path path = folder / "allocation.h5";
  AllocationStore::Create(path, TestIdentity(), DesignPoints(), TestOptions());
  EXPECT_THAT(InputErrorOf([&] { AllocationStore::Create(path, TestIdentity(), DesignPoints()); }),
              HasSubstr("already exists; pass --resume"));
  const fs::path missing = folder / "no_such_directory" / "allocation.h5";
  EXPECT_THAT(InputErrorOf([&] { AllocationStore::Create(missing, TestIdentity(), DesignPoints()); }),
              HasSubstr("directory '" + (folder / "no_such_directory").string() + "' does not exist"));
}

TEST(AllocationStore, ResumeRefusesAnotherAllocationNamingWhatDiffers) {
  const fs::path path = TestFolder() / "allocation.h5";
  AllocationStore::Create(path, TestIdentity(), DesignPoints(), TestOptions());
  struct Case {
    std::function<void(AllocationIdentity&)> change;
    std::string named;
  };
  const std::vector<Case> cases = {
      {[](AllocationIdentity& i) { i.seed += 1; }, "seed differs"},
      {[](AllocationIdentity& i) { i.allocation_file += "\n"; }, "allocation_file differs (first at line"},
      {[](AllocationIdentity& i) { i.screen = "none"; }, "screen differs ('linear' in the file, 'none' now)"},
      {[](AllocationIdentity& i) { i.samples *= 2; }, "samples differs"},
      {[](AllocationIdentity& i) { i.options[1][1].cost = 3.5; }, "options of rollers differs"},
      {[](AllocationIdentity& i) { i.constraints[0].upper = 0.025; }, "constraints differs"},
      {[](AllocationIdentity& i) { i.reference.reset(); }, "reference differs"},
  };
  for (const Case& c : cases) {
    AllocationIdentity other = TestIdentity();
    c.change(other);
    EXPECT_THAT(InputErrorOf([&] { AllocationStore::Resume(path, other); }),
                AllOf(HasSubstr("was written by another allocation"), HasSubstr(c.named)));
  }
  AllocationIdentity moved = TestIdentity();
  moved.allocation_path = "elsewhere/demo.toml";  // provenance only
  EXPECT_NO_THROW(AllocationStore::Resume(path, moved));
}

TEST(AllocationStore, ResumeAndReaderRefuseACampaignFileNamingItsKind) {
  const fs::path folder = TestFolder();
  const fs::path campaign = folder / "campaign.h5";
  CampaignIdentity identity;
  identity.inputs = TestIdentity().inputs;
  identity.rollers = {"spring", "fixed_a", "fixed_b"};
  CampaignStore::Create(campaign, identity, 8);
  EXPECT_THAT(InputErrorOf([&] { AllocationStore::Resume(campaign, TestIdentity()); }),
              HasSubstr("is a ringtol campaign results file, not an allocation's"));
  EXPECT_THAT(InputErrorOf([&] { AllocationReader reader(campaign); }), HasSubstr("is a ringtol campaign"));
}

TEST(ReadResultsKind, TellsCampaignsFromAllocationsAndRefusesOtherHdf5Files) {
  const fs::path folder = TestFolder();
  const fs::path allocation = folder / "allocation.h5";
  AllocationStore::Create(allocation, TestIdentity(), DesignPoints(), TestOptions());
  const fs::path campaign = folder / "campaign.h5";
  CampaignIdentity identity;
  identity.inputs = TestIdentity().inputs;
  identity.rollers = {"spring", "fixed_a", "fixed_b"};
  CampaignStore::Create(campaign, identity, 8);
  const fs::path foreign = folder / "foreign.h5";
  H5Fclose(H5Fcreate(foreign.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, H5P_DEFAULT));

  EXPECT_EQ(ReadResultsKind(allocation), ResultsKind::kAllocation);
  EXPECT_EQ(ReadResultsKind(campaign), ResultsKind::kCampaign);
  EXPECT_THAT(InputErrorOf([&] { ReadResultsKind(foreign); }), HasSubstr("is not a ringtol results file"));
  EXPECT_THAT(InputErrorOf([&] { ReadResultsKind(folder / "missing.h5"); }), HasSubstr("does not exist"));
  // The campaign's readers name what an allocation file is.
  EXPECT_THAT(InputErrorOf([&] { CheckResults(allocation); }), HasSubstr("is a ringtol allocation results file"));
  EXPECT_THAT(InputErrorOf([&] { CampaignReader reader(allocation); }), HasSubstr("not a campaign's"));
}

// ---------------------------------------------------------------------------------------
// Damage

// A damaged range of an allocation's check, by dataset, candidate and samples.
struct Damaged {
  std::string path;
  std::int64_t candidate = 0;
  SampleRange samples;
  std::string problem;
};
std::vector<Damaged> DamagedOf(const ResultsCheck& check) {
  std::vector<Damaged> damaged;
  for (const DatasetCheck& dataset : check.datasets) {
    for (const SampleRange& rows : dataset.damaged) {
      damaged.push_back({dataset.path, check.CandidateOf(rows), check.SamplesOf(rows), dataset.first_problem});
    }
  }
  return damaged;
}

constexpr std::int64_t kDamagedCandidate = 2;
constexpr std::int64_t kDamagedSample = 20;  // in the second chunk, [16, 32)
constexpr std::size_t kFlippedBytes = 8;

void FlipChunk(const fs::path& path, const std::string& dataset, std::int64_t candidate, std::int64_t sample) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t data = H5Dopen2(file, dataset.c_str(), H5P_DEFAULT);
  const hsize_t offset[2] = {static_cast<hsize_t>(candidate),
                             static_cast<hsize_t>(sample / kChunkSamples * kChunkSamples)};
  unsigned mask = 0;
  haddr_t address = 0;
  hsize_t bytes = 0;
  EXPECT_GE(H5Dget_chunk_info_by_coord(data, offset, &mask, &address, &bytes), 0) << dataset;
  H5Dclose(data);
  H5Fclose(file);
  testing::FlipBytes(path, address + bytes / 2 - kFlippedBytes / 2, kFlippedBytes);
}

TEST(AllocationStore, ResumeRepairsADamagedChunkToPendingAndKeepsTheRest) {
  const fs::path path = TestFolder() / "allocation.h5";
  {
    AllocationStore store = AllocationStore::Create(path, TestIdentity(), DesignPoints(), TestOptions());
    AddDeterministic(store, EvaluationRole::kConfirm, kDamagedCandidate, 0, kSamples);
    store.Commit(TestOutcome());
  }
  FlipChunk(path, "/samples/confirm/runout_mm", kDamagedCandidate, kDamagedSample);
  EXPECT_THAT(InputErrorOf([&] {
                AllocationReader(path).ReadOutput(EvaluationRole::kConfirm, "runout_mm", kDamagedCandidate, 0,
                                                  kSamples);
              }),
              AllOf(HasSubstr("dataset /samples/confirm/runout_mm is damaged"), HasSubstr("candidate 2")));

  const std::int64_t first = kDamagedSample / kChunkSamples * kChunkSamples;
  const ResultsCheck check = CheckAllocationResults(path);
  EXPECT_FALSE(check.intact());
  const std::vector<Damaged> damaged = DamagedOf(check);
  ASSERT_EQ(damaged.size(), 1u);
  EXPECT_EQ(damaged[0].path, "/samples/confirm/runout_mm");
  EXPECT_EQ(damaged[0].candidate, kDamagedCandidate);
  EXPECT_EQ(damaged[0].samples, (SampleRange{first, first + kChunkSamples}));
  EXPECT_EQ(check.done_confirm, kSamples);

  AllocationStore store = AllocationStore::Resume(path, TestIdentity(), TestOptions());
  const std::vector<bool> done = store.Done(EvaluationRole::kConfirm, kDamagedCandidate, 0, kSamples);
  for (std::int64_t i = 0; i < kSamples; ++i) {
    EXPECT_EQ(done[static_cast<std::size_t>(i)], i < first || i >= first + kChunkSamples) << "sample " << i;
  }
  ExpectDeterministic(store, EvaluationRole::kConfirm, kDamagedCandidate, 0, first);
  ExpectDeterministic(store, EvaluationRole::kConfirm, kDamagedCandidate, first + kChunkSamples, kSamples);
  // Computed again, the chunk holds the same bits as before.
  AddDeterministic(store, EvaluationRole::kConfirm, kDamagedCandidate, first, first + kChunkSamples);
  store.Commit(TestOutcome());
  ExpectDeterministic(AllocationReader(path), EvaluationRole::kConfirm, kDamagedCandidate, 0, kSamples);
}

TEST(AllocationStore, EveryDatasetEndsItsFiltersWithTheFletcher32Checksum) {
  const fs::path path = TestFolder() / "allocation.h5";
  AllocationStore::Create(path, TestIdentity(), DesignPoints(), TestOptions());
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  std::vector<std::string> unchecked;
  H5Ovisit2(
      file, H5_INDEX_NAME, H5_ITER_NATIVE,
      [](hid_t root, const char* name, const H5O_info_t* info, void* data) -> herr_t {
        if (info->type != H5O_TYPE_DATASET) return 0;
        const hid_t dataset = H5Dopen2(root, name, H5P_DEFAULT);
        const hid_t dcpl = H5Dget_create_plist(dataset);
        const int filters = H5Pget_nfilters(dcpl);
        unsigned flags = 0;
        std::size_t elements = 0;
        const bool last_is_checksum =
            filters > 0 && H5Pget_filter2(dcpl, static_cast<unsigned>(filters - 1), &flags, &elements, nullptr, 0,
                                          nullptr, nullptr) == H5Z_FILTER_FLETCHER32;
        if (!last_is_checksum) static_cast<std::vector<std::string>*>(data)->push_back(name);
        H5Pclose(dcpl);
        H5Dclose(dataset);
        return 0;
      },
      &unchecked, H5O_INFO_BASIC);
  H5Fclose(file);
  EXPECT_THAT(unchecked, ::testing::IsEmpty());
  const ResultsCheck check = CheckAllocationResults(path);
  EXPECT_TRUE(check.intact());
  EXPECT_TRUE(check.checksummed());
  EXPECT_EQ(check.candidates, kCandidates);
  EXPECT_EQ(check.done_screen + check.done_confirm, 0);
  EXPECT_TRUE(std::any_of(check.datasets.begin(), check.datasets.end(), [](const DatasetCheck& d) {
    return d.path == "/samples/screen/d_trajectory_error_mm" && d.per_sample && d.checksummed;
  }));
}

// ---------------------------------------------------------------------------------------
// Crash safety: a child process commits candidates batch after batch and is killed with
// SIGKILL at a different moment each round, on the file the previous round left. After
// every kill a resume must find every sample it calls done exact, and the batches it had
// committed before the kill (it says so through a pipe) done.

constexpr std::int64_t kKillBatchCandidates = 2;
constexpr int kKillRounds = 8;
constexpr auto kFirstKill = std::chrono::milliseconds(0);
constexpr auto kLastKill = std::chrono::milliseconds(30);

// Writes every candidate's screen and confirm samples, a batch of candidates per commit,
// skipping what is done; writes a byte to `committed` after each commit.
void WriteAllocation(const fs::path& path, int committed) {
  AllocationStore store = fs::exists(path) ? AllocationStore::Resume(path, TestIdentity(), TestOptions())
                                           : AllocationStore::Create(path, TestIdentity(), DesignPoints(), TestOptions());
  for (int pass = 0;; ++pass) {  // rewrites everything, committing on, until killed
    for (std::int64_t c = 0; c < kCandidates; ++c) {
      for (const EvaluationRole role : {EvaluationRole::kScreen, EvaluationRole::kConfirm}) {
        const std::vector<bool> done = store.Done(role, c, 0, kSamples);
        for (std::int64_t i = kSamples; i-- > 0;) {
          if (pass > 0 || !done[static_cast<std::size_t>(i)]) store.Add(role, c, DeterministicRecord(role, c, i));
        }
      }
      if (c % kKillBatchCandidates == kKillBatchCandidates - 1) {
        store.Commit(TestOutcome());
        const char byte = 1;
        if (committed >= 0 && ::write(committed, &byte, 1) != 1) return;
      }
    }
    if (committed < 0) return;
  }
}

TEST(AllocationStore, SurvivesSigkillKeepingEveryCommittedSampleAndNothingHalfWritten) {
  const fs::path folder = TestFolder();
  const fs::path path = folder / "allocation.h5";
  int killed = 0;
  for (int round = 0; round < kKillRounds; ++round) {
    const auto delay = std::chrono::duration_cast<std::chrono::microseconds>(
        kFirstKill + (kLastKill - kFirstKill) * round / (kKillRounds - 1));
    SCOPED_TRACE("round " + std::to_string(round) + ": kill " + std::to_string(delay.count()) +
                 " us after the first commit");
    int pipe_ends[2];
    ASSERT_EQ(::pipe(pipe_ends), 0);
    std::fflush(nullptr);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0) << "fork failed";  // never kill(-1)
    if (child == 0) {
      ::close(pipe_ends[0]);
      int code = 0;
      try {
        WriteAllocation(path, pipe_ends[1]);
      } catch (const std::exception& error) {
        std::fprintf(stderr, "child: %s\n", error.what());
        code = 1;
      }
      ::_exit(code);  // never back into the test framework
    }
    ::close(pipe_ends[1]);
    char byte = 0;
    const bool committed = ::read(pipe_ends[0], &byte, 1) == 1;
    std::this_thread::sleep_for(delay);
    ::kill(child, SIGKILL);
    int status = 0;
    EXPECT_EQ(::waitpid(child, &status, 0), child);
    ::close(pipe_ends[0]);
    killed += WIFSIGNALED(status) ? 1 : 0;
    ASSERT_TRUE(committed) << "the child failed before its first commit";
    for (const auto& entry : fs::directory_iterator(folder)) {
      if (entry.path() != path) fs::remove(entry.path());
    }
    // The first batch was committed before the kill; every sample called done is exact.
    AllocationStore store = AllocationStore::Resume(path, TestIdentity(), TestOptions());
    for (std::int64_t c = 0; c < kCandidates && !HasFailure(); ++c) {
      for (const EvaluationRole role : {EvaluationRole::kScreen, EvaluationRole::kConfirm}) {
        const std::vector<SampleStatus> statuses = store.ReadStatus(role, c, 0, kSamples);
        if (c < kKillBatchCandidates) {
          EXPECT_EQ(std::count(statuses.begin(), statuses.end(), SampleStatus::kPending), 0) << "candidate " << c;
        }
        for (std::int64_t i = 0; i < kSamples; ++i) {
          if (statuses[static_cast<std::size_t>(i)] != SampleStatus::kPending) {
            ExpectDeterministic(store, role, c, i, i + 1);
          }
        }
      }
    }
    ASSERT_FALSE(HasFailure());
  }
  EXPECT_GE(killed, kKillRounds / 2) << "the kills came too late to test anything";
  WriteAllocation(path, -1);
  const AllocationReader reader(path);
  for (std::int64_t c = 0; c < kCandidates; ++c) {
    ExpectDeterministic(reader, EvaluationRole::kScreen, c, 0, kSamples);
    ExpectDeterministic(reader, EvaluationRole::kConfirm, c, 0, kSamples);
  }
  ExpectSameOutcome(reader.ReadOutcome(), TestOutcome());
}

// ---------------------------------------------------------------------------------------
// Size: the [C, N] datasets are chunked by candidate rows, so what a file takes follows
// what was simulated, not C x N. The allocation docs/results.md quotes: 160 candidates of
// up to 2048 samples, every one screened at 256 and 20 confirmed to 2048, one constraint.

TEST(AllocationStore, TakesSpaceForTheSamplesSimulatedNotForEveryCandidate) {
  constexpr std::int64_t kSizeSamples = 2048;
  constexpr std::int64_t kScreenSamples = 256;
  constexpr std::int64_t kConfirmed = 20;
  AllocationIdentity identity = TestIdentity();
  identity.samples = kSizeSamples;
  identity.first_samples = kScreenSamples;
  identity.options = {std::vector<AllocationIdentity::Option>(5, {"IT", "", 10.0, 1.0}),
                      std::vector<AllocationIdentity::Option>(4, {"P", "kea", 5.0, 1.0}),
                      std::vector<AllocationIdentity::Option>(2, {"S", "", 10.0, 1.0}),
                      std::vector<AllocationIdentity::Option>(4, {"IT", "", 20.0, 1.0})};
  identity.components = {"ring", "rollers", "springs", "roller_positions"};
  identity.constraints = {{"runout_mm", analysis::ConstraintKind::kQuantile, 0.99, 0.02}};
  identity.reference.reset();
  const std::int64_t candidates = 5 * 4 * 2 * 4;
  ASSERT_EQ(candidates, 160);
  const std::vector<double> u(static_cast<std::size_t>(kSizeSamples) * kInputs, 0.25);
  AllocationOutcome outcome;
  outcome.candidates.resize(static_cast<std::size_t>(candidates));

  const fs::path path = TestFolder() / "allocation.h5";
  {
    AllocationStore store = AllocationStore::Create(path, identity, u);
    store.Commit(outcome);
  }
  const auto empty = static_cast<double>(fs::file_size(path));
  {
    AllocationStore store = AllocationStore::Resume(path, identity);
    for (std::int64_t c = 0; c < candidates; ++c) {
      AddDeterministic(store, EvaluationRole::kScreen, c, 0, kScreenSamples);
      store.Commit(outcome);
    }
    for (std::int64_t c = 0; c < kConfirmed; ++c) {
      for (std::int64_t n = kScreenSamples; n <= kSizeSamples; n *= 2) {  // stage by stage
        AddDeterministic(store, EvaluationRole::kConfirm, c, n == kScreenSamples ? 0 : n / 2, n);
        store.Commit(outcome);
      }
    }
  }
  const auto full = static_cast<double>(fs::file_size(path));
  // Per sample: screen runout, error bound, solve time (8 bytes each), steps (4), status
  // (1); confirm the same without the error bound.
  const double data = static_cast<double>(candidates * kScreenSamples) * (3 * 8 + 4 + 1) +
                      static_cast<double>(kConfirmed * kSizeSamples) * (2 * 8 + 4 + 1);
  const double dense = static_cast<double>(candidates * kSizeSamples) * (3 * 8 + 4 + 1 + 2 * 8 + 4 + 1);
  std::printf("allocation file: %.0f bytes before any sample, %.0f after (%.0f bytes of samples; %.0f if every "
              "candidate took N samples of both roles)\n",
              empty, full, data, dense);
  RecordProperty("bytes_empty", std::to_string(empty));
  RecordProperty("bytes_full", std::to_string(full));
  // Chunk index entries, B-tree nodes and the outcome's datasets cost a few hundred bytes a
  // chunk: well below half again the data.
  constexpr double kOverheadFactor = 1.5;
  EXPECT_LT(full - empty, kOverheadFactor * data);
  EXPECT_LT(empty, data);
}

// The rows of a shard's index entry, from what the shard itself says it holds.
AllocationShard ShardOf(const fs::path& path) {
  const AllocationStore shard = AllocationStore::Resume(path, TestIdentity(), TestOptions());
  AllocationShard entry{path, {}};
  for (const AllocationSample& sample : shard.Finished()) {
    auto& rows = entry.rows[sample.role == EvaluationRole::kScreen ? 0 : 1];
    if (rows.empty() || rows.back().candidate != sample.candidate) rows.push_back({sample.candidate, {}});
    std::vector<SampleRange>& samples = rows.back().samples;
    if (!samples.empty() && samples.back().end == sample.sample) {
      ++samples.back().end;
    } else {
      samples.push_back({sample.sample, sample.sample + 1});
    }
  }
  return entry;
}

// The root attribute `layout` marks an index; indexes written before it are recognised by
// their schema number.
TEST(AllocationShardIndex, SaysWhatItIsAndIsReadAsAnIndexWithoutTheAttributeToo) {
  const fs::path index = TestFolder() / "allocation.h5";
  const fs::path shard = ShardPath(index, 0);
  {
    AllocationStore zero = AllocationStore::CreateShard(shard, TestIdentity(), TestOptions());
    AddDeterministic(zero, EvaluationRole::kScreen, 1, 0, kFirstSamples);
    zero.CommitSamples();
  }
  WriteAllocationIndex(index, TestIdentity(), DesignPoints(), TestOutcome(), {ShardOf(shard)});
  const auto layout = [](const fs::path& path) {
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    std::string value = "(none)";
    if (H5Aexists(file, "layout") > 0) {
      const hid_t attribute = H5Aopen(file, "layout", H5P_DEFAULT);
      const hid_t type = H5Aget_type(attribute);
      char* text = nullptr;
      if (H5Aread(attribute, type, &text) >= 0 && text != nullptr) value = text;
      H5free_memory(text);
      H5Tclose(type);
      H5Aclose(attribute);
    }
    H5Fclose(file);
    return value;
  };
  EXPECT_EQ(layout(index), "shard index");
  EXPECT_EQ(layout(shard), "file");
  {
    const hid_t file = H5Fopen(index.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    H5Adelete(file, "layout");
    H5Adelete(file, "rows_schema");
    H5Fclose(file);
  }
  ASSERT_EQ(layout(index), "(none)");
  EXPECT_EQ(IndexedAllocationShards(index), std::vector<fs::path>{shard});
  ExpectDeterministic(AllocationReader(index), EvaluationRole::kScreen, 1, 0, kFirstSamples);
}

TEST(AllocationShardIndex, ReadsEverySampleFromTheShardThatHoldsItAndChecksEveryShard) {
  const fs::path folder = TestFolder();
  const fs::path index = folder / "allocation.h5";
  const fs::path shards[2] = {ShardPath(index, 0), ShardPath(index, 1)};
  {
    AllocationStore zero = AllocationStore::CreateShard(shards[0], TestIdentity(), TestOptions());
    AllocationStore one = AllocationStore::CreateShard(shards[1], TestIdentity(), TestOptions());
    AddDeterministic(zero, EvaluationRole::kScreen, 1, 0, kFirstSamples);
    AddDeterministic(zero, EvaluationRole::kConfirm, kDamagedCandidate, 0, 32);
    AddDeterministic(one, EvaluationRole::kConfirm, kDamagedCandidate, 32, kSamples);
    AddDeterministic(one, EvaluationRole::kConfirm, 9, 8, 24);
    zero.CommitSamples();
    one.CommitSamples();
    // What a shard reports is what it holds, each sample's stored outputs and bound as kept.
    const std::vector<AllocationSample> finished = one.Finished();
    ASSERT_EQ(finished.size(), static_cast<std::size_t>((kSamples - 32) + 16));
    const AllocationSample& first = finished.front();
    EXPECT_EQ(first.candidate, kDamagedCandidate);
    EXPECT_EQ(first.sample, 32);
    const SampleRecord expected = DeterministicRecord(EvaluationRole::kConfirm, kDamagedCandidate, 32);
    ASSERT_EQ(one.outputs().size(), first.outputs.size());
    for (std::size_t q = 0; q < first.outputs.size(); ++q) {
      EXPECT_EQ(std::bit_cast<std::uint64_t>(first.outputs[q]),
                std::bit_cast<std::uint64_t>(StoredOutput(expected, one.outputs()[q])));
    }
  }
  WriteAllocationIndex(index, TestIdentity(), DesignPoints(), TestOutcome(), {ShardOf(shards[0]), ShardOf(shards[1])});
  EXPECT_EQ(IndexedAllocationShards(index), (std::vector<fs::path>{shards[0], shards[1]}));
  {
    const AllocationReader reader(index);
    EXPECT_EQ(Bits(reader.ReadDesignPoints(0, kSamples)), Bits(DesignPoints()));
    ExpectDeterministic(reader, EvaluationRole::kScreen, 1, 0, kFirstSamples);
    ExpectDeterministic(reader, EvaluationRole::kConfirm, kDamagedCandidate, 0, kSamples);
    ExpectDeterministic(reader, EvaluationRole::kConfirm, 9, 8, 24);
    EXPECT_EQ(reader.ReadStatus(EvaluationRole::kConfirm, 9, 0, 8), std::vector<SampleStatus>(8, SampleStatus::kPending));
    ExpectSameOutcome(reader.ReadOutcome(), TestOutcome());
  }
  ResultsCheck check = CheckAllocationResults(index);
  EXPECT_TRUE(check.intact());
  EXPECT_TRUE(check.checksummed());
  EXPECT_EQ(check.done_screen, kFirstSamples);
  EXPECT_EQ(check.done_confirm, kSamples + 16);

  // Joined into one file, every sample, the design points and the outcome are as they were.
  const fs::path joined = folder / "joined.h5";
  EXPECT_EQ(JoinAllocationShards(index, joined), kFirstSamples + kSamples + 16);
  EXPECT_TRUE(IndexedAllocationShards(joined).empty());
  {
    const AllocationReader reader(joined);
    EXPECT_EQ(Bits(reader.ReadDesignPoints(0, kSamples)), Bits(DesignPoints()));
    ExpectDeterministic(reader, EvaluationRole::kScreen, 1, 0, kFirstSamples);
    ExpectDeterministic(reader, EvaluationRole::kConfirm, kDamagedCandidate, 0, kSamples);
    ExpectDeterministic(reader, EvaluationRole::kConfirm, 9, 8, 24);
    ExpectSameOutcome(reader.ReadOutcome(), TestOutcome());
    const AllocationReader shown(index);
    const auto confirm = EvaluationRole::kConfirm;
    EXPECT_EQ(reader.ReadSteps(confirm, kDamagedCandidate, 0, kSamples),
              shown.ReadSteps(confirm, kDamagedCandidate, 0, kSamples));
    EXPECT_EQ(Bits(reader.ReadSolveTime(confirm, kDamagedCandidate, 0, kSamples)),
              Bits(shown.ReadSolveTime(confirm, kDamagedCandidate, 0, kSamples)));
    EXPECT_EQ(Bits(reader.ReadErrorBound(1, 0, kFirstSamples)), Bits(shown.ReadErrorBound(1, 0, kFirstSamples)));
    EXPECT_EQ(shown.ReadSteps(confirm, kDamagedCandidate, 40, 41)[0],
              DeterministicRecord(confirm, kDamagedCandidate, 40).steps);
  }
  EXPECT_TRUE(CheckAllocationResults(joined).intact());

  // Damage in a shard is the index's, named with its shard.
  FlipChunk(shards[1], "/samples/confirm/runout_mm", kDamagedCandidate, 40);
  check = CheckAllocationResults(index);
  const std::vector<Damaged> damaged = DamagedOf(check);
  ASSERT_EQ(damaged.size(), 1u);
  EXPECT_EQ(damaged[0].path, "/samples/confirm/runout_mm");
  EXPECT_EQ(damaged[0].candidate, kDamagedCandidate);
  EXPECT_EQ(damaged[0].samples, (SampleRange{32, 48}));
  EXPECT_THAT(damaged[0].problem, HasSubstr("allocation.h5.shard-1"));
  // A join refuses it, keeping the index and every shard for the resume it names.
  EXPECT_THAT(InputErrorOf([&] { JoinAllocationShards(index, index); }),
              AllOf(HasSubstr("cannot be joined"), HasSubstr("/samples/confirm/runout_mm"),
                    HasSubstr("candidate " + std::to_string(kDamagedCandidate) + ", samples 32 to 47"),
                    HasSubstr("allocation.h5.shard-1"), HasSubstr("--out " + index.string() + " --resume")));
  EXPECT_EQ(IndexedAllocationShards(index), (std::vector<fs::path>{shards[0], shards[1]}));

  // An index is continued through its shards, never itself; it never replaces a file that
  // keeps samples; a missing shard is an error, not fill.
  EXPECT_THAT(InputErrorOf([&] { AllocationStore::Resume(index, TestIdentity(), TestOptions()); }),
              HasSubstr("is an index of shards"));
  const fs::path plain = folder / "plain.h5";
  { AllocationStore store = AllocationStore::Create(plain, TestIdentity(), DesignPoints(), TestOptions()); }
  EXPECT_THAT(InputErrorOf([&] {
                WriteAllocationIndex(plain, TestIdentity(), DesignPoints(), TestOutcome(),
                                     {AllocationShard{folder / "x.h5.shard-0", {}}});
              }),
              HasSubstr("keeps samples of its own"));
  fs::rename(shards[0], folder / "aside.h5");
  for (const auto& open : std::vector<std::function<void()>>{[&] { AllocationReader reader(index); },
                                                             [&] { CheckAllocationResults(index); }}) {
    EXPECT_THAT(InputErrorOf(open), AllOf(HasSubstr("allocation.h5.shard-0"), HasSubstr("is missing")));
  }
}

}  // namespace
}  // namespace ringtol::jobs
