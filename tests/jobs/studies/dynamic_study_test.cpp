#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>

#include "jobs/studies/dynamic_study.h"
#include "jobs/inputs/input_error.h"
#include "solvers/dynamic.h"
#include "solvers/quasistatic.h"
#include "solvers/simulation.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

using ::testing::HasSubstr;
using testing::kDeg;

jobs::DynamicStudyOptions Quick() {
  jobs::DynamicStudyOptions options;
  options.orders = {3};
  options.rates = {1.0 * kDeg, 30.0 * kDeg};
  return options;
}

// The study's numbers are the solvers' own: its diameters are what the rungs give for
// the same order-3 scene, bit for bit (the adaptive integrator would turn even a
// one-ulp change of the scene into a tolerance-sized one, so equality is the test).
TEST(DynamicStudy, ReportsWhatTheRungsGiveForTheSameScene) {
  const engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  const jobs::DynamicStudy study = jobs::RunDynamicStudy(scene, Quick(), nullptr);
  ASSERT_TRUE(study.failures.empty()) << study.failures.front();
  ASSERT_EQ(study.transient.size(), 1u);
  engine::Scene order3 = scene;
  testing::SetRing(order3, {{3, 0.14e-3, 45.0 * kDeg}});
  EXPECT_EQ(study.transient[0].quasistatic, solvers::Simulate(order3, solvers::QuasistaticSolver()).d_trajectory);
  order3.motion = engine::ArticleLaw(0.5, 270.0 * kDeg, 4.0);
  const solvers::SimulationResult dynamic = solvers::Simulate(order3, solvers::DynamicSolver());
  EXPECT_EQ(study.transient[0].first, dynamic.d_trajectory);
  ASSERT_TRUE(dynamic.steady);
  EXPECT_EQ(study.transient[0].steady, dynamic.steady->d_trajectory);
  solvers::DynamicOptions article;
  article.start = solvers::DynamicStart::kArticleSettle;
  const solvers::SimulationResult settled = solvers::Simulate(order3, solvers::DynamicSolver(article));
  EXPECT_EQ(study.transient[0].first_article_settle, settled.d_trajectory);
  ASSERT_TRUE(settled.steady);
  EXPECT_EQ(study.transient[0].steady_article_settle, settled.steady->d_trajectory);
}

// The chart carries every curve of the start table and the article's range.
TEST(DynamicStudy, ChartsEveryRevolutionAgainstTheArticlesRange) {
  jobs::DynamicStudy study;
  study.rate = 270.0 * kDeg;
  study.settle = 0.5;
  study.transient.push_back({.order = 3,
                             .quasistatic = 546.8e-6,
                             .first = 560.0e-6,
                             .steady = 559.0e-6,
                             .first_article_settle = 655.4e-6,
                             .first_long_settle = 561.4e-6,
                             .steady_article_settle = 559.0e-6});
  std::ostringstream svg;
  jobs::WriteDynamicStudySvg(svg, study);
  EXPECT_THAT(svg.str(), HasSubstr("<svg"));
  EXPECT_THAT(svg.str(), HasSubstr("reported range, 0.29-0.63 mm"));
  EXPECT_THAT(svg.str(), HasSubstr("first revolution from the quasistatic equilibrium"));
  EXPECT_THAT(svg.str(), HasSubstr("first revolution after the article"));
  EXPECT_THAT(svg.str(), HasSubstr("steady (4th) revolution"));
  EXPECT_THAT(svg.str(), HasSubstr("quasistatic"));
}

// The creep lag grows with speed (tau * rate * |dx/dpsi|), so the gap to the quasi-static
// path must grow from 1 to 30 deg/s, and for order 3 cross 1 um in between (about 0.01 um
// at 1 deg/s and 5 um at 30 deg/s): the threshold lies strictly inside the range.
TEST(DynamicStudy, GapGrowsWithSpeedAndTheThresholdFallsBetween) {
  const jobs::DynamicStudy study =
      jobs::RunDynamicStudy(testing::PaperScene(engine::ContactLaw::Model::kPenalty), Quick(), nullptr);
  ASSERT_EQ(study.speed.size(), 1u);
  const jobs::SpeedRow& row = study.speed[0];
  ASSERT_EQ(row.gap.size(), 2u);
  EXPECT_LT(row.gap[0], 1e-6);
  EXPECT_GT(row.gap[1], 1e-6);
  EXPECT_GT(row.threshold, 1.0 * kDeg);
  EXPECT_LT(row.threshold, 30.0 * kDeg);
  std::ostringstream text;
  jobs::PrintDynamicStudy(text, study);
  EXPECT_THAT(text.str(), HasSubstr("1 um above"));
}

TEST(DynamicStudy, NeedsASteadyRateAndSomethingToStudy) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  jobs::DynamicStudyOptions no_orders = Quick();
  no_orders.orders.clear();
  EXPECT_THROW(jobs::RunDynamicStudy(scene, no_orders, nullptr), jobs::InputError);
  scene.motion = engine::TestBenchLaw();
  EXPECT_THROW(jobs::RunDynamicStudy(scene, Quick(), nullptr), jobs::InputError);
}

}  // namespace
}  // namespace ringtol
