// Life metrics (solvers/life.h) against what is known exactly: without roller lobes every
// revolution is the first; the union of revolutions only grows with their number and
// never passes the closed form's every-phase envelope; revolutions repeat after the cycle
// rational spin ratios give; and the linear rung's phasor-summed revolutions agree with
// the quasistatic rung solving each revolution afresh.
#include "solvers/life.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "solvers/linear.h"
#include "solvers/quasistatic.h"
#include "solvers/simulation.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

constexpr double kRoundOff = 1e-12;  // [m]

solvers::SimulationOptions Options() {
  solvers::SimulationOptions options;
  options.steps = 1440;
  return options;
}

// The paper's assembly with a lobed ring and lobed rollers of three sizes within a class,
// so that their spin ratios never repeat.
engine::Scene DriftingScene() {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{2, 40e-6, 0.3}, {3, 10e-6, 1.0}, {7, 3e-6, 2.0}});
  const double sizes[] = {-1.3e-6, 0.4e-6, -0.2e-6};
  for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
    engine::Roller& roller = scene.rollers[i];
    roller.outline = engine::PolarProfile(roller.outline.radius(), sizes[i],
                                          {{2, 3e-6, 0.5 * static_cast<double>(i)}, {3, 1.5e-6, 1.0}, {5, 0.8e-6, 2.0}});
  }
  return scene;
}

TEST(Life, WithoutRollerLobesEveryRevolutionIsTheFirst) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{2, 40e-6, 0.3}, {5, 6e-6, 1.0}});
  const solvers::LinearSolver linear;
  const solvers::SimulationResult one = solvers::Simulate(scene, linear, Options());
  ASSERT_EQ(one.status, solvers::Status::kOk) << one.message;
  const solvers::LifeResult life = solvers::LinearLife(scene, linear, Options(), 8);
  ASSERT_EQ(life.status, solvers::Status::kOk) << life.message;
  ASSERT_TRUE(life.asymptotic.has_value());
  for (const solvers::LifeValues& values : {life.values, *life.asymptotic}) {
    EXPECT_NEAR(values.d_trajectory, one.d_trajectory, kRoundOff);
    EXPECT_NEAR(values.runout, one.runout, kRoundOff);
    EXPECT_NEAR(values.error_motion.asynchronous, 0.0, kRoundOff);
    EXPECT_NEAR(values.error_motion.total, values.error_motion.synchronous, kRoundOff);
  }
  const solvers::LifeResult exact = solvers::SimulateLife(scene, solvers::QuasistaticSolver(), Options(), 3);
  ASSERT_EQ(exact.status, solvers::Status::kOk) << exact.message;
  EXPECT_NEAR(exact.values.error_motion.asynchronous, 0.0, 1e-11);
}

// The first revolution summed from the phasors is the linear rung's own path.
TEST(Life, TheFirstRevolutionIsTheLinearPath) {
  const engine::Scene scene = DriftingScene();
  const solvers::LinearSolver linear;
  const solvers::SimulationResult one = solvers::Simulate(scene, linear, Options());
  ASSERT_EQ(one.status, solvers::Status::kOk) << one.message;
  const solvers::LifeResult life = solvers::LinearLife(scene, linear, Options(), 1);
  ASSERT_EQ(life.status, solvers::Status::kOk) << life.message;
  EXPECT_NEAR(life.values.d_trajectory, one.d_trajectory, kRoundOff);
  EXPECT_NEAR(life.values.runout, one.runout, kRoundOff);
}

TEST(Life, TheUnionGrowsWithRevolutionsUpToTheEnvelope) {
  const engine::Scene scene = DriftingScene();
  const solvers::LinearSolver linear;
  const solvers::LifeResult first = solvers::LinearLife(scene, linear, Options(), 1);
  ASSERT_EQ(first.status, solvers::Status::kOk) << first.message;
  ASSERT_TRUE(first.asymptotic.has_value());
  EXPECT_EQ(first.cycle, 0) << "the sizes were chosen never to repeat";
  const solvers::LifeValues& every = *first.asymptotic;
  const double lobes = every.d_trajectory - first.values.d_trajectory;
  EXPECT_GT(lobes, 2.0 * first.error_estimate) << "the lobes add no more than the allowance: the test shows nothing";
  double previous_d = 0.0, previous_runout = 0.0, previous_total = 0.0;
  std::vector<double> gaps;
  for (const int revolutions : {1, 4, 16, 64, 256}) {
    const solvers::LifeResult life = solvers::LinearLife(scene, linear, Options(), revolutions);
    ASSERT_EQ(life.status, solvers::Status::kOk) << life.message;
    EXPECT_GE(life.values.d_trajectory, previous_d - kRoundOff) << revolutions;
    EXPECT_GE(life.values.runout, previous_runout - kRoundOff) << revolutions;
    EXPECT_GE(life.values.error_motion.total, previous_total - kRoundOff) << revolutions;
    EXPECT_LE(life.values.d_trajectory, every.d_trajectory + life.error_estimate) << revolutions;
    EXPECT_LE(life.values.runout, every.runout + life.error_estimate) << revolutions;
    EXPECT_LE(life.values.error_motion.asynchronous, every.error_motion.asynchronous + life.error_estimate)
        << revolutions;
    previous_d = life.values.d_trajectory;
    previous_runout = life.values.runout;
    previous_total = life.values.error_motion.total;
    gaps.push_back(every.d_trajectory - life.values.d_trajectory);
  }
  // Three incommensurate rollers fill their phase torus slowly: 256 revolutions leave less
  // than half of what 16 leave.
  EXPECT_LT(gaps.back(), 0.5 * gaps[2]);
  RecordProperty("gap_1_um", std::to_string(gaps[0] * 1e6));
  RecordProperty("gap_16_um", std::to_string(gaps[2] * 1e6));
  RecordProperty("gap_256_um", std::to_string(gaps.back() * 1e6));
}

