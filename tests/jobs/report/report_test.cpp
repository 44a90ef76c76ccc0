// The campaign report in process: what it counts, excludes and replays, from results
// files written here with known failures (the executable, the physics and the browser are
// tested in report_cli_test.cpp).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "engine/units.h"
#include "jobs/campaign/campaign.h"
#include "jobs/report/campaign_report.h"
#include "jobs/report/campaign_summary.h"
#include "jobs/inputs/input_error.h"
#include "jobs/cli/report_command.h"
#include "jobs/report/report_html.h"
#include "jobs/report/report_text.h"
#include "tests/support/older_results.h"
#include "tests/support/small_campaign.h"
#include "tests/support/text_files.h"

namespace ringtol::jobs {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::Not;

// A copy of the paper's scene beside the campaign file, so the test can take both away.
const std::string kCampaign = ringtol::testing::SmallCampaign("scene.toml", 3, 40);

class ReportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ringtol::testing::FreshTestFolder("report_test");
    std::filesystem::copy_file(std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/paper/scene.toml",
                               dir_ / "scene.toml");
    std::ofstream(dir_ / "campaign.toml") << kCampaign;
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // Runs the campaign in process; samples whose index is a multiple of 7 throw. Without
  // `store_calibrations` the file is as one written before they were stored.
  std::filesystem::path RunWithFailures(const std::string& name = "results.h5", bool store_calibrations = true) {
    ok_d_.clear();
    ok_records_.clear();
    const Campaign campaign(dir_ / "campaign.toml", std::nullopt, std::nullopt);
    EvaluatorFaults faults;
    faults.before_simulate = [](std::int64_t index) {
      if (index % 7 == 0) throw std::runtime_error("injected fault in sample " + std::to_string(index));
    };
    SampleEvaluator evaluator(campaign, faults);
    const std::filesystem::path results = dir_ / name;
    CampaignIdentity identity = campaign.identity();
    if (!store_calibrations) identity.calibrations.clear();
    CampaignStore store = CampaignStore::Create(results, identity, campaign.samples());
    for (std::int64_t i = 0; i < campaign.samples(); ++i) {
      SampleRecord record = evaluator.Evaluate(i);
      if (record.status == SampleStatus::kOk) {
        ok_d_.push_back(record.outputs[Column("d_trajectory_mm")]);
        ok_records_.push_back(record);
      }
      store.Add(std::move(record));
    }
    store.Commit();
    return results;
  }

  // The report without replays or bootstrap intervals: what the answer and the JSON say.
  static CampaignReport QuickReport(const std::filesystem::path& results) {
    ReportOptions options;
    options.bootstrap_resamples = 0;
    options.replay = false;
    return BuildReport(results, options);
  }

  // The page's answer block.
  static std::string AnswerOf(const std::string& html) {
    const std::size_t open = html.find("id=\"answer\"");
    return open == std::string::npos ? "" : html.substr(open, html.find("</div>", open) - open);
  }

  static std::size_t Column(std::string_view name) {
    return static_cast<std::size_t>(
        std::find_if(kOutputNames.begin(), kOutputNames.end(), [&](const char* output) { return name == output; }) -
        kOutputNames.begin());
  }

