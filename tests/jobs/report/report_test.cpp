// The campaign report in process: what it counts, excludes and replays, from results
// files written here with known failures (the executable, the physics and the browser are
// tested in report_cli_test.cpp).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>

#include "jobs/campaign/campaign.h"
#include "jobs/report/campaign_report.h"
#include "jobs/inputs/input_error.h"
#include "jobs/cli/report_command.h"
#include "jobs/report/report_html.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

using ::testing::HasSubstr;

// A copy of the paper's scene beside the campaign file, so the test can take both away.
const std::string kCampaign = R"(scene = "scene.toml"
seed = 3
[design]
kind = "monte_carlo"
samples = 40
[tolerances.ring]
circularity_mm = 0.2
max_order = 6
[tolerances.roller_positions]
zone_diameter_mm = 0.05
[solver]
name = "quasistatic"
[spec]
d_trajectory_mm = 0.25
)";

class ReportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ringtol::testing::FreshTestFolder("report_test");
    std::filesystem::copy_file(std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/paper/scene.toml",
                               dir_ / "scene.toml");
    std::ofstream(dir_ / "campaign.toml") << kCampaign;
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // Runs the campaign in process; samples whose index is a multiple of 7 throw.
  std::filesystem::path RunWithFailures() {
    const Campaign campaign(dir_ / "campaign.toml", std::nullopt, std::nullopt);
    EvaluatorFaults faults;
    faults.before_simulate = [](std::int64_t index) {
      if (index % 7 == 0) throw std::runtime_error("injected fault in sample " + std::to_string(index));
    };
    SampleEvaluator evaluator(campaign, faults);
    const std::filesystem::path results = dir_ / "results.h5";
    CampaignStore store = CampaignStore::Create(results, campaign.identity(), campaign.samples());
    for (std::int64_t i = 0; i < campaign.samples(); ++i) {
      SampleRecord record = evaluator.Evaluate(i);
      if (record.status == SampleStatus::kOk) ok_d_.push_back(record.outputs[0]);
      store.Add(std::move(record));
    }
    store.Commit();
    return results;
  }

  std::filesystem::path dir_;
  std::vector<double> ok_d_;  // D_trajectory of the ok samples, in index order
};

TEST_F(ReportTest, FailedSamplesAreCountedListedAndExcludedFromEveryStatistic) {
  const std::filesystem::path results = RunWithFailures();
  const std::int64_t failed = 6;  // 0, 7, ..., 35 of 40
  ASSERT_EQ(static_cast<std::int64_t>(ok_d_.size()), 40 - failed);

  ReportOptions options;
  options.bootstrap_resamples = 50;
  const CampaignReport report = BuildReport(results, options);
  EXPECT_EQ(report.used, 40);
  EXPECT_EQ(report.done, 40);
  EXPECT_EQ(report.ok, 40 - failed);
  EXPECT_EQ(report.failures.at("exception"), failed);
  ASSERT_EQ(static_cast<std::int64_t>(report.failed.size()), failed);
  EXPECT_EQ(report.failed[1].index, 7);
  EXPECT_THAT(report.failed[1].message, HasSubstr("injected fault in sample 7"));

  const OutputReport& d = report.outputs.front();
  ASSERT_EQ(d.name, "d_trajectory_mm");
  ASSERT_TRUE(d.distribution.has_value());
  EXPECT_EQ(d.count, 40 - failed);
  const double mean = std::accumulate(ok_d_.begin(), ok_d_.end(), 0.0) / static_cast<double>(ok_d_.size());
  EXPECT_NEAR(d.distribution->mean, mean, 1e-12 * mean);
  EXPECT_EQ(d.distribution->max, *std::max_element(ok_d_.begin(), ok_d_.end()));
  const auto good = std::count_if(ok_d_.begin(), ok_d_.end(), [](double v) { return v <= 0.25; });
  ASSERT_TRUE(d.distribution->within_spec.has_value());
  EXPECT_EQ(d.distribution->within_spec->successes, good);
  EXPECT_EQ(d.distribution->within_spec->trials, 40 - failed);
  ASSERT_TRUE(d.within_spec_counting_failures.has_value());
  EXPECT_EQ(d.within_spec_counting_failures->successes, good);
  EXPECT_EQ(d.within_spec_counting_failures->trials, 40);
  EXPECT_EQ(d.convergence.back().samples, 40 - failed);

  // The screening (a Monte Carlo design) sees only ok samples.
  ASSERT_FALSE(report.sensitivities.empty());
  EXPECT_EQ(report.sensitivities.front().method, "screening");
  EXPECT_EQ(report.sensitivities.front().rows, 40 - failed);

  const std::string html = ReportHtml(report);
  EXPECT_THAT(html, HasSubstr("failed: exception"));
  EXPECT_THAT(html, HasSubstr("injected fault in sample 14"));
  EXPECT_THAT(html, HasSubstr("excluded from every statistic"));
  const nlohmann::json json = ReportJson(report);
  EXPECT_EQ(json["samples"]["failed"], failed);
  EXPECT_EQ(json["samples"]["failures"]["exception"], failed);
  EXPECT_EQ(json["failed_samples"].size(), static_cast<std::size_t>(failed));
  EXPECT_EQ(json["outputs"]["d_trajectory_mm"]["count"], 40 - failed);
  EXPECT_EQ(json["outputs"]["d_trajectory_mm"]["yield_counting_failures"]["trials"], 40);
}