// One lobed roller has one phase to fill, which 256 revolutions fill to within a phase
// step of 2 pi / 256: the union then meets the closed-form envelope up to what such a step
// and the allowance leave.
TEST(Life, OneLobedRollerFillsItsEnvelope) {
  engine::Scene scene = DriftingScene();
  for (std::size_t i = 1; i < scene.rollers.size(); ++i) {
    engine::Roller& roller = scene.rollers[i];
    roller.outline = engine::PolarProfile(roller.outline.radius(), roller.outline.mean_deviation(), {});
  }
  const solvers::LinearSolver linear;
  const solvers::LifeResult life = solvers::LinearLife(scene, linear, Options(), 256);
  ASSERT_EQ(life.status, solvers::Status::kOk) << life.message;
  ASSERT_TRUE(life.asymptotic.has_value());
  const solvers::LifeResult first = solvers::LinearLife(scene, linear, Options(), 1);
  const double lobes = life.asymptotic->d_trajectory - first.values.d_trajectory;
  EXPECT_GT(lobes, 2.0 * life.error_estimate) << "the lobes add no more than the allowance: the test shows nothing";
  // A phase step of 2 pi / 256 on order-5 lobes misses at most (5 pi / 256)^2 / 2 of them.
  EXPECT_NEAR(life.values.d_trajectory, life.asymptotic->d_trajectory, 0.01 * lobes + life.error_estimate);
  EXPECT_NEAR(life.values.error_motion.asynchronous, life.asymptotic->error_motion.asynchronous,
              0.01 * life.asymptotic->error_motion.asynchronous + life.error_estimate);
}

// Equal rollers in the paper's 302 mm bore turn 60.4 times a revolution: every fifth
// revolution is the first again, and the life is those five.
TEST(Life, RationalSpinRatiosRepeatAfterTheirCycle) {
  engine::Scene scene = DriftingScene();
  for (engine::Roller& roller : scene.rollers) {
    roller.outline = engine::PolarProfile(roller.outline.radius(), 0.0, roller.outline.harmonics());
  }
  const solvers::LinearSolver linear;
  const solvers::LifeResult five = solvers::LinearLife(scene, linear, Options(), 5);
  const solvers::LifeResult fifty = solvers::LinearLife(scene, linear, Options(), 50);
  ASSERT_EQ(five.status, solvers::Status::kOk) << five.message;
  EXPECT_EQ(five.cycle, 5);
  ASSERT_TRUE(five.asymptotic.has_value());
  EXPECT_NEAR(fifty.values.d_trajectory, five.values.d_trajectory, 1e-11);
  EXPECT_NEAR(fifty.values.error_motion.asynchronous, five.values.error_motion.asynchronous, 1e-11);
  // The cycle's revolutions summed from the phasors, against each solved on its own.
  EXPECT_NEAR(five.asymptotic->d_trajectory, five.values.d_trajectory, five.error_estimate);
  EXPECT_NEAR(five.asymptotic->error_motion.asynchronous, five.values.error_motion.asynchronous,
              five.error_estimate);
}

// The reference: the quasistatic rung solves every revolution from the rollers' turned
// phases, and so does the linear rung; they agree within the linear rung's estimate. The
// closed-form envelope, which carries the first revolution's second-order correction to
// every phase, holds every solved revolution within its allowance.
TEST(Life, PhasorRevolutionsAreTheQuasistaticRungsRevolutions) {
  const engine::Scene scene = DriftingScene();
  const solvers::LinearSolver linear;
  const solvers::QuasistaticSolver quasistatic;
  constexpr int kRevolutions = 6;
  const solvers::LifeResult summed = solvers::LinearLife(scene, linear, Options(), kRevolutions);
  const solvers::LifeResult solved = solvers::SimulateLife(scene, quasistatic, Options(), kRevolutions);
  ASSERT_EQ(summed.status, solvers::Status::kOk) << summed.message;
  ASSERT_EQ(solved.status, solvers::Status::kOk) << solved.message;
  const double allowance = summed.error_estimate;
  EXPECT_NEAR(summed.values.d_trajectory, solved.values.d_trajectory, allowance);
  EXPECT_NEAR(summed.values.runout, solved.values.runout, allowance);
  EXPECT_NEAR(summed.values.error_motion.total, solved.values.error_motion.total, allowance);
  EXPECT_NEAR(summed.values.error_motion.synchronous, solved.values.error_motion.synchronous, allowance);
  EXPECT_NEAR(summed.values.error_motion.asynchronous, solved.values.error_motion.asynchronous, allowance);
  EXPECT_NEAR(summed.artefact, solved.artefact, kRoundOff);
  // Each solved revolution lies inside the every-phase envelope.
  for (int k = 0; k < kRevolutions; ++k) {
    const solvers::SimulationResult revolution =
        solvers::Simulate(solvers::AtRevolution(scene, k), quasistatic, Options());
    EXPECT_LE(revolution.d_trajectory, summed.asymptotic->d_trajectory + allowance) << k;
  }
}

}  // namespace
}  // namespace ringtol
