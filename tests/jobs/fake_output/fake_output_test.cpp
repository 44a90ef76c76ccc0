// A fake output proves that adding an output is a row of the outputs table (kOutputs,
// jobs/campaign/sample_record.h), its value in SampleEvaluator::Evaluate and its
// documentation: this executable's libraries are the campaign, allocation, store and
// report compiled with RINGTOL_TEST_OUTPUT (tests/CMakeLists.txt), under which the table
// ends in test_output_mm, a revolution output in mm worth twice D_trajectory. Nothing else
// names it, yet the results file stores it, the reader reads it, a [spec] limit on it is
// judged, the report labels it and an allocation may constrain it without paying for the
// life.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <hdf5.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "jobs/allocation/allocation.h"
#include "jobs/campaign/campaign.h"
#include "jobs/report/allocation_summary.h"
#include "jobs/report/campaign_report.h"
#include "jobs/report/campaign_summary.h"
#include "jobs/report/html_parts.h"
#include "jobs/report/report_html.h"
#include "jobs/store/campaign_store.h"
#include "tests/support/small_allocation.h"
#include "tests/support/small_campaign.h"
#include "tests/support/text_files.h"

#ifndef RINGTOL_TEST_OUTPUT
#error "the fake output's test is compiled with RINGTOL_TEST_OUTPUT (tests/CMakeLists.txt)"
#endif

namespace ringtol::jobs {
namespace {

using ::testing::HasSubstr;

constexpr std::size_t kFake = kOutputCount - 1;
constexpr std::size_t kDTrajectory = OutputIndex("d_trajectory_mm");
static_assert(std::string_view(kOutputs[kFake].name) == "test_output_mm");
// A new output's first schema is the current one (docs/architecture.md, "An output").
static_assert(kOutputs[kFake].first_schema == kCampaignSchemaVersion,
              "the fake output's row in jobs/campaign/sample_record.h names the current schema");

// The limit on the fake output: near its median on the small campaign (D_trajectory's
// spec there is 0.25 mm, so twice it some 0.5 mm), so that samples fall on both sides.
constexpr double kFakeLimitMm = 0.45;
constexpr std::int64_t kSamples = 24;

// /outputs/<name> as HDF5 holds it, read without the store.
std::vector<double> Dataset(const std::filesystem::path& path, const std::string& name) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) return {};
  std::vector<double> values;
  if (H5Lexists(file, name.c_str(), H5P_DEFAULT) > 0) {
    const hid_t dataset = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
    const hid_t space = H5Dget_space(dataset);
    values.resize(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
    if (H5Dread(dataset, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()) < 0) values.clear();
    H5Sclose(space);
    H5Dclose(dataset);
  }
  H5Fclose(file);
  return values;
}

class FakeOutput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ringtol::testing::FreshTestFolder("fake_output_test");
    std::filesystem::copy_file(std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/paper/scene.toml",
                               dir_ / "scene.toml");
    ringtol::testing::WriteText(dir_ / "campaign.toml", ringtol::testing::SmallCampaign("scene.toml", 3, kSamples) +
                                                            "test_output_mm = " + std::to_string(kFakeLimitMm) + "\n");
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // Runs the campaign in process into results.h5, keeping every record.
  std::filesystem::path Run() {
    const Campaign campaign(dir_ / "campaign.toml", std::nullopt, std::nullopt);
    SampleEvaluator evaluator(campaign);
    const std::filesystem::path results = dir_ / "results.h5";
    CampaignStore store = CampaignStore::Create(results, campaign.identity(), campaign.samples());
    for (std::int64_t i = 0; i < campaign.samples(); ++i) {
      records_.push_back(evaluator.Evaluate(i));
      store.Add(SampleRecord(records_.back()));
    }
    store.Commit();
    return results;
  }

  std::filesystem::path dir_;
  std::vector<SampleRecord> records_;
};

