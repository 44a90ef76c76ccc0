// `ringtol report` as a user runs it, on campaigns run alone first: on ringtol's own physics
// (the per-order Sobol' indices of the article's three rollers) and in a browser (headless
// Chromium loads the page offline and paints its charts).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "jobs/store/campaign_store.h"
#include "tests/support/chromium.h"
#include "tests/support/mpi_environment.h"
#include "tests/support/shell.h"
#include "tests/support/text_files.h"

namespace {

using ::testing::HasSubstr;
using ::testing::Not;

class CampaignReport : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ringtol::testing::FreshTestFolder("report_cli_test");
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  ringtol::testing::ShellOutcome Run(const std::string& command) {
    return ringtol::testing::RunShell(command, dir_ / "stderr.txt");
  }
  // `ringtol campaign` starts MPI even alone.
  ringtol::testing::ShellOutcome Ringtol(const std::string& arguments) {
    return Run(ringtol::testing::kMpiEnvironment + RINGTOL_EXECUTABLE + " " + arguments);
  }
  std::string Example(const std::string& name) const {
    return (std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/campaigns" / name).string();
  }

  std::filesystem::path dir_;
};

// The tests that start headless Chromium (label browser).
class CampaignReportInChromium : public CampaignReport {};

// Three rollers 120 degrees apart, a ring whose orders 2..12 all have the same amplitude
// scale, a Saltelli design with one group per order. Why the multiples of Z = 3 lead: the
// ring's radius error of order n at roller k (angle theta_k = 2 pi k / 3) is
// A cos(n (theta_k - psi) + phi). When 3 divides n, n theta_k is a multiple of 2 pi, so all
// three contacts see the same error A cos(phi - n psi) at once: the ring swells and shrinks
// as a whole. Held by the two fixed rollers, whose normals are 120 degrees apart, a bore
// larger by delta moves the centre along their bisector by delta / cos(60 deg) = 2 delta,
// so the centre swings 2 A either side: D_trajectory = 4 A. For other n the three errors
// are 120 degrees out of phase, the pattern of a circle moved sideways by A, and the
// centre only circles: D_trajectory = 2 A. Equal amplitudes, twice the swing: each
// multiple of 3 carries about four times the variance of another order.
TEST_F(CampaignReport, OrdersThatAreMultiplesOfTheRollerCountRankAboveTheOthers) {
  const std::string results = (dir_ / "orders.h5").string(), json = (dir_ / "orders.json").string();
  const auto campaign = Ringtol("campaign " + Example("ring_orders.toml") + " --out " + results + " --quiet");
  ASSERT_EQ(campaign.exit_code, 0) << campaign.err;
  const auto report = Ringtol("report " + results + " --out " + (dir_ / "orders.html").string() + " --json " + json);
  ASSERT_EQ(report.exit_code, 0) << report.err;
  const nlohmann::json summary = nlohmann::json::parse(ringtol::testing::ReadText(json));
  EXPECT_EQ(summary["campaign"]["rollers"], 3);
  const nlohmann::json& by_order = summary["sensitivity"]["d_trajectory_mm"]["order"];
  EXPECT_EQ(by_order["aggregation"], "exact");  // the design froze each order as one group
  double lowest_multiple = INFINITY, highest_other = -INFINITY;
  double lowest_multiple_lower = INFINITY, highest_other_upper = -INFINITY;
  int multiples = 0, others = 0;
  for (const nlohmann::json& entry : by_order["entries"]) {
    const int order = entry["order"];
    const double st = entry["ST"], lower = entry["ST_interval"][0], upper = entry["ST_interval"][1];
    ASSERT_GE(order, 2);
    if (order % 3 == 0) {
      ++multiples;
      lowest_multiple = std::min(lowest_multiple, st);
      lowest_multiple_lower = std::min(lowest_multiple_lower, lower);
    } else {
      ++others;
      highest_other = std::max(highest_other, st);
      highest_other_upper = std::max(highest_other_upper, upper);
    }
  }
  EXPECT_EQ(multiples, 4);  // 3, 6, 9, 12
  EXPECT_EQ(others, 7);
  EXPECT_GT(lowest_multiple, highest_other);
  // Not by chance: the bootstrap intervals (95 %) do not overlap either.
  EXPECT_GT(lowest_multiple_lower, highest_other_upper);
  // The ranking the page shows is the JSON's.
  const std::string html = ringtol::testing::ReadText(dir_ / "orders.html");
  EXPECT_THAT(html, HasSubstr("Dominant orders, largest first: "));

  // The orbit drawn first is the sample with the largest D_trajectory of the independent
  // draws, replayed to the value the results file holds for that index.
  const nlohmann::json& worst = summary["trajectories"][0];
  EXPECT_EQ(worst["label"], "worst");
  EXPECT_EQ(worst["reproduced"], true);
  EXPECT_EQ(worst["stored_d_trajectory_mm"], summary["outputs"]["d_trajectory_mm"]["max"]);
  const ringtol::jobs::CampaignReader reader(results);
  EXPECT_EQ(reader.ReadSample(worst["index"].get<std::int64_t>()).outputs[0], worst["stored_d_trajectory_mm"]);
  EXPECT_LE(std::abs(worst["d_trajectory_mm"].get<double>() - worst["stored_d_trajectory_mm"].get<double>()),
            worst["tolerance_mm"].get<double>());
  EXPECT_THAT(html, HasSubstr("Orbits of the worst and the median assembly"));
  EXPECT_THAT(html, HasSubstr("Worst D_trajectory: sample " + std::to_string(worst["index"].get<std::int64_t>())));
}

TEST_F(CampaignReportInChromium, PageIsSelfContainedAndHeadlessChromiumPaintsItsCharts) {
  const std::string results = (dir_ / "small.h5").string(), page = (dir_ / "report.html").string();
  const auto campaign = Ringtol("campaign " + Example("default.toml") + " --samples 64 --out " + results + " --quiet");
  ASSERT_EQ(campaign.exit_code, 0) << campaign.err;
  const auto report = Ringtol("report " + results + " --out " + page);
  ASSERT_EQ(report.exit_code, 0) << report.err;
  EXPECT_THAT(report.out, HasSubstr("Report: " + page));

  // Self-contained: nothing a browser would fetch.
  const std::string html = ringtol::testing::ReadText(page);
  for (const char* fetch : ringtol::testing::kFetches) EXPECT_THAT(html, Not(HasSubstr(fetch))) << fetch;
  EXPECT_GE(std::count(html.begin(), html.end(), '<'), 100);

  // Chromium renders the file offline and paints its charts.
  const ringtol::testing::ChromiumPage shown = ringtol::testing::RenderInChromium(page, dir_);
  ringtol::testing::ExpectPaintedWithoutErrors(shown);
  EXPECT_GE(shown.svg_count, 9u) << "histogram, CDF, two convergence plots, sensitivity bars, two orbits with their sensors";
  EXPECT_THAT(shown.dom.out, HasSubstr("Which tolerance to tighten first"));
  EXPECT_THAT(shown.dom.out, HasSubstr("Orbits of the worst and the median assembly"));
}

}  // namespace
