// The report's ISO 230-7 polar plot (jobs/report/error_motion_plot.h) against the engine's
// own reading of the same revolutions (engine::MeasureErrorMotion), and against what is
// known exactly: round rollers make every revolution the first, so there is no band.
#include "jobs/report/error_motion_plot.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/error_motion.h"
#include "jobs/report/report_html.h"
#include "jobs/report/report_text.h"
#include "jobs/report/svg_chart.h"
#include "solvers/life.h"
#include "solvers/linear.h"
#include "tests/support/paper_scene.h"

namespace ringtol::jobs {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;
using svg::EscapeXml;

// The values are differences of micrometre-sized numbers computed in two orders (less the
// mean here, not in the engine): round-off of ~1e-16 of the axis motion's ~100 um offset,
// so 1e-9 um leaves room.
constexpr double kRoundOffUm = 1e-9;
constexpr int kRevolutions = 8;

solvers::SimulationOptions Options() {
  solvers::SimulationOptions options;
  options.steps = 720;
  return options;
}

// The axis motion of revolutions first .. last - 1, solved here on their own,
// revolution-major.
std::vector<double> AxisMotion(const engine::Scene& scene, const solvers::Solver& solver, int steps, int first,
                               int last) {
  solvers::SimulationOptions options = Options();
  options.steps = steps;
  const Eigen::Vector2d ray = engine::Direction(scene.sensor_angle);
  std::vector<double> motion;
  for (int k = first; k < last; ++k) {
    const solvers::SimulationResult one = solvers::Simulate(solvers::AtRevolution(scene, k), solver, options);
    EXPECT_EQ(one.status, solvers::Status::kOk) << one.message;
    for (int j = 0; j < steps; ++j) motion.push_back(ray.dot(one.trajectory.centre[static_cast<std::size_t>(j)]));
  }
  return motion;
}

void ExpectTheValuesOf(const ErrorMotionPlot& plot, const engine::ErrorMotion& expected) {
  constexpr double um = 1e6;
  EXPECT_NEAR(plot.total_um, expected.total * um, kRoundOffUm);
  EXPECT_NEAR(plot.synchronous_um, expected.synchronous * um, kRoundOffUm);
  EXPECT_NEAR(plot.asynchronous_um, expected.asynchronous * um, kRoundOffUm);
  EXPECT_NEAR(plot.fundamental_um, expected.fundamental * um, kRoundOffUm);
}

TEST(ErrorMotionPlot, ValuesAndCirclesAreTheEnginesReadingOfTheSameRevolutions) {
  engine::Scene scene = testing::CampaignLikeScene();
  scene.error_motion_filter.cutoff_upr = 0.0;
  const solvers::LinearSolver linear;
  const ErrorMotionPlot plot = PlotErrorMotion(scene, linear, Options(), kRevolutions);
  ASSERT_EQ(plot.status, "ok") << plot.message;
  EXPECT_EQ(plot.revolutions, kRevolutions);
  EXPECT_EQ(plot.steps, Options().steps);

  ExpectTheValuesOf(plot, engine::MeasureErrorMotion(AxisMotion(scene, linear, plot.steps, 0, kRevolutions), plot.steps));
  // The rollers' drifting phases make a band worth drawing, not round-off.
  EXPECT_GT(plot.asynchronous_um, 0.01);

  // The circles' radii differ by the values they draw, and the drawn curves reach them:
  // decimation keeps every extreme.
  EXPECT_DOUBLE_EQ(plot.total_outer_um - plot.total_inner_um, plot.total_um);
  EXPECT_DOUBLE_EQ(plot.synchronous_outer_um - plot.synchronous_inner_um, plot.synchronous_um);
  EXPECT_EQ(*std::min_element(plot.lowest_um.begin(), plot.lowest_um.end()), plot.total_inner_um);
  EXPECT_EQ(*std::max_element(plot.highest_um.begin(), plot.highest_um.end()), plot.total_outer_um);
  EXPECT_EQ(*std::min_element(plot.average_um.begin(), plot.average_um.end()), plot.synchronous_inner_um);
  EXPECT_EQ(*std::max_element(plot.average_um.begin(), plot.average_um.end()), plot.synchronous_outer_um);
  ASSERT_EQ(plot.angle_deg.size(), plot.lowest_um.size());
  ASSERT_EQ(plot.angle_deg.size(), plot.highest_um.size());
  ASSERT_EQ(plot.angle_deg.size(), plot.average_um.size());
  for (std::size_t j = 0; j < plot.angle_deg.size(); ++j) {
    EXPECT_LE(plot.lowest_um[j], plot.average_um[j]) << plot.angle_deg[j];
    EXPECT_LE(plot.average_um[j], plot.highest_um[j]) << plot.angle_deg[j];
  }
  // The synchronous circles lie within the total ones: the average is within the band.
  EXPECT_LE(plot.total_inner_um, plot.synchronous_inner_um);
  EXPECT_GE(plot.total_outer_um, plot.synchronous_outer_um);
}

// Through the scene's filter, the plot reads the revolutions as an analyser recording on
// does: with the filter's margin of revolutions either side, and the band's widest radius
// is where it says the asynchronous value is read.
TEST(ErrorMotionPlot, FilteredItReadsTheRevolutionsWithTheFiltersMarginsAroundThem) {
  engine::Scene scene = testing::CampaignLikeScene();
  scene.error_motion_filter.cutoff_upr = 15.0;
  const solvers::LinearSolver linear;
  const ErrorMotionPlot plot = PlotErrorMotion(scene, linear, Options(), kRevolutions);
  ASSERT_EQ(plot.status, "ok") << plot.message;
  EXPECT_EQ(plot.filter, scene.error_motion_filter);
  const int margin = scene.error_motion_filter.MarginRevolutions();
  ExpectTheValuesOf(plot, engine::MeasureErrorMotion(
                              engine::FilterErrorMotion(AxisMotion(scene, linear, plot.steps, -margin,
                                                                   kRevolutions + margin),
                                                        plot.steps, scene.error_motion_filter),
                              plot.steps));
  scene.error_motion_filter.cutoff_upr = 0.0;
  const ErrorMotionPlot unfiltered = PlotErrorMotion(scene, linear, Options(), kRevolutions);
  EXPECT_LT(plot.asynchronous_um, 0.9 * unfiltered.asynchronous_um) << "the filter takes nothing out";
  const auto at = std::find(plot.angle_deg.begin(), plot.angle_deg.end(), plot.asynchronous_angle_deg);
  ASSERT_NE(at, plot.angle_deg.end()) << "the angle the value is read at is drawn";
  const auto j = static_cast<std::size_t>(at - plot.angle_deg.begin());
  EXPECT_DOUBLE_EQ(plot.highest_um[j] - plot.lowest_um[j], plot.asynchronous_um);
}

TEST(ErrorMotionPlot, WithRoundRollersTheBandCollapsesOntoTheSynchronousAverage) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{2, 40e-6, 0.3}, {5, 6e-6, 1.0}});
  const ErrorMotionPlot plot = PlotErrorMotion(scene, solvers::LinearSolver(), Options(), kRevolutions);
  ASSERT_EQ(plot.status, "ok") << plot.message;
  EXPECT_GT(plot.synchronous_um, 0.1);  // the ring's form moves the axis; only the band is absent
  EXPECT_NEAR(plot.asynchronous_um, 0.0, kRoundOffUm);
  EXPECT_NEAR(plot.total_um, plot.synchronous_um, kRoundOffUm);
  for (std::size_t j = 0; j < plot.angle_deg.size(); ++j) {
    EXPECT_NEAR(plot.lowest_um[j], plot.average_um[j], kRoundOffUm) << plot.angle_deg[j];
    EXPECT_NEAR(plot.highest_um[j], plot.average_um[j], kRoundOffUm) << plot.angle_deg[j];
  }
}

