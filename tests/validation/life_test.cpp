// Life metrics (solvers/life.h) against what is known exactly: without roller lobes every
// revolution is the first; the union of revolutions only grows with their number and
// never passes the closed form's every-phase envelope; rollers of independent phases fill
// it whatever their sizes, and the values are continuous in the sizes; phase-locked
// rollers repeat after the cycle rational spin ratios give, also beside rollers that
// drift; and the linear rung's phasor-summed revolutions agree with the quasistatic rung
// solving each revolution afresh.
#include "solvers/life.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "engine/enclosing_circle.h"
#include "engine/sensor.h"
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

// Equal rollers in the paper's 302 mm bore turn 60.4 times a revolution: geared together,
// every fifth revolution is the first again, and the life is those five.
TEST(Life, PhaseLockedRollersOfEqualSizeRepeatAfterTheirCycle) {
  engine::Scene scene = DriftingScene();
  for (engine::Roller& roller : scene.rollers) {
    roller.outline = engine::PolarProfile(roller.outline.radius(), 0.0, roller.outline.harmonics());
  }
  scene.phase_locked_rollers = true;
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

// A roller's lobe of order o passes the contact o R/r times a revolution: through the error
// motion's filter its share of the asynchronous value is the Gaussian's transmission at
// that rate, and the filter reads nothing but the error motion.
TEST(Life, TheFilterPassesARollersLobeByItsTransmissionAtTheLobesRate) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{2, 40e-6, 0.3}});
  // A fixed roller: a spring roller's form moves its spring, not the ring.
  engine::Roller& lobed = scene.rollers[1];
  lobed.outline = engine::PolarProfile(lobed.outline.radius(), 0.0, {{2, 3e-6, 0.5}});
  const solvers::LinearSolver linear;
  scene.error_motion_filter.cutoff_upr = 0.0;
  const solvers::LifeResult unfiltered = solvers::LinearLife(scene, linear, Options(), 1);
  constexpr double kCutoff = 150.0;  // [UPR] passes about 2/3 of an order-2 lobe at R/r = 60.4
  scene.error_motion_filter.cutoff_upr = kCutoff;
  const solvers::LifeResult filtered = solvers::LinearLife(scene, linear, Options(), 1);
  ASSERT_EQ(unfiltered.status, solvers::Status::kOk) << unfiltered.message;
  ASSERT_EQ(filtered.status, solvers::Status::kOk) << filtered.message;
  ASSERT_TRUE(unfiltered.asymptotic && filtered.asymptotic);
  const double rate = 2.0 * engine::SpinRatio(scene, 1);
  const double transmission = engine::GaussianTransmission(rate, kCutoff);
  ASSERT_GT(unfiltered.asymptotic->error_motion.asynchronous, 0.1e-6);
  EXPECT_NEAR(filtered.asymptotic->error_motion.asynchronous / unfiltered.asymptotic->error_motion.asynchronous,
              transmission, 1e-9);
  EXPECT_EQ(filtered.asymptotic->d_trajectory, unfiltered.asymptotic->d_trajectory);
  EXPECT_EQ(filtered.asymptotic->runout, unfiltered.asymptotic->runout);
}

// Through the filter, the cycle of phase-locked rollers solved revolution by revolution
// (with the filter's margins of revolutions either side) reads what the closed form reads
// from its phasors: the filter is applied to the same motion both ways.
TEST(Life, FilteredRevolutionsOfACycleAreTheClosedFormsCycle) {
  engine::Scene scene = DriftingScene();
  for (engine::Roller& roller : scene.rollers) {
    roller.outline = engine::PolarProfile(roller.outline.radius(), 0.0, roller.outline.harmonics());
  }
  scene.phase_locked_rollers = true;
  const solvers::LinearSolver linear;
  scene.error_motion_filter.cutoff_upr = 0.0;
  const solvers::LifeResult unfiltered = solvers::LinearLife(scene, linear, Options(), 5);
  scene.error_motion_filter.cutoff_upr = 100.0;  // keeps a third of the order-2 lobes at 120.8 UPR
  const solvers::LifeResult five = solvers::LinearLife(scene, linear, Options(), 5);
  ASSERT_EQ(five.status, solvers::Status::kOk) << five.message;
  ASSERT_EQ(five.cycle, 5);
  ASSERT_TRUE(five.asymptotic.has_value());
  const engine::ErrorMotion& solved = five.values.error_motion;
  const engine::ErrorMotion& closed = five.asymptotic->error_motion;
  EXPECT_GT(unfiltered.values.error_motion.asynchronous - solved.asynchronous, 4.0 * five.error_estimate)
      << "the filter takes out no more than the allowance: the test shows nothing";
  EXPECT_NEAR(closed.asynchronous, solved.asynchronous, five.error_estimate);
  EXPECT_NEAR(closed.synchronous, solved.synchronous, five.error_estimate);
  EXPECT_NEAR(closed.total, solved.total, five.error_estimate);
}

