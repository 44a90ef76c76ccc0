#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <string>

#include "engine/units.h"
#include "jobs/campaign/campaign.h"
#include "jobs/inputs/input_error.h"
#include "jobs/studies/campaign_speed.h"

namespace ringtol::jobs {
namespace {

using ::testing::HasSubstr;

// The default campaign at 4 samples (one per replicate): the reference costs most, ~0.1 s a
// sample in Release, and runs twice.
constexpr std::int64_t kSamples = 4;

const Campaign& SmallCampaign() {
  static const Campaign campaign(RINGTOL_SOURCE_DIR "/examples/campaigns/default.toml", kSamples, std::nullopt);
  return campaign;
}

const CampaignSpeedResult& Study() {
  static const CampaignSpeedResult result = [] {
    const solvers::SolverSettings own = SmallCampaign().plan().solver;
    solvers::SolverSettings linear = own;
    linear.rung = solvers::Rung::kLinear;
    // Linear first: its records (and error bounds) are the ones the study keeps.
    std::vector<CampaignMode> modes = {{"linear first", linear}};
    for (CampaignMode& mode : DefaultCampaignModes(own)) modes.push_back(std::move(mode));
    modes.push_back({"as reference", FullResolutionReference(own)});
    CampaignSpeedOptions options;
    options.modes = modes;
    return RunCampaignSpeed(SmallCampaign().plan(), options, nullptr);
  }();
  return result;
}

const CampaignModeRow& Row(const std::string& name) {
  const auto& rows = Study().rows;
  const auto it = std::find_if(rows.begin(), rows.end(), [&](const CampaignModeRow& r) { return r.name == name; });
  if (it == rows.end()) throw std::logic_error("no mode " + name);
  return *it;
}

TEST(CampaignSpeed, AModeWithTheReferenceSettingsMatchesItSampleForSample) {
  // A sample is a pure function of (campaign, index): the same settings give the same bits.
  const CampaignModeRow& same = Row("as reference");
  EXPECT_EQ(same.status_mismatches, 0);
  EXPECT_EQ(same.compared, same.ok);
  EXPECT_EQ(same.max_error_d_trajectory, 0.0);
  EXPECT_EQ(same.max_error_runout, 0.0);
  EXPECT_EQ(same.max_error_swing, 0.0);
}

TEST(CampaignSpeed, EveryModeComputesEverySampleAndTheQuasistaticRowIsTheSpeedUnit) {
  EXPECT_EQ(Study().samples, kSamples);
  ASSERT_EQ(Study().first_mode_records.size(), static_cast<std::size_t>(kSamples));
  for (std::size_t i = 0; i < Study().first_mode_records.size(); ++i) {
    EXPECT_EQ(Study().first_mode_records[i].index, static_cast<std::int64_t>(i));
  }
  EXPECT_EQ(Row("quasistatic").speed_ratio, 1.0);
  for (const CampaignModeRow& row : Study().rows) {
    EXPECT_GT(row.samples_per_second, 0.0) << row.name;
    EXPECT_GT(row.median_solve_time, 0.0) << row.name;
  }
}

TEST(CampaignSpeed, TheLinearRungStaysWithinItsOwnBoundPlusBothSamplingBudgets) {
  // |D_lin - D_ref| <= the linear rung's second-order bound (each sample's own, at most the
  // largest) + the sampling error of its step rule at the campaign's budget (D within the
  // budget of the continuous path's) + the reference's own sampling error (the exact rule:
  // far below the budget, bounded by it).
  const double budget_um = SmallCampaign().plan().solver.simulation.path_tolerance * units::kMicrometresPerMetre;
  double largest_bound_um = 0.0;
  for (const SampleRecord& record : Study().first_mode_records) {
    largest_bound_um = std::max(largest_bound_um, record.d_trajectory_error * units::kMicrometresPerMillimetre);
  }
  const CampaignModeRow& row = Row("linear first");
  EXPECT_EQ(row.status_mismatches, 0);
  EXPECT_GT(row.compared, 0);
  EXPECT_LE(row.max_error_d_trajectory, largest_bound_um + 2.0 * budget_um);
}

TEST(CampaignSpeed, TableCsvAndChartNameEveryMode) {
  std::ostringstream table, csv, svg;
  PrintCampaignSpeed(table, Study());
  WriteCampaignSpeedCsv(csv, Study());
  WriteCampaignSpeedSvg(svg, Study());
  const std::string csv_text = csv.str();
  EXPECT_EQ(std::count(csv_text.begin(), csv_text.end(), '\n'), static_cast<long>(Study().rows.size()) + 2);
  for (const CampaignModeRow& row : Study().rows) {
    EXPECT_THAT(table.str(), HasSubstr(row.name));
    EXPECT_THAT(csv_text, HasSubstr(row.name + ","));
    EXPECT_THAT(svg.str(), HasSubstr(row.name + ": D_trajectory"));
  }
  EXPECT_THAT(svg.str(), HasSubstr("<svg"));
}

TEST(CampaignSpeed, TheCampaignsOwnModeRunsOnceUnderItsNameAndFirst) {
  // The default campaign runs auto with spectral angles: that mode leads, and no other
  // mode repeats it; a dynamic campaign is not among the listed modes and leads as
  // "campaign".
  std::vector<std::string> names;
  for (const CampaignMode& mode : DefaultCampaignModes(SmallCampaign().plan().solver)) names.push_back(mode.name);
  // Then, for what the life values cost, the campaign's own mode and the linear ones again
  // reading one revolution only; last the accuracy fast, with the life and without.
  EXPECT_THAT(names, ::testing::ElementsAre("auto, spectral", "linear", "quasistatic", "auto", "linear, refined",
                                            "quasistatic, refined", "auto, refined", "linear, spectral",
                                            "auto, spectral, one revolution", "linear, one revolution",
                                            "linear, refined, one revolution", "linear, spectral, one revolution",
                                            "auto, spectral, fast", "auto, spectral, fast, one revolution"));
  for (const CampaignMode& mode : DefaultCampaignModes(SmallCampaign().plan().solver)) {
    EXPECT_EQ(mode.solver.simulation.life, !mode.name.ends_with("one revolution")) << mode.name;
    EXPECT_EQ(mode.solver.simulation.accuracy == solvers::Accuracy::kFast, mode.name.find(", fast") != std::string::npos)
        << mode.name;
  }
  // A campaign at accuracy fast leads under that name, once, and every other mode is full.
  solvers::SolverSettings fast = SmallCampaign().plan().solver;
  fast.simulation.accuracy = solvers::Accuracy::kFast;
  names.clear();
  for (const CampaignMode& mode : DefaultCampaignModes(fast)) {
    names.push_back(mode.name);
    EXPECT_EQ(mode.solver.simulation.accuracy == solvers::Accuracy::kFast, mode.name.find(", fast") != std::string::npos)
        << mode.name;
  }
  EXPECT_EQ(names.front(), "auto, spectral, fast");
  EXPECT_EQ(std::count(names.begin(), names.end(), "auto, spectral, fast, one revolution"), 1);
  EXPECT_EQ(std::count(names.begin(), names.end(), "auto, spectral"), 1);
  EXPECT_EQ(names.size(), 13u);
  solvers::SolverSettings dynamic = SmallCampaign().plan().solver;
  dynamic.rung = solvers::Rung::kDynamic;
  const std::vector<CampaignMode> modes = DefaultCampaignModes(dynamic);
  ASSERT_EQ(modes.size(), 15u);
  EXPECT_EQ(modes.front().name, "campaign");
  EXPECT_EQ(modes.front().solver.rung, solvers::Rung::kDynamic);
}

TEST(CampaignSpeed, NegativeThreadsAreRefusedBeforeAnySample) {
  CampaignSpeedOptions options;
  options.threads = -1;
  EXPECT_THROW(RunCampaignSpeed(SmallCampaign().plan(), options, nullptr), InputError);
}

}  // namespace
}  // namespace ringtol::jobs