TEST_F(FakeOutput, ItsRowAloneMakesTheStoreTheReaderTheSpecTheSummaryAndTheReportCarryIt) {
  const std::filesystem::path results = Run();
  std::vector<double> expected;  // the records' fake values, NaN where a sample failed
  std::int64_t ok = 0, within = 0;
  for (const SampleRecord& record : records_) {
    expected.push_back(record.outputs[kFake]);
    if (record.status != SampleStatus::kOk) continue;
    ++ok;
    // Twice a double is exact: the campaign filled the row with the value it names.
    EXPECT_EQ(record.outputs[kFake], 2.0 * record.outputs[kDTrajectory]) << "sample " << record.index;
    within += record.outputs[kFake] <= kFakeLimitMm ? 1 : 0;
  }
  ASSERT_GT(ok, kSamples / 2);
  ASSERT_GT(within, 0);
  ASSERT_LT(within, ok) << "the limit should split the samples";

  const std::vector<double> stored = Dataset(results, "/outputs/test_output_mm");
  ASSERT_EQ(stored.size(), expected.size()) << "no /outputs/test_output_mm of every sample";
  const CampaignReader reader(results);
  ASSERT_TRUE(reader.HasOutput("test_output_mm"));
  const std::vector<double> read = reader.ReadOutput("test_output_mm", 0, kSamples);
  for (std::size_t i = 0; i < expected.size(); ++i) {
    if (std::isnan(expected[i])) continue;
    EXPECT_EQ(stored[i], expected[i]) << "sample " << i;
    EXPECT_EQ(read[i], expected[i]) << "sample " << i;
  }

  // The campaign file's [spec] took the limit, and the summary judges it.
  ASSERT_EQ(reader.identity().spec.size(), 2u);
  EXPECT_EQ(reader.identity().spec[1].output, "test_output_mm");
  const CampaignSummary summary = Summarise(reader, {});
  // Every output but the dynamic rung's own two revolutions, which the quasistatic rung does not show.
  ASSERT_EQ(summary.outputs.size(), kOutputCount - 2);
  const OutputSummary& fake = summary.outputs.back();
  EXPECT_EQ(fake.name, "test_output_mm");
  EXPECT_EQ(fake.count, ok);
  EXPECT_EQ(fake.upper_spec_limit, kFakeLimitMm);
  ASSERT_EQ(summary.in_spec_by_limit.size(), 2u);
  EXPECT_EQ(summary.in_spec_by_limit[1].output, "test_output_mm");
  EXPECT_EQ(summary.in_spec_by_limit[1].within.successes, within);
  EXPECT_EQ(summary.in_spec_by_limit[1].within.trials, kSamples);
  EXPECT_TRUE(SummaryJson(summary)["outputs"].contains("test_output_mm"));

  // The report labels it from its row, with its unit.
  EXPECT_EQ(html::Label("test_output_mm"), "test output [mm]");
  ReportOptions options;
  options.bootstrap_resamples = 0;
  options.replay = false;
  const std::string page = ReportHtml(BuildReport(results, options));
  EXPECT_THAT(page, HasSubstr("Distribution of test output [mm]"));
}

TEST_F(FakeOutput, AnAllocationMayConstrainItWithTheLimitOfItsUnitAndLeavesTheLifeOut) {
  const std::string text = ringtol::testing::ReplaceOnce(ringtol::testing::SmallAllocation(),
                                                         "output = \"d_trajectory_mm\"", "output = \"test_output_mm\"");
  const std::filesystem::path file = dir_ / "allocation.toml";
  ringtol::testing::WriteText(file, text);
  const Allocation allocation(file);
  ASSERT_EQ(allocation.stored_outputs(), std::vector<std::string>{"test_output_mm"});
  EXPECT_EQ(ConstraintText(allocation.identity().constraints.at(0)), "test_output_mm: 90 % quantile <= 0.1 mm");
  EXPECT_FALSE(allocation.CandidateCampaign(0, EvaluationRole::kConfirm).simulation().life)
      << "a revolution output is no reason to compute the life";
}

}  // namespace
}  // namespace ringtol::jobs