TEST_F(ReportTest, MedianAndWorstSamplesReplayToTheirStoredOutputsAfterTheFilesAreGone) {
  const std::filesystem::path results = RunWithFailures();
  // The report rebuilds the campaign from the text the results file keeps.
  std::filesystem::remove(dir_ / "campaign.toml");
  std::filesystem::remove(dir_ / "scene.toml");
  ReportOptions options;
  options.bootstrap_resamples = 0;
  const CampaignReport report = BuildReport(results, options);
  ASSERT_FALSE(report.replay_problem.has_value()) << *report.replay_problem;
  ASSERT_EQ(report.trajectories.size(), 2u);
  std::vector<double> sorted = ok_d_;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(report.trajectories[0].label, "median");
  EXPECT_EQ(report.trajectories[0].stored_d_trajectory_mm, sorted[(sorted.size() - 1) / 2]);
  EXPECT_EQ(report.trajectories[1].label, "worst");
  EXPECT_EQ(report.trajectories[1].stored_d_trajectory_mm, sorted.back());
  for (const ReplayedTrajectory& t : report.trajectories) {
    // Same scene, same solver, same steps: the same bits.
    EXPECT_EQ(t.d_trajectory_mm, t.stored_d_trajectory_mm) << t.label;
    EXPECT_EQ(t.status, "ok");
    ASSERT_FALSE(t.x_um.empty());
    // Every point of the path lies in its minimum enclosing circle, whose diameter is D.
    for (std::size_t k = 0; k < t.x_um.size(); ++k) {
      EXPECT_LE(std::hypot(t.x_um[k] - t.circle_x_um, t.y_um[k] - t.circle_y_um), t.circle_radius_um * (1 + 1e-9));
    }
    EXPECT_NEAR(2 * t.circle_radius_um, t.d_trajectory_mm * 1e3, 1e-9 * t.circle_radius_um);
  }
}

TEST_F(ReportTest, AFileWithoutAnOkSampleGivesAReportThatSaysSo) {
  const Campaign campaign(dir_ / "campaign.toml", std::nullopt, std::nullopt);
  EvaluatorFaults faults;
  faults.before_simulate = [](std::int64_t) { throw std::runtime_error("every sample fails"); };
  SampleEvaluator evaluator(campaign, faults);
  const std::filesystem::path results = dir_ / "failed.h5";
  {
    CampaignStore store = CampaignStore::Create(results, campaign.identity(), campaign.samples());
    for (std::int64_t i = 0; i < 10; ++i) store.Add(evaluator.Evaluate(i));  // the other 30 stay pending
  }
  const CampaignReport report = BuildReport(results);
  EXPECT_EQ(report.ok, 0);
  EXPECT_EQ(report.done, 10);
  EXPECT_EQ(report.pending, 30);
  EXPECT_EQ(report.failures.at("exception"), 10);
  EXPECT_FALSE(report.outputs.front().distribution.has_value());
  EXPECT_TRUE(report.sensitivities.empty());
  EXPECT_TRUE(report.trajectories.empty());
  const std::string html = ReportHtml(report);
  EXPECT_THAT(html, HasSubstr("No sample finished ok"));
  EXPECT_THAT(html, HasSubstr("every sample fails"));
  EXPECT_EQ(ReportJson(report)["samples"]["pending"], 30);
}

TEST_F(ReportTest, CommandRefusesBadPathsAndOptionsBeforeAnyWork) {
  const std::filesystem::path results = RunWithFailures();
  std::ostringstream out;
  const auto error_of = [&](ReportCommand command) {
    try {
      RunReport(command, out);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  ReportCommand command;
  command.results = results;
  command.out = dir_ / "missing" / "report.html";
  EXPECT_THAT(error_of(command), HasSubstr("--out " + command.out.string() + ": the folder"));
  command.out = results;
  EXPECT_THAT(error_of(command), HasSubstr("is the results file itself"));
  command.out = dir_ / "report.html";
  command.estimator = "sobol-magic";
  EXPECT_THAT(error_of(command), HasSubstr("--estimator sobol-magic: unknown; allowed: saltelli2010-jansen"));
  command.estimator = "martinez";
  command.json = dir_ / "nowhere" / "summary.json";
  EXPECT_THAT(error_of(command), HasSubstr("--json"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "report.html"));  // refused before any work

  std::ofstream(dir_ / "foreign.h5") << "not HDF5 at all";
  command.results = dir_ / "foreign.h5";
  command.json.reset();
  EXPECT_THAT(error_of(command), HasSubstr("foreign.h5"));
  EXPECT_FALSE(std::filesystem::exists(dir_ / "report.html"));

  command.results = results;
  command.options.bootstrap_resamples = 20;
  EXPECT_EQ(RunReport(command, out), 0);
  EXPECT_THAT(out.str(), HasSubstr("Report: " + command.out.string()));
  EXPECT_TRUE(std::filesystem::exists(command.out));
  EXPECT_FALSE(std::filesystem::exists(command.out.string() + ".partial"));
}

}  // namespace
}  // namespace ringtol::jobs