  std::filesystem::path dir_;
  std::vector<double> ok_d_;                 // D_trajectory of the ok samples, in index order
  std::vector<SampleRecord> ok_records_;     // the ok samples as stored, in index order
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

TEST_F(ReportTest, OrbitsOfTheWorstAndTheMedianSampleReplayTheirStoredOutputsAfterTheFilesAreGone) {
  const std::filesystem::path results = RunWithFailures();
  // The report rebuilds the campaign from the text the results file keeps.
  std::filesystem::remove(dir_ / "campaign.toml");
  std::filesystem::remove(dir_ / "scene.toml");
  ReportOptions options;
  options.bootstrap_resamples = 0;
  const CampaignReport report = BuildReport(results, options);
  ASSERT_FALSE(report.replay_problem.has_value()) << *report.replay_problem;
  ASSERT_EQ(report.trajectories.size(), 2u);

  // The worst is the sample with the largest stored D_trajectory, the median the one at the
  // lower middle rank (of an even count both middle ones are as near the median).
  const auto worst = std::max_element(ok_records_.begin(), ok_records_.end(), [&](const auto& a, const auto& b) {
    return a.outputs[Column("d_trajectory_mm")] < b.outputs[Column("d_trajectory_mm")];
  });
  std::vector<double> sorted = ok_d_;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_EQ(report.trajectories[0].label, "worst");
  EXPECT_EQ(report.trajectories[0].index, worst->index);
  EXPECT_EQ(report.trajectories[0].stored_d_trajectory_mm, sorted.back());
  EXPECT_EQ(report.trajectories[1].label, "median");
  EXPECT_EQ(report.trajectories[1].stored_d_trajectory_mm, sorted[(sorted.size() - 1) / 2]);

  constexpr double kUmPerMm = 1e3;
  // The campaign's own solver settings: 1 % of the 1 um sampling budget per angle.
  const double tolerance_mm = ReplayTolerance(CampaignSolverDefaults()) * units::kMillimetresPerMetre;
  const double tolerance_um = tolerance_mm * kUmPerMm;
  // The circle's radius is the largest distance from its centre to a point of the path
  // (engine/enclosing_circle.h); converted to µm, coordinates below 1e3 µm carry round-off
  // of ~1e-13 µm: 1e-9 µm leaves four orders of room.
  constexpr double kRoundOffUm = 1e-9;
  // The last angle, 2 pi steps / steps converted to degrees: a few ulp of 360.
  constexpr double kRoundOffDeg = 1e-9;
  for (const ReplayedTrajectory& t : report.trajectories) {
    const SampleRecord& stored =
        *std::find_if(ok_records_.begin(), ok_records_.end(), [&](const SampleRecord& r) { return r.index == t.index; });
    EXPECT_EQ(t.status, "ok") << t.label;
    EXPECT_TRUE(t.reproduced) << t.label;
    EXPECT_EQ(t.tolerance_mm, tolerance_mm);
    EXPECT_NEAR(t.d_trajectory_mm, t.stored_d_trajectory_mm, tolerance_mm) << t.label;
    EXPECT_EQ(t.steps, stored.steps);
    // The drawn circle is the stored D_trajectory's, and every drawn point lies in it.
    EXPECT_NEAR(2 * t.circle_radius_um, t.stored_d_trajectory_mm * kUmPerMm, tolerance_um) << t.label;
    ASSERT_FALSE(t.x_um.empty());
    EXPECT_LE(t.x_um.size(), kDrawnPoints);
    double farthest = 0.0;
    for (std::size_t k = 0; k < t.x_um.size(); ++k) {
      farthest = std::max(farthest, std::hypot(t.x_um[k] - t.circle_x_um, t.y_um[k] - t.circle_y_um));
    }
    EXPECT_LE(farthest, t.circle_radius_um + kRoundOffUm) << t.label;
    // The path still touches its circle where the full path does (DecimateCurve keeps them).
    EXPECT_NEAR(farthest, t.circle_radius_um, kRoundOffUm) << t.label;
    // The static equilibrium lies Dist_init from the circle's centre.
    EXPECT_NEAR(std::hypot(t.static_x_um - t.circle_x_um, t.static_y_um - t.circle_y_um),
                stored.outputs[Column("dist_init_mm")] * kUmPerMm, tolerance_um)
        << t.label;
    // The sensor: one revolution, its minimum at 0 and its maximum at TIR, the stored
    // total indicator reading, runout_mm.
    ASSERT_FALSE(t.sensor_um.empty());
    EXPECT_EQ(t.angle_deg.front(), 0.0);
    EXPECT_NEAR(t.angle_deg.back(), 360.0, kRoundOffDeg);
    EXPECT_EQ(*std::min_element(t.sensor_um.begin(), t.sensor_um.end()), 0.0);
    EXPECT_EQ(*std::max_element(t.sensor_um.begin(), t.sensor_um.end()), t.tir_um);
    EXPECT_NEAR(t.tir_um, stored.outputs[Column("runout_mm")] * kUmPerMm, tolerance_um)
        << t.label;
  }

  const std::string html = ReportHtml(report);
  EXPECT_THAT(html, HasSubstr("Orbits of the worst and the median assembly"));
  EXPECT_THAT(html, HasSubstr(fmt::format("Worst D_trajectory: sample {},", worst->index)));
  EXPECT_THAT(html, HasSubstr(fmt::format("Median D_trajectory: sample {},", report.trajectories[1].index)));
  EXPECT_THAT(html, HasSubstr("TIR = max − min"));
  const nlohmann::json json = ReportJson(report);
  EXPECT_EQ(json["trajectories"][0]["index"], worst->index);
  EXPECT_EQ(json["trajectories"][0]["reproduced"], true);
}

TEST_F(ReportTest, AFileWrittenBeforeCalibrationsWereStoredReplaysTheSameOrbits) {
  const std::filesystem::path older = RunWithFailures("older.h5", false);
  const std::filesystem::path newer = RunWithFailures("newer.h5", true);
  ASSERT_TRUE(CampaignReader(older).identity().calibrations.empty());
  ASSERT_FALSE(CampaignReader(newer).identity().calibrations.empty());
  ReportOptions options;
  options.bootstrap_resamples = 0;
  const CampaignReport calibrated = BuildReport(older, options);
  const CampaignReport stored = BuildReport(newer, options);
  ASSERT_EQ(calibrated.trajectories.size(), 2u);
  ASSERT_EQ(stored.trajectories.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_TRUE(calibrated.trajectories[k].reproduced) << k;
    EXPECT_TRUE(stored.trajectories[k].reproduced) << k;
    EXPECT_EQ(calibrated.trajectories[k].index, stored.trajectories[k].index);
    // The same draws and the same solver on one machine: the same bits.
    EXPECT_EQ(calibrated.trajectories[k].d_trajectory_mm, stored.trajectories[k].d_trajectory_mm) << k;
    EXPECT_EQ(calibrated.trajectories[k].x_um, stored.trajectories[k].x_um) << k;
  }
}

TEST_F(ReportTest, TheAnswerStatesTheShareOfSamplesEachRungSettled) {
  const std::filesystem::path results = RunWithFailures();
  ReportOptions options;
  options.bootstrap_resamples = 0;
  options.replay = false;
  CampaignReport report = BuildReport(results, options);
  // The campaign runs the quasistatic rung; the 6 samples that threw ran none.
  EXPECT_THAT(report.settled_by, ElementsAre(0, 34, 0));
  EXPECT_THAT(ReportHtml(report),
              HasSubstr("<p>Rungs: linear 0.0 %, quasistatic 100.0 %, dynamic 0.0 % (of the 34 samples a rung ran "
                        "on).</p>"));
  const nlohmann::json json = ReportJson(report);
  EXPECT_EQ(json["rungs"]["quasistatic"]["samples"], 34);
  EXPECT_EQ(json["rungs"]["quasistatic"]["share"], 1.0);
  report.settled_by.clear();  // a file of schema < 3 records no rung
  EXPECT_THAT(ReportHtml(report), Not(HasSubstr("Rungs:")));
  EXPECT_FALSE(ReportJson(report).contains("rungs"));
}

// auto sends a sample to the dynamic rung for one reason; the summary gives it with the
// count and how many of those failed. Another solver's campaign states no reason.
TEST(CampaignSummaryRungs, AutosDynamicSamplesAreCountedWithTheirFailuresAndWhyTheyWentThere) {
  CampaignSummary summary;
  summary.settled_by = {10, 20, 5};
  summary.failed_by = {0, 1, 3};
  summary.auto_rung = true;
  std::ostringstream text;
  PrintSummary(text, summary);
  EXPECT_THAT(text.str(), HasSubstr("dynamic           5 samples, 3 of them failed: auto's bound on the ring's "
                                    "inertial force reached the least force its support rests on"));
  const nlohmann::json json = SummaryJson(summary);
  EXPECT_EQ(json["rungs"]["dynamic"]["failed"], 3);
  EXPECT_EQ(json["rungs"]["quasistatic"]["failed"], 1);
  EXPECT_THAT(json["rungs"]["dynamic"]["reason"].get<std::string>(), HasSubstr("inertial force"));
  summary.auto_rung = false;
  std::ostringstream chosen;
  PrintSummary(chosen, summary);
  EXPECT_THAT(chosen.str(), Not(HasSubstr("dynamic           ")));
  EXPECT_FALSE(SummaryJson(summary)["rungs"]["dynamic"].contains("reason"));
}

// A file of today's schema has the life columns. This campaign's rollers are round, so
// every revolution is the first: the life adds nothing to one revolution, and the replayed
// revolutions of the polar plot coincide (no band).
TEST_F(ReportTest, RoundRollersGiveALifeEqualToOneRevolutionAndNoBand) {
  const std::filesystem::path results = RunWithFailures();
  ReportOptions options;
  options.bootstrap_resamples = 0;
  options.error_motion_revolutions = 3;
  const CampaignReport report = BuildReport(results, options);
  ASSERT_EQ(report.life_gaps.size(), 2u);
  for (const LifeGap& gap : report.life_gaps) {
    EXPECT_NEAR(gap.life_q99, gap.one_q99, 1e-9) << gap.label;
    EXPECT_NEAR(gap.median_excess, 0.0, 1e-9) << gap.label;
  }
  ASSERT_TRUE(report.error_motion.has_value());
  EXPECT_EQ(report.error_motion->status, "ok") << report.error_motion->message;
  EXPECT_NEAR(report.error_motion->asynchronous_um, 0.0, 1e-6);
  EXPECT_NEAR(report.error_motion->total_um, report.error_motion->synchronous_um, 1e-6);
  EXPECT_NEAR(report.error_motion->total_um, report.error_motion->stored_total_mm * 1e3, 1e-3);
  EXPECT_THAT(ReportHtml(report), HasSubstr("ISO 230-7"));
}

// Files of schema 3 and before have no life columns: the report and the summary leave out
// the life's parts without an error, replays or not.
TEST_F(ReportTest, AFileWithoutTheLifeColumnsHasNoLifeParts) {
  const std::filesystem::path results = RunWithFailures();
  ringtol::testing::AsOlderSchema(results, 3);
  ReportOptions options;
  options.bootstrap_resamples = 0;
  const CampaignReport report = BuildReport(results, options);
  EXPECT_FALSE(report.error_motion.has_value());
  EXPECT_FALSE(report.error_motion_problem.has_value());
  EXPECT_TRUE(report.life_gaps.empty());
  EXPECT_EQ(report.trajectories.size(), 2u);  // the orbits are replayed as before
  const std::string html = ReportHtml(report);
  EXPECT_THAT(html, Not(HasSubstr("ISO 230-7")));
  EXPECT_THAT(html, Not(HasSubstr("Over the stage")));  // its apostrophe is escaped in the page
  const nlohmann::json json = ReportJson(report);
  EXPECT_FALSE(json.contains("error_motion"));
  EXPECT_FALSE(json.contains("life"));

  const CampaignSummary summary = Summarise(CampaignReader(results), {});
  EXPECT_TRUE(summary.life_gaps.empty());
  std::ostringstream text;
  PrintSummary(text, summary);
  EXPECT_THAT(text.str(), Not(HasSubstr("Over the stage's life")));
}

// The orbits shown are the worst and the median by what the spec constrains: with a limit
// on the runout alone, by the runout; with limits on both, by each in turn.
TEST_F(ReportTest, OrbitsAreTheWorstAndMedianByEachOutputTheSpecConstrains) {
  for (const bool both : {false, true}) {
    SCOPED_TRACE(both ? "D_trajectory and runout" : "runout alone");
    std::string text = kCampaign;
    const std::string spec = "d_trajectory_mm = 0.25\n";
    text.replace(text.find(spec), spec.size(), both ? spec + "runout_mm = 0.2\n" : "runout_mm = 0.2\n");
    std::ofstream(dir_ / "campaign.toml") << text;
    const std::filesystem::path results = RunWithFailures(both ? "both.h5" : "runout.h5");
    ReportOptions options;
    options.bootstrap_resamples = 0;
    const CampaignReport report = BuildReport(results, options);
    std::vector<std::string> by;
    for (const ReplayedTrajectory& t : report.trajectories) by.push_back(t.by + " " + t.label);
    const std::vector<std::string> expected =
        both ? std::vector<std::string>{"d_trajectory_mm worst", "d_trajectory_mm median", "runout_mm worst",
                                        "runout_mm median"}
             : std::vector<std::string>{"runout_mm worst", "runout_mm median"};
    EXPECT_EQ(by, expected);
    const auto largest_runout = std::max_element(ok_records_.begin(), ok_records_.end(), [&](const auto& a, const auto& b) {
      return a.outputs[Column("runout_mm")] < b.outputs[Column("runout_mm")];
    });
    const ReplayedTrajectory& worst = report.trajectories[both ? 2 : 0];
    EXPECT_EQ(worst.index, largest_runout->index);
    EXPECT_EQ(worst.stored_by, largest_runout->outputs[Column("runout_mm")]);
    EXPECT_TRUE(worst.reproduced);
    const std::string html = ReportHtml(report);
    EXPECT_THAT(html, HasSubstr(fmt::format("Worst runout (max - min): sample {},", worst.index)));
    EXPECT_THAT(html, HasSubstr("(what the spec constrains)"));
    EXPECT_EQ(ReportJson(report)["trajectories"][both ? 2 : 0]["by"], "runout_mm");
  }
}

// A yield as the page and the terminal write it: to the resolution its sample count gives,
// one decimal for the 34 or 40 samples here (1/34 is 2.9 points).
std::string YieldText(std::int64_t successes, std::int64_t trials) {
  return fmt::format("{:.1f} %", 100.0 * static_cast<double>(successes) / static_cast<double>(trials));
}

// Two limits: the answer and the terminal name both, each with its own yield and interval,
// then the yield within both at once. The limits are the medians of a first run, so each
// holds for about half the samples and both together for fewer.
TEST_F(ReportTest, EveryLimitIsNamedWithItsOwnYieldAndThenTheJointOne) {
  RunWithFailures("first.h5");
  std::vector<double> trajectory, runout;
  for (const SampleRecord& r : ok_records_) {
    trajectory.push_back(r.outputs[Column("d_trajectory_mm")]);
    runout.push_back(r.outputs[Column("runout_mm")]);
  }
  const auto median = [](std::vector<double> values) {
    std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2), values.end());
    return std::stod(fmt::format("{:.3g}", values[values.size() / 2]));
  };
  const double trajectory_limit = median(trajectory), runout_limit = median(runout);
  std::string text = kCampaign;
  const std::string spec = "d_trajectory_mm = 0.25\n";
  text.replace(text.find(spec), spec.size(),
               fmt::format("d_trajectory_mm = {}\nrunout_mm = {}\n", trajectory_limit, runout_limit));
  std::ofstream(dir_ / "campaign.toml") << text;
  const std::filesystem::path results = RunWithFailures("two_limits.h5");
  std::int64_t within_trajectory = 0, within_runout = 0, within_both = 0;
  for (const SampleRecord& r : ok_records_) {
    const bool t = r.outputs[Column("d_trajectory_mm")] <= trajectory_limit;
    const bool u = r.outputs[Column("runout_mm")] <= runout_limit;
    within_trajectory += t;
    within_runout += u;
    within_both += t && u;
  }
  const auto ok = static_cast<std::int64_t>(ok_records_.size());
  const std::int64_t done = 40;
  ASSERT_LT(within_both, within_trajectory);  // the joint yield is its own number
  ASSERT_GT(within_both, 0);

  const CampaignReport report = QuickReport(results);
  const std::string answer = AnswerOf(ReportHtml(report));
  EXPECT_THAT(answer, HasSubstr(fmt::format("D_trajectory [mm] &#8804; {:g}", trajectory_limit)));
  EXPECT_THAT(answer, HasSubstr(fmt::format("runout (max - min) [mm] &#8804; {:g}", runout_limit)));
  EXPECT_THAT(answer, HasSubstr(YieldText(within_trajectory, ok)));
  EXPECT_THAT(answer, HasSubstr(YieldText(within_runout, ok)));
  EXPECT_THAT(answer, HasSubstr("every limit at once"));
  EXPECT_THAT(answer, HasSubstr(YieldText(within_both, ok)));
  EXPECT_THAT(answer, HasSubstr(YieldText(within_both, done)));  // the failed samples counted as outside
  const nlohmann::json json = ReportJson(report);
  ASSERT_TRUE(json.contains("within_every_limit"));
  EXPECT_EQ(json["within_every_limit"]["successes"], within_both);
  EXPECT_EQ(json["within_every_limit"]["trials"], ok);
  EXPECT_EQ(json["within_every_limit_counting_failures"]["trials"], done);
  EXPECT_EQ(json["outputs"]["runout_mm"]["yield"]["successes"], within_runout);

  // The terminal: each limit over the done samples (failures count as outside), then both.
  const CampaignSummary summary = Summarise(CampaignReader(results), {});
  std::ostringstream terminal;
  PrintSummary(terminal, summary);
  const std::string printed = terminal.str();
  const std::string within = printed.substr(printed.find("within spec"));
  const std::size_t trajectory_line = within.find(fmt::format("d_trajectory_mm <= {:g}", trajectory_limit));
  const std::size_t runout_line = within.find(fmt::format("runout_mm <= {:g}", runout_limit));
  const std::size_t joint_line = within.find("every limit at once");
  ASSERT_NE(trajectory_line, std::string::npos) << printed;
  ASSERT_NE(runout_line, std::string::npos) << printed;
  ASSERT_NE(joint_line, std::string::npos) << printed;
  EXPECT_LT(runout_line, joint_line);
  EXPECT_THAT(within.substr(trajectory_line, within.find('\n', trajectory_line) - trajectory_line),
              HasSubstr(YieldText(within_trajectory, done)));
  EXPECT_THAT(within.substr(runout_line, within.find('\n', runout_line) - runout_line),
              HasSubstr(YieldText(within_runout, done)));
  EXPECT_THAT(within.substr(joint_line, within.find('\n', joint_line) - joint_line),
              HasSubstr(YieldText(within_both, done)));
  const nlohmann::json summary_json = SummaryJson(summary);
  ASSERT_TRUE(summary_json.contains("in_spec_by_limit"));
  ASSERT_EQ(summary_json["in_spec_by_limit"].size(), 2u);
  EXPECT_EQ(summary_json["in_spec_by_limit"][0]["output"], "d_trajectory_mm");
  EXPECT_EQ(summary_json["in_spec_by_limit"][0]["limit"], trajectory_limit);
  EXPECT_EQ(summary_json["in_spec_by_limit"][0]["successes"], within_trajectory);
  EXPECT_EQ(summary_json["in_spec_by_limit"][1]["successes"], within_runout);
  EXPECT_EQ(summary_json["in_spec_by_limit"][1]["trials"], done);
  EXPECT_EQ(summary_json["in_spec"]["successes"], within_both);
}