// The article's combination case 4 (docs/model.md §6.3: the bore's order 2 of 140 um, each
// roller's order 2 of 14 um, all at 45 deg), the rollers assembled at phases of their own
// and their radii `apart` from one to the next. Its error motion is read unfiltered: what
// the tests below check of it holds whatever the filter, and unfiltered the rollers'
// lobes, at 120.8 UPR, keep their whole size, which the checks need to show something.
engine::Scene CombinationCase4(double apart) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  scene.error_motion_filter.cutoff_upr = 0.0;
  testing::SetRing(scene, {{2, 0.14e-3, 45.0 * testing::kDeg}});
  for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
    engine::Roller& roller = scene.rollers[i];
    const double step = static_cast<double>(i);
    roller.outline = engine::PolarProfile(roller.outline.radius(), apart * step, {{2, 14e-6, 45.0 * testing::kDeg}});
    roller.spin_phase = 2.1 * step;
  }
  return scene;
}

// Rollers of equal size keep their relative phase only as long as nothing slips, and
// rollers a micrometre apart drift through every one within a few hundred revolutions: the
// every-revolution values take every phase of each roller whatever the sizes, so they do
// not jump where the sizes meet.
TEST(Life, EveryRevolutionValuesAreContinuousInTheRollerSizes) {
  const solvers::LinearSolver linear;
  const solvers::LifeResult equal = solvers::LinearLife(CombinationCase4(0.0), linear, Options(), 5);
  ASSERT_EQ(equal.status, solvers::Status::kOk) << equal.message;
  ASSERT_TRUE(equal.asymptotic.has_value());
  EXPECT_EQ(equal.cycle, 0) << "independent phases never repeat";
  // Not the five revolutions after which the equal rollers' phases would repeat if they
  // never slipped: those are one assembly's relative phases, of which every other occurs.
  EXPECT_GT(equal.asymptotic->d_trajectory, equal.values.d_trajectory + equal.error_estimate);
  EXPECT_GT(equal.asymptotic->error_motion.asynchronous,
            equal.values.error_motion.asynchronous + equal.error_estimate);
  // [m] what may change between sizes: each curve's sampling, widened by at most
  // kCurveStraying (2e-4) of its amplitudes (~20 um here), in a diameter or a range twice,
  // for three curves (0.024 um); and the geometry, in which a roller's radius enters at
  // first order: a relative change of its radius moves the values by as much relative.
  constexpr double kSampling = 0.025e-6;
  constexpr double kRollerRadius = 5e-3;  // [m] the paper's
  for (const double apart : {1e-12, 1e-9, 1e-6}) {  // [m]: 1e-9, 1e-6, 1e-3 mm
    const solvers::LifeResult life = solvers::LinearLife(CombinationCase4(apart), linear, Options(), 1);
    ASSERT_EQ(life.status, solvers::Status::kOk) << life.message;
    const solvers::LifeValues& every = *life.asymptotic;
    const solvers::LifeValues& reference = *equal.asymptotic;
    const double geometry = 2.0 * apart / kRollerRadius;  // the largest relative change of a radius
    const auto allowed = [&](double value) { return kSampling + geometry * value; };
    EXPECT_NEAR(every.d_trajectory, reference.d_trajectory, allowed(reference.d_trajectory)) << apart;
    EXPECT_NEAR(every.runout, reference.runout, allowed(reference.runout)) << apart;
    EXPECT_NEAR(every.error_motion.total, reference.error_motion.total, allowed(reference.error_motion.total))
        << apart;
    EXPECT_NEAR(every.error_motion.synchronous, reference.error_motion.synchronous,
                allowed(reference.error_motion.synchronous))
        << apart;
    EXPECT_NEAR(every.error_motion.asynchronous, reference.error_motion.asynchronous,
                allowed(reference.error_motion.asynchronous))
        << apart;
  }
}