TEST(ErrorMotionPlot, RefusesFewerThanOneRevolution) {
  EXPECT_THROW(PlotErrorMotion(testing::CampaignLikeScene(), solvers::LinearSolver(), Options(), 0),
               std::invalid_argument);
}

// The page draws the plot where the report has one, says why where it has a reason
// instead, and has no error motion section for a file without the life columns.
TEST(ErrorMotionPlot, TheReportPageDrawsItOnlyWhereTheReportHasIt) {
  CampaignReport report;
  report.ok = 12;
  const std::string without = ReportHtml(report);
  EXPECT_THAT(without, Not(HasSubstr("ISO 230-7")));
  EXPECT_THAT(without, Not(HasSubstr("class=\"band\"")));

  report.error_motion_problem = "replays were not asked for";
  EXPECT_THAT(ReportHtml(report), HasSubstr("No polar plot is drawn: replays were not asked for."));

  report.error_motion_problem.reset();
  report.error_motion = PlotErrorMotion(testing::CampaignLikeScene(), solvers::LinearSolver(), Options(), kRevolutions);
  report.error_motion->index = 5;
  report.error_motion->stored_total_mm = 0.0021;
  const ErrorMotionPlot& plot = *report.error_motion;
  const std::string page = ReportHtml(report);
  EXPECT_THAT(page, HasSubstr("Radial error motion of the worst assembly (ISO 230-7)"));
  EXPECT_THAT(page, HasSubstr("Sample 5: radial error motion over 8 revolutions"));
  EXPECT_THAT(page, HasSubstr("class=\"band\""));
  EXPECT_THAT(page, HasSubstr("class=\"base\""));
  EXPECT_THAT(page, HasSubstr("µm per division"));
  EXPECT_THAT(page, HasSubstr("Total error motion " + Micrometres(plot.total_um)));
  EXPECT_THAT(page, HasSubstr("synchronous " + Micrometres(plot.synchronous_um)));
  EXPECT_THAT(page, HasSubstr("asynchronous " + Micrometres(plot.asynchronous_um)));
  // Beside them, how they were read: through the scene's filter, over the replayed
  // revolutions, not the life.
  EXPECT_THAT(page, HasSubstr(EscapeXml(
                        ErrorMotionConditions({.filter = plot.filter, .revolutions = kRevolutions}))));
  EXPECT_THAT(page, HasSubstr("Gaussian filter at 50 UPR"));
  // The band at its own scale, the radius where the asynchronous value is read marked on
  // both, and why the replay reads less than the stored value.
  EXPECT_THAT(page, HasSubstr("Sample 5: the band of revolutions about their average"));
  EXPECT_THAT(page, HasSubstr("class=\"spoke\""));
  EXPECT_THAT(page, HasSubstr(fmt::format("at ψ = {:.1f}°", plot.asynchronous_angle_deg)));
  EXPECT_THAT(page, HasSubstr("The replay reads a total of " + Micrometres(plot.total_um) + " against the " +
                              Micrometres(2.1) + " stored"));
  EXPECT_THAT(page, HasSubstr("meet only 8 phases of each roller"));
  const nlohmann::json json = ReportJson(report);
  EXPECT_EQ(json["error_motion"]["index"], 5);
  EXPECT_EQ(json["error_motion"]["total_um"], plot.total_um);
  EXPECT_EQ(json["error_motion"]["angle_deg"].size(), plot.angle_deg.size());

  // A fundamental of a third of a nanometre carries nothing: it reads as below 1 nm.
  report.error_motion->fundamental_um = 0.0003119;
  const std::string fundamental = ReportHtml(report);
  EXPECT_THAT(fundamental, HasSubstr("synchronous average (here &lt; 0.001 µm)"));
  EXPECT_THAT(fundamental, Not(HasSubstr("0.0003119")));

  report.error_motion->status = "lift_off";
  report.error_motion->message = "revolution 3 of 8: the ring lifts off";
  EXPECT_THAT(ReportHtml(report), HasSubstr("does not replay over 8 revolutions (status lift_off: revolution 3"));
}

}  // namespace
}  // namespace ringtol::jobs