// Over the life, error motion has no one-revolution value to stand beside (one revolution
// has no asynchronous part): the terminal and the answer say what it is instead, its three
// values at q99 and q50 in µm, how they are read, and that no one-revolution comparison
// exists.
TEST_F(ReportTest, TheLifeSectionSaysWhatTheErrorMotionOverTheLifeIs) {
  const std::filesystem::path results = RunWithFailures();
  const CampaignSummary summary = Summarise(CampaignReader(results), {});
  std::ostringstream terminal;
  PrintSummary(terminal, summary);
  const std::string printed = terminal.str();
  const std::size_t at = printed.find("error motion");
  ASSERT_NE(at, std::string::npos) << printed;
  const std::size_t line_start = printed.rfind('\n', at) + 1;
  const std::string line = printed.substr(line_start, printed.find('\n', at) - line_start);
  EXPECT_EQ(line.rfind("life ", 0), 0u) << line;
  for (const char* said : {"ISO 230-7", "total", "synchronous", "asynchronous", "fundamental removed", "µm",
                           "several revolutions"}) {
    EXPECT_THAT(line, HasSubstr(said)) << said;
  }
  // q99 of the total, in µm: the same order statistic the table prints in mm.
  const OutputSummary* total = nullptr;
  for (const OutputSummary& o : summary.outputs) {
    if (o.name == "error_motion_total_mm") total = &o;
  }
  ASSERT_NE(total, nullptr);
  const double q99_um = total->quantiles[2].value * 1e3;
  ASSERT_GT(q99_um, 1.0);  // the ring's form moves the axis by micrometres
  EXPECT_THAT(line, HasSubstr(fmt::format("{:.4g} µm", q99_um)));
  const nlohmann::json json = SummaryJson(summary);
  ASSERT_TRUE(json.contains("life"));
  ASSERT_TRUE(json["life"].contains("error_motion"));
  EXPECT_DOUBLE_EQ(json["life"]["error_motion"]["total_mm"]["q99"].get<double>(), total->quantiles[2].value);
  // Beside every error-motion number, its filter and its revolutions: on the life line, under
  // the table and with each error-motion output in JSON.
  const std::string reading = ErrorMotionConditions({.filter = summary.error_motion_filter});
  EXPECT_THAT(reading, HasSubstr("Gaussian filter at 50 UPR"));
  EXPECT_THAT(line, HasSubstr(reading));
  EXPECT_THAT(printed, HasSubstr("error_motion_*               " + reading));
  for (const char* output : {"error_motion_total_mm", "error_motion_synchronous_mm", "error_motion_asynchronous_mm"}) {
    EXPECT_EQ(json["outputs"][output]["reading"], reading) << output;
  }
  EXPECT_FALSE(json["outputs"]["d_trajectory_mm"].contains("reading"));

  const CampaignReport report = QuickReport(results);
  const std::string answer = AnswerOf(ReportHtml(report));
  EXPECT_THAT(answer, HasSubstr("ISO 230-7"));
  EXPECT_THAT(answer, HasSubstr(fmt::format("{:.4g} µm", q99_um)));
  EXPECT_TRUE(ReportJson(report)["life"].contains("error_motion"));
}