// The every-phase envelope against its definition: two lobed rollers of equal size, each
// turned on its own through a grid of phases, every combination solved by the quasistatic
// rung. The union lies inside the closed form within its allowance, and comes within what
// the grid can miss of it. Rollers geared together keep one assembly's phases instead.
TEST(Life, RollersOfEqualSizeAtIndependentPhasesFillTheEnvelope) {
  engine::Scene scene = CombinationCase4(0.0);
  scene.rollers[0].outline = engine::PolarProfile(scene.rollers[0].outline.radius(), 0.0, {});
  const solvers::LinearSolver linear;
  solvers::SimulationOptions options;
  options.steps = 256;
  const solvers::LifeResult closed = solvers::LinearLife(scene, linear, options, 1);
  ASSERT_EQ(closed.status, solvers::Status::kOk) << closed.message;
  const solvers::LifeValues& every = *closed.asymptotic;

  constexpr int kGrid = 24;  // phases a roller
  const solvers::QuasistaticSolver quasistatic;
  const Eigen::Vector2d ray = engine::Direction(scene.sensor_angle);
  std::vector<Eigen::Vector2d> centres;
  std::vector<double> motion;
  for (int a = 0; a < kGrid; ++a) {
    for (int b = 0; b < kGrid; ++b) {
      engine::Scene turned = scene;
      turned.rollers[1].spin_phase += 2.0 * std::numbers::pi * a / kGrid;
      turned.rollers[2].spin_phase += 2.0 * std::numbers::pi * b / kGrid;
      const solvers::SimulationResult one = solvers::Simulate(turned, quasistatic, options);
      ASSERT_EQ(one.status, solvers::Status::kOk) << one.message;
      for (int j = 0; j < one.steps; ++j) {
        centres.push_back(one.trajectory.centre[static_cast<std::size_t>(j)]);
        motion.push_back(ray.dot(centres.back()));
      }
    }
  }
  const double d_trajectory = 2.0 * engine::MinimumEnclosingCircle(centres).radius;
  const engine::ErrorMotion solved = engine::MeasureErrorMotion(motion, options.steps);

  // What the grid misses: a roller's phase is within delta = pi / kGrid of any other, and a
  // curve sum_p c_p cos(o_p u) + s_p sin(o_p u) falls from its extreme in any direction by
  // at most sum_p A_p o_p^2 delta^2 / 2 within delta of it (A_p = sqrt(|c_p|^2 + |s_p|^2),
  // the lobes' amplitudes in the centre from the phasors); a diameter or a range, twice.
  const solvers::PhasorSum sum = linear.Phasors(scene);
  const double delta = std::numbers::pi / kGrid;
  double missed = 0.0;
  for (std::size_t p = 0; p < sum.rates.size(); ++p) {
    if (sum.roller[p] < 0) continue;
    const auto column = static_cast<Eigen::Index>(p);
    const double amplitude = std::hypot(sum.cosine.col(column).head<2>().norm(), sum.sine.col(column).head<2>().norm());
    missed += amplitude * sum.order[p] * sum.order[p] * delta * delta / 2.0;
  }
  const double allowance = closed.error_estimate;
  EXPECT_LE(d_trajectory, every.d_trajectory + allowance);
  EXPECT_GE(d_trajectory, every.d_trajectory - allowance - 2.0 * missed);
  EXPECT_LE(solved.asynchronous, every.error_motion.asynchronous + allowance);
  EXPECT_GE(solved.asynchronous, every.error_motion.asynchronous - allowance - 2.0 * missed);
  EXPECT_NEAR(solved.synchronous, every.error_motion.synchronous, allowance);
  RecordProperty("grid_misses_um", std::to_string(2.0 * missed * 1e6));
  RecordProperty("gap_d_um", std::to_string((every.d_trajectory - d_trajectory) * 1e6));
  RecordProperty("gap_asynchronous_um", std::to_string((every.error_motion.asynchronous - solved.asynchronous) * 1e6));

  // Geared, the same rollers keep their assembled phases: the life is five revolutions'.
  scene.phase_locked_rollers = true;
  const solvers::LifeResult locked = solvers::LinearLife(scene, linear, options, 5);
  ASSERT_EQ(locked.status, solvers::Status::kOk) << locked.message;
  EXPECT_EQ(locked.cycle, 5);
  EXPECT_NEAR(locked.asymptotic->d_trajectory, locked.values.d_trajectory, locked.error_estimate);
  EXPECT_LT(locked.asymptotic->d_trajectory, d_trajectory - allowance);
}

