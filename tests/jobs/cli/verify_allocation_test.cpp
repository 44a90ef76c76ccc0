// RunVerify on an allocation's results file: it reads the file as an allocation (not as a
// campaign it is not), says intact for a fresh file and names a damaged chunk's dataset,
// candidate and samples, in the table and in the JSON.
#include <array>
#include <bit>
#include <cstdint>
#include <filesystem>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "jobs/cli/verify_command.h"
#include "jobs/store/allocation_store.h"
#include "tests/support/damage.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr std::int64_t kSamples = 32;
constexpr std::int64_t kChunkSamples = 16;
constexpr std::int64_t kCandidate = 1;
constexpr std::size_t kFlippedBytes = 8;
constexpr std::int64_t kDamagedSample = 21;

double RunoutOf(std::int64_t sample) { return 1e-3 * static_cast<double>(sample); }

AllocationIdentity TwoByTwo() {
  AllocationIdentity identity;
  identity.design = "sobol";
  identity.samples = kSamples;
  identity.first_samples = kChunkSamples;
  identity.inputs = {{"ring.order2.amplitude_um", sampling::ErrorSource::kRingShape, -1, 2, "ring.order2", "ring"}};
  identity.components = {"ring", "springs"};
  identity.options = {{{"P3", "turned", 40.0, 1.0}, {"P2", "ground", 20.0, 2.0}},
                      {{"S20", "", 20.0, 0.5}, {"S5", "", 5.0, 1.5}}};
  identity.constraints = {{"runout_mm", analysis::ConstraintKind::kQuantile, 0.99, 0.02}};
  return identity;
}

// A file whose candidate kCandidate has every confirming sample done.
fs::path WrittenFile(const fs::path& folder) {
  const fs::path path = folder / "allocation.h5";
  AllocationStore store =
      AllocationStore::Create(path, TwoByTwo(), std::vector<double>(kSamples, 0.5), {.chunk_samples = kChunkSamples});
  for (std::int64_t i = 0; i < kSamples; ++i) {
    SampleRecord record;
    record.index = i;
    record.status = SampleStatus::kOk;
    record.outputs.fill(RunoutOf(i));
    store.Add(EvaluationRole::kConfirm, kCandidate, record);
  }
  AllocationOutcome outcome;
  outcome.candidates.resize(4);
  store.Commit(outcome);
  return path;
}

TEST(VerifyAllocation, CallsAFreshFileIntactWithWhatIsDone) {
  const fs::path path = WrittenFile(ringtol::testing::FreshTestFolder("verify_allocation_test"));
  std::ostringstream out;
  EXPECT_EQ(RunVerify({path, false}, out), kVerifyIntact);
  EXPECT_THAT(out.str(), AllOf(HasSubstr("allocation of 4 candidates x 32 samples"),
                               HasSubstr("0 screened, 32 confirmed"), HasSubstr("Verdict: intact")));
}

TEST(VerifyAllocation, NamesTheDamagedChunkByDatasetCandidateAndSamples) {
  const fs::path path = WrittenFile(ringtol::testing::FreshTestFolder("verify_allocation_test"));
  // Sample 21's runout is stored nowhere else (the constraint's limit is 0.02): its bytes
  // lie in the chunk of samples 16 to 31.
  const auto value = std::bit_cast<std::array<char, sizeof(double)>>(RunoutOf(kDamagedSample));
  const std::string bytes = ringtol::testing::ReadText(path);
  const std::size_t at = bytes.find(std::string_view(value.data(), value.size()));
  ASSERT_NE(at, std::string::npos);
  testing::FlipBytes(path, at, kFlippedBytes);

  std::ostringstream table;
  EXPECT_EQ(RunVerify({path, false}, table), kVerifyDamaged);
  EXPECT_THAT(table.str(), AllOf(HasSubstr("/samples/confirm/runout_mm  DAMAGED at candidate 1, samples 16 to 31"),
                                 HasSubstr("Verdict: damaged")));
  std::ostringstream json;
  EXPECT_EQ(RunVerify({path, true}, json), kVerifyDamaged);
  const nlohmann::json result = nlohmann::json::parse(json.str());
  EXPECT_EQ(result["kind"], "allocation");
  ASSERT_EQ(result["damaged"].size(), 1u);
  EXPECT_EQ(result["damaged"][0]["candidate"], kCandidate);
  EXPECT_EQ(result["damaged"][0]["samples"], nlohmann::json::array({16, 31}));
}

}  // namespace
}  // namespace ringtol::jobs