// Beside the TIR of each replayed orbit, the page says what an indicator reads (the bore's
// form and the axis's motion) and what error motion is (the axis alone, its fundamental
// removed), and points to the polar plot.
TEST_F(ReportTest, TheIndicatorReadingIsToldApartFromErrorMotionBesideTheTir) {
  const std::filesystem::path results = RunWithFailures();
  ReportOptions options;
  options.bootstrap_resamples = 0;
  options.error_motion_revolutions = 2;
  const std::string html = ReportHtml(BuildReport(results, options));
  const std::size_t sensor = html.find(": sensor, TIR ");
  ASSERT_NE(sensor, std::string::npos);
  const std::size_t caption = html.find("<figcaption>", sensor);
  const std::string beside = html.substr(caption, html.find("</figcaption>", caption) - caption);
  EXPECT_THAT(beside, HasSubstr("form"));
  EXPECT_THAT(beside, HasSubstr("axis"));
  EXPECT_THAT(beside, HasSubstr("error motion"));
  EXPECT_THAT(beside, HasSubstr("fundamental removed"));
  EXPECT_THAT(beside, HasSubstr("polar plot"));
  EXPECT_LT(caption, html.find("id=\"error-motion\""));  // said before the polar plot, where the TIR is
}

// Numbers are written to what they mean: the page's text (charts aside) has none in
// exponent notation, such as a replay tolerance of picometres.
TEST_F(ReportTest, NoNumberOnThePageIsWrittenInExponentNotation) {
  const std::filesystem::path results = RunWithFailures();
  ReportOptions options;
  options.bootstrap_resamples = 0;
  options.error_motion_revolutions = 2;
  std::string text = ReportHtml(BuildReport(results, options));
  for (std::size_t at = text.find("<svg"); at != std::string::npos; at = text.find("<svg", at)) {
    text.erase(at, text.find("</svg>", at) + 6 - at);
  }
  for (std::size_t at = 0; at + 2 < text.size(); ++at) {
    const bool exponent = std::isdigit(static_cast<unsigned char>(text[at])) && text[at + 1] == 'e' &&
                          (text[at + 2] == '-' || text[at + 2] == '+');
    EXPECT_FALSE(exponent) << "..." << text.substr(at < 80 ? 0 : at - 80, 120) << "...";
  }
}