// Phase-locked rollers, one at its nominal size (60.4 = 302/5 turns a revolution: its
// phases repeat after five revolutions, and its fifth-order lobes turn a whole 302 times a
// revolution, so they repeat every revolution) and two drawn (their phases drift through
// every value): the life is the five revolutions of the first with every phase of the
// others. Against the quasistatic rung's successive revolutions, which the union of 512
// comes close to.
TEST(Life, ALockedRollerOfNominalSizeKeepsItsCycleBesideDriftingOnes) {
  engine::Scene scene = testing::CampaignLikeScene();
  const double sizes[] = {-2.2e-6, 0.0, -3.1e-6};
  for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
    engine::Roller& roller = scene.rollers[i];
    std::vector<engine::Harmonic> lobes = roller.outline.harmonics();
    if (sizes[i] == 0.0) lobes.push_back({5, 3e-6, 0.3});
    roller.outline = engine::PolarProfile(roller.outline.radius(), sizes[i], std::move(lobes));
  }
  scene.phase_locked_rollers = true;
  // 256 angles a revolution alias the fifth-order lobe's 302 UPR to 46 UPR in the solved
  // revolutions, which a filter would pass where the closed form, filtering at the true
  // rate, does not: read unfiltered (filtered revolutions against the closed form, at
  // enough angles: FilteredRevolutionsOfACycleAreTheClosedFormsCycle).
  scene.error_motion_filter.cutoff_upr = 0.0;
  solvers::SimulationOptions options;
  options.steps = 256;
  const solvers::LifeResult closed = solvers::LinearLife(scene, solvers::LinearSolver(), options, 1);
  ASSERT_EQ(closed.status, solvers::Status::kOk) << closed.message;
  EXPECT_EQ(closed.cycle, 0) << "the drawn rollers never repeat";
  const solvers::LifeValues& every = *closed.asymptotic;
  constexpr int kRevolutions = 512;
  const solvers::LifeResult solved = solvers::SimulateLife(scene, solvers::QuasistaticSolver(), options, kRevolutions);
  ASSERT_EQ(solved.status, solvers::Status::kOk) << solved.message;
  const double allowance = closed.error_estimate;
  EXPECT_NEAR(solved.values.error_motion.asynchronous, every.error_motion.asynchronous, allowance);
  EXPECT_NEAR(solved.values.error_motion.synchronous, every.error_motion.synchronous, allowance);
  EXPECT_LE(solved.values.d_trajectory, every.d_trajectory + allowance);
  // [m] how far the union may stay inside the envelope: life_envelope_test's kConverged.
  constexpr double kConverged = 1e-6;
  EXPECT_LE(every.d_trajectory - solved.values.d_trajectory, kConverged);
  RecordProperty("gap_d_um", std::to_string((every.d_trajectory - solved.values.d_trajectory) * 1e6));
  RecordProperty("allowance_um", std::to_string(allowance * 1e6));
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