TEST_F(ReportTest, ASampleThatNoLongerReplaysIsReportedInsteadOfDrawn) {
  CampaignReport report;
  ReplayedTrajectory moved;
  moved.label = "worst";
  moved.index = 17;
  moved.status = "ok";
  moved.stored_d_trajectory_mm = 0.25;
  moved.d_trajectory_mm = 0.26;
  moved.tolerance_mm = 4e-5;
  report.trajectories.push_back(moved);
  const std::string html = ReportHtml(report);
  EXPECT_THAT(html, HasSubstr("Sample 17 does not replay to its stored result (D_trajectory 0.26 mm against 0.25 mm"));
  EXPECT_THAT(html, Not(HasSubstr("Sample 17: ring centre")));
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
  EXPECT_THAT(html, HasSubstr("No orbit is drawn: no sample finished ok."));
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
  command.out = dir_;
  EXPECT_THAT(error_of(command), HasSubstr("is a folder; allowed: a file name in it"));
  // A folder no one may write in, root included: the error says so, not how the
  // temporary file failed.
  command.out = "/proc/ringtol-report.html";
  const std::string unwritable = error_of(command);
  EXPECT_THAT(unwritable, HasSubstr("/proc/ringtol-report.html"));
  EXPECT_THAT(unwritable, ::testing::Not(HasSubstr("filesystem error")));
  EXPECT_THAT(unwritable, ::testing::Not(HasSubstr(".partial")));
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

// Shares of a sum of 1, listed out of order; the rule (99 % together, then any other of at
// least 0.5 %) keeps the largest five: 0.5 + 0.3 + 0.15 + 0.035 = 0.985 falls short, the
// 0.006 order brings 0.991, and 0.004 is below 0.5 %.
TEST(OrderChart, KeepsTheFewestOrdersThatCarryNinetyNinePercent) {
  const std::vector<double> shares = {0.002, 0.3, 0.004, 0.5, 0.035, 0.003, 0.15, 0.006};
  EXPECT_THAT(OrdersCarryingVariance(shares, 0.99, 0.005), ElementsAre(1, 3, 4, 6, 7));
  // Shares, not values: the same table at another scale keeps the same orders.
  std::vector<double> scaled = shares;
  for (double& v : scaled) v *= 7.0;
  EXPECT_THAT(OrdersCarryingVariance(scaled, 0.99, 0.005), ElementsAre(1, 3, 4, 6, 7));
}

// 0.9 + 0.092 = 0.992 reaches 99 % with two orders; 0.006 is kept for its own 0.6 %.
TEST(OrderChart, KeepsAnOrderAboveHalfAPercentEvenAfterNinetyNinePercentAreReached) {
  EXPECT_THAT(OrdersCarryingVariance(std::vector<double>{0.9, 0.002, 0.092, 0.006}, 0.99, 0.005),
              ElementsAre(0, 2, 3));
}

// A negative estimate (noise about 0) and NaN carry nothing and are not counted in the sum.
TEST(OrderChart, NegativeAndNonFiniteEstimatesCarryNothing) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT(OrdersCarryingVariance(std::vector<double>{-0.2, 0.6, kNaN, 0.4}, 0.99, 0.005), ElementsAre(1, 3));
  EXPECT_THAT(OrdersCarryingVariance(std::vector<double>{0.0, -0.1, 0.0}, 0.99, 0.005), ElementsAre(0, 1, 2));
}

// A hand-made Sobol' table of twelve orders: the chart names the kept orders, sums the
// others into one bar and states the rule; the JSON keeps every order.
TEST(OrderChart, TheReportChartsOnlyTheKeptOrdersAndSumsTheRest) {
  CampaignReport report;
  report.rollers = 3;
  report.primary_output = "d_trajectory_mm";
  OutputSensitivity s;
  s.output = "d_trajectory_mm";
  s.method = "sobol";
  s.rows = 1000;
  SensitivityLevel by_order{"order", Aggregation::kExact, {}};
  const std::vector<double> st = {0.6, 0.25, 0.1, 0.03, 0.012, 0.004, 0.002, 0.001, 0.0005, 0.0003, 0.0001, 0.0001};
  for (std::size_t k = 0; k < st.size(); ++k) {
    SensitivityEntry e;
    e.name = fmt::format("order {}", k + 2);
    e.order = static_cast<int>(k) + 2;
    e.first_order = {0.8 * st[k], 0.01, {0.8 * st[k] - 0.01, 0.8 * st[k] + 0.01}};
    e.total_order = analysis::SobolIndex{st[k], 0.01, {st[k] - 0.01, st[k] + 0.01}};
    e.ranking = st[k];
    by_order.entries.push_back(e);
  }
  s.levels = {by_order, by_order};  // the first level is the finest table's
  s.levels[0].level = "design";
  for (SensitivityEntry& e : s.levels[0].entries) e.name = "ring " + e.name;
  report.sensitivities.push_back(s);
  const std::string html = ReportHtml(report);
  // Sum 1.0: 0.6 + 0.25 + 0.1 + 0.03 = 0.98, + 0.012 = 0.992: orders 2 to 6.
  for (int order = 2; order <= 6; ++order) EXPECT_THAT(html, HasSubstr(fmt::format(">order {}<", order))) << order;
  for (int order = 7; order <= 13; ++order) EXPECT_THAT(html, Not(HasSubstr(fmt::format(">order {}<", order)))) << order;
  EXPECT_THAT(html, HasSubstr(">7 other orders<"));
  EXPECT_THAT(html, HasSubstr("together carry 99 % of what all 12 orders carry"));
  EXPECT_THAT(html, HasSubstr("at least 0.5 %"));
  EXPECT_EQ(ReportJson(report)["sensitivity"]["d_trajectory_mm"]["order"]["entries"].size(), st.size());
}

}  // namespace
}  // namespace ringtol::jobs
