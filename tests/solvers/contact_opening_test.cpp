// Contacts that open (solvers/validity.h, RollerLosingSupport): a roller beyond the ones
// the ring needs may leave the bore and come back, and the exact rungs follow it; the
// linear rung, whose path assumes every contact stays closed, refuses; on three rollers
// any opening is still lift-off.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gmock/gmock.h>

#include "engine/motion_law.h"
#include "solvers/auto.h"
#include "solvers/dynamic.h"
#include "solvers/linear.h"
#include "solvers/quasistatic.h"
#include "solvers/simulation.h"
#include "solvers/validity.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

using ::testing::HasSubstr;
using testing::kDeg;

// The article's assembly with a third fixed roller at 250 deg and an order-2 bore of
// `amplitude` [m]. fixed_a (210 deg) then carries 3.5 N on a round bore, a penetration of
// about 50 um at the article's law: from an amplitude near that on the bore's recess
// passes it by for part of each half-revolution, and the ring rests on fixed_b and fixed_c,
// which hold it on their own (up to 120 um fixed_c keeps 3 N or more).
engine::Scene FourRollers(double amplitude) {
  engine::Scene scene = testing::PaperScene();
  scene.rollers.push_back(testing::PaperRoller("fixed_c", 250.0, false));
  testing::SetRing(scene, {{2, amplitude, 30.0 * kDeg}});
  return scene;
}

constexpr std::size_t kOpening = 1;  // fixed_a

// Share of the revolution's angles at which roller i carries nothing.
double OpenShare(const solvers::Trajectory& path, std::size_t i, std::size_t rollers) {
  std::size_t open = 0;
  for (std::size_t k = 0; k < path.psi.size(); ++k) open += path.contact_force[k * rollers + i] > 0.0 ? 0U : 1U;
  return static_cast<double>(open) / static_cast<double>(path.psi.size());
}

solvers::SimulationResult Simulated(const engine::Scene& scene, const solvers::Solver& solver, int steps) {
  solvers::SimulationOptions options;
  options.steps = steps;
  return solvers::Simulate(scene, solver, options);
}

// A sweep of the quasistatic path over the bore's amplitude [from, to] in `step`s [m] on
// scene_of(amplitude), each path handed to `visit`: every one ok, D_trajectory continuous
// in the amplitude (the centre cannot move by more than the bore does: D changes by at most
// 4 times the amplitude's change, the rigid three-roller gain of an order that is a
// multiple of 3, the largest any order has, plus the sampling's bound) and converged in the
// steps (720 against 2880 within the sampling bound).
template <typename SceneOf, typename Visit>
void ExpectWellPosedAcrossAmplitudes(SceneOf scene_of, double from, double to, double step, Visit visit) {
  const solvers::QuasistaticSolver solver;
  double previous = -1.0;
  for (double amplitude = from; amplitude <= to; amplitude += step) {
    const engine::Scene scene = scene_of(amplitude);
    const solvers::SimulationResult coarse = Simulated(scene, solver, 720);
    ASSERT_EQ(coarse.status, solvers::Status::kOk) << amplitude * 1e6 << " um: " << coarse.message;
    visit(coarse, scene);
    if (previous >= 0.0) {
      EXPECT_LE(std::abs(coarse.d_trajectory - previous), 4.0 * step + 2e-7) << amplitude * 1e6 << " um";
    }
    previous = coarse.d_trajectory;
    const solvers::SimulationResult fine = Simulated(scene, solver, 2880);
    ASSERT_EQ(fine.status, solvers::Status::kOk) << fine.message;
    EXPECT_NEAR(coarse.d_trajectory, fine.d_trajectory, solvers::SamplingErrorBoundsAt(scene, 720).d_trajectory + 2e-12)
        << amplitude * 1e6 << " um";
  }
}

// The life reads the linear rung's phasors, which assume every contact closed: where a
// redundant roller leaves the bore the sample keeps its revolution's outputs and says why
// it has no life values; where none leaves, the life is there.
TEST(ContactOpening, CostsTheLifeValuesNotTheSample) {
  const solvers::QuasistaticSolver quasistatic;
  solvers::SimulationOptions options;
  options.steps = 360;
  options.life = true;
  const solvers::SimulationResult opened = solvers::Simulate(FourRollers(100e-6), quasistatic, options);
  ASSERT_EQ(opened.status, solvers::Status::kOk) << opened.message;
  EXPECT_GT(opened.contact_force[kOpening].off_bore, 0.2);
  EXPECT_FALSE(opened.life.has_value());
  EXPECT_THAT(opened.life_missing, HasSubstr("roller fixed_a leaves the bore"));
  const solvers::SimulationResult closed = solvers::Simulate(FourRollers(20e-6), quasistatic, options);
  ASSERT_EQ(closed.status, solvers::Status::kOk) << closed.message;
  EXPECT_EQ(closed.contact_force[kOpening].off_bore, 0.0);
  EXPECT_TRUE(closed.life.has_value());
  EXPECT_TRUE(closed.life_missing.empty());
}

TEST(SupportRule, OnThreeRollersEveryContactIsNeeded) {
  const engine::Scene scene = testing::PaperScene();  // spring, fixed_a, fixed_b
  EXPECT_EQ(solvers::RollerLosingSupport(scene, std::vector{19.0, 10.0, 10.0}), -1);
  EXPECT_EQ(solvers::RollerLosingSupport(scene, std::vector{19.0, 10.0, 0.0}), 2);
  EXPECT_EQ(solvers::RollerLosingSupport(scene, std::vector{0.0, 10.0, 10.0}), 0);
  EXPECT_EQ(solvers::SupportForce(scene, std::vector{19.0, 7.0, 10.0}), 7.0);
}

// Beyond three rollers, a spring presses the ring onto whichever fixed rollers touch: one
// is support enough where an equilibrium exists on it (the exact rungs' equations decide
// that), none is not, and a spring roller off the bore never is.
TEST(SupportRule, BeyondThreeRollersASpringPressesTheRingOntoAnyFixedRoller) {
  const engine::Scene scene = FourRollers(0.0);  // spring, fixed_a, fixed_b, fixed_c
  EXPECT_EQ(solvers::RollerLosingSupport(scene, std::vector{19.0, 10.0, 10.0, 0.0}), -1);
  EXPECT_EQ(solvers::RollerLosingSupport(scene, std::vector{19.0, 0.0, 10.0, 10.0}), -1);
  EXPECT_EQ(solvers::RollerLosingSupport(scene, std::vector{19.0, 0.0, 10.0, 0.0}), -1);
  EXPECT_EQ(solvers::RollerLosingSupport(scene, std::vector{19.0, 0.0, 0.0, 0.0}), 1);
  EXPECT_EQ(solvers::RollerLosingSupport(scene, std::vector{0.0, 10.0, 10.0, 10.0}), 0);
  // The largest fixed force: the ring keeps a fixed roller until it is gone.
  EXPECT_EQ(solvers::SupportForce(scene, std::vector{19.0, 3.0, 10.0, 0.0}), 10.0);
  EXPECT_EQ(solvers::SupportForce(scene, std::vector{2.0, 3.0, 10.0, 0.0}), 2.0);
}

// Three fixed rollers at 210, 270 and 330 deg under the article's spring at 90 deg, and an
// order-2 bore of `amplitude` [m]: the middle roller, opposite the spring, carries most of
// its push, and the outer ones a few newtons on a round bore.
engine::Scene SymmetricFourRollers(double amplitude) {
  engine::Scene scene = testing::PaperScene();
  scene.rollers.push_back(testing::PaperRoller("fixed_c", 270.0, false));
  testing::SetRing(scene, {{2, amplitude, 30.0 * kDeg}});
  return scene;
}

// On the symmetric layout both outer rollers leave the bore at once where the bore's form
// lets the ring settle onto the middle roller alone: the spring presses it there, and the
// contacts' curvature holds it sideways. The quasistatic rung follows the path through that
// state (it was lift_off under a rule that asked for two fixed rollers), continuous in the
// amplitude and converged in the steps.
TEST(ContactOpening, OnASymmetricLayoutTheRingMayRestOnTheMiddleRollerAlone) {
  bool alone_seen = false;
  ExpectWellPosedAcrossAmplitudes(SymmetricFourRollers, 40e-6, 120e-6, 10e-6,
                                  [&](const solvers::SimulationResult& result, const engine::Scene&) {
                                    const solvers::Trajectory& path = result.trajectory;
                                    for (std::size_t k = 0; k < path.psi.size(); ++k) {
                                      const double* force = &path.contact_force[k * 4];
                                      if (force[1] > 0.0 || force[2] > 0.0) continue;
                                      alone_seen = true;
                                      EXPECT_GT(force[3], 0.0);
                                      EXPECT_GT(force[0], 0.0);
                                    }
                                  });
  EXPECT_TRUE(alone_seen) << "the sweep must reach the middle roller alone";
}

TEST(SupportRule, WithoutSpringsThreeFixedRollersAreNeeded) {
  const engine::Scene scene = testing::EquallySpacedScene(5, 0, 2e-6, 1e8);
  EXPECT_EQ(solvers::RollerLosingSupport(scene, std::vector{1.0, 0.0, 1.0, 0.0, 1.0}), -1);
  EXPECT_EQ(solvers::RollerLosingSupport(scene, std::vector{1.0, 0.0, 0.0, 0.0, 1.0}), 1);
  EXPECT_EQ(solvers::SupportForce(scene, std::vector{4.0, 0.0, 2.0, 0.0, 3.0}), 2.0);
}

TEST(ContactOpening, TheQuasistaticRungFollowsARedundantRollerOffTheBoreAndBack) {
  const engine::Scene scene = FourRollers(100e-6);
  const solvers::SimulationResult result = Simulated(scene, solvers::QuasistaticSolver(), 720);
  ASSERT_EQ(result.status, solvers::Status::kOk) << result.message;
  const double open = OpenShare(result.trajectory, kOpening, scene.rollers.size());
  EXPECT_GT(open, 0.05) << "the scene must open the middle roller's contact";
  EXPECT_LT(open, 0.95);
  EXPECT_EQ(result.contact_force[kOpening].min, 0.0);
  EXPECT_GT(result.contact_force[kOpening].max, 0.0);
  // The result states the share: every angle but the one closing the revolution, once.
  EXPECT_NEAR(result.contact_force[kOpening].off_bore, open, 2.0 / 720.0);
  EXPECT_EQ(result.contact_force[3].off_bore, 0.0);
  EXPECT_EQ(OpenShare(result.trajectory, 2, scene.rollers.size()), 0.0);
  EXPECT_EQ(OpenShare(result.trajectory, 3, scene.rollers.size()), 0.0);
}

// Well-posed through the contact change: D_trajectory is continuous in the amplitude from
// below the opening (every contact closed) to well past it, and converged in the steps.
TEST(ContactOpening, DTrajectoryIsContinuousInTheAmplitudeAcrossTheOpeningAndConvergedInTheSteps) {
  bool closed_seen = false;
  bool open_seen = false;
  ExpectWellPosedAcrossAmplitudes(FourRollers, 20e-6, 120e-6, 5e-6,
                                  [&](const solvers::SimulationResult& result, const engine::Scene& scene) {
                                    const bool open = OpenShare(result.trajectory, kOpening, scene.rollers.size()) > 0.0;
                                    closed_seen = closed_seen || !open;
                                    open_seen = open_seen || open;
                                  });
  EXPECT_TRUE(closed_seen && open_seen) << "the sweep must cross the opening";
}

// The refined and spectral angles interpolate between evaluated angles on the linear path,
// whose contacts stay closed: through an opening they must give the dense angles' values
// (within the sampling budget they are held to), not the linear model's.
TEST(ContactOpening, RefinedAndSpectralAnglesGiveTheDenseValuesThroughTheOpening) {
  const engine::Scene scene = FourRollers(100e-6);
  solvers::SimulationOptions dense;
  dense.path_tolerance = 1e-6;
  solvers::AutoOptions automatic;
  automatic.budget = solvers::kAutoShareOfPathTolerance * dense.path_tolerance;
  const solvers::QuasistaticSolver quasistatic;
  const solvers::AutoSolver auto_rung(automatic);
  for (const solvers::Solver* solver : {static_cast<const solvers::Solver*>(&quasistatic),
                                        static_cast<const solvers::Solver*>(&auto_rung)}) {
    const solvers::SimulationResult reference = solvers::Simulate(scene, *solver, dense);
    ASSERT_EQ(reference.status, solvers::Status::kOk) << reference.message;
    for (const solvers::AngleMode mode : {solvers::AngleMode::kRefined, solvers::AngleMode::kSpectral}) {
      solvers::SimulationOptions options = dense;
      options.angles = mode;
      const solvers::SimulationResult result = solvers::Simulate(scene, *solver, options);
      ASSERT_EQ(result.status, solvers::Status::kOk) << result.message;
      EXPECT_NEAR(result.d_trajectory, reference.d_trajectory, dense.path_tolerance)
          << solver->name() << ", " << NameOf(solvers::kAngleModeNames, mode);
      EXPECT_NEAR(result.runout, reference.runout, dense.path_tolerance)
          << solver->name() << ", " << NameOf(solvers::kAngleModeNames, mode);
    }
  }
}

TEST(ContactOpening, TheLinearRungRefusesWhereAContactOpensAndAutoGivesTheExactPath) {
  const engine::Scene scene = FourRollers(100e-6);
  const solvers::SimulationResult linear = Simulated(scene, solvers::LinearSolver(), 720);
  EXPECT_EQ(linear.status, solvers::Status::kBeyondLinearRange);
  EXPECT_THAT(linear.message, HasSubstr("fixed_a leaves the bore"));
  const solvers::SimulationResult exact = Simulated(scene, solvers::QuasistaticSolver(), 720);
  solvers::AutoOptions options;
  options.budget = 0.5e-6;
  const solvers::SimulationResult automatic = Simulated(scene, solvers::AutoSolver(options), 720);
  ASSERT_EQ(automatic.status, solvers::Status::kOk) << automatic.message;
  ASSERT_EQ(automatic.trajectory.rung, solvers::Rung::kQuasistatic)
      << "the ring's inertia at 270 deg/s is far below the 2 fixed rollers' least force";
  EXPECT_EQ(automatic.d_trajectory, exact.d_trajectory);
}

// The dynamic rung lets the redundant contact open and close, and its path approaches the
// quasistatic one through the opening as the rate falls: at a slow steady rate the
// damping forces vanish with the velocities (DynamicSolver.SlowRotationApproachesTheQuasi-
// staticPath in dynamic_test.cpp gives the estimate, ~1 um at 0.4 deg/s), so the
// difference is first order in the rate: halving the rate about halves it.
TEST(ContactOpening, TheDynamicRungFollowsTheOpeningAndApproachesTheQuasistaticPathAsTheRateFalls) {
  constexpr int kSteps = 72;
  constexpr double kLagBound = 2e-6;        // [m] twice the estimate at 0.4 deg/s
  constexpr double kFirstOrderSlack = 0.1;  // the ratio 0.5 up to the O(rate^2) part
  engine::Scene scene = FourRollers(100e-6);
  scene.dynamics.friction = false;
  scene.dynamics.rolling_without_slip = true;
  const solvers::Trajectory quasistatic = solvers::QuasistaticSolver().SolveRevolution(scene, kSteps);
  ASSERT_EQ(quasistatic.status, solvers::Status::kOk) << quasistatic.message;
  solvers::DynamicOptions options;
  options.steady_revolution = 0;
  double previous = 0.0;
  for (const double rate_deg : {0.4, 0.2}) {
    scene.motion = engine::ArticleLaw(12.0, rate_deg * kDeg, 1.2);
    const solvers::Trajectory path = solvers::DynamicSolver(options).SolveRevolution(scene, kSteps);
    ASSERT_EQ(path.status, solvers::Status::kOk) << path.message;
    EXPECT_GT(OpenShare(path, kOpening, scene.rollers.size()), 0.05) << rate_deg << " deg/s";
    // From 30 degrees on: the start from rest is a transient of its own.
    double largest = 0.0;
    for (std::size_t k = 6; k < path.centre.size(); ++k) {
      largest = std::max(largest, (path.centre[k] - quasistatic.centre[k]).norm());
    }
    EXPECT_LT(largest, kLagBound) << rate_deg << " deg/s";
    if (previous > 0.0) {
      EXPECT_NEAR(largest / previous, 0.5, kFirstOrderSlack) << rate_deg << " deg/s";
    }
    previous = largest;
  }
}

// Why a lightly loaded roller opens at 270 deg/s where the time-free path keeps it closed
// (docs/model.md §7, "Contacts that open"): the contact damping of the article's law, not
// the step to speed nor friction. At 40 um the quasistatic fixed_a keeps 0.35 N; a
// separating contact's damping force c dDelta/dt (c_max = 1e5 N s/m from 1 um of
// penetration, dDelta/dt up to n omega A = 0.4 mm/s) cancels it. A smooth ramp to the same
// speed opens it just as the step does; a hundredth of the damping keeps it closed and
// gives the quasistatic path.
TEST(ContactOpening, AtSpeedTheContactDampingNotTheStepOpensALightRollerEarly) {
  constexpr int kSteps = 720;
  const engine::Scene scene = FourRollers(40e-6);
  const solvers::SimulationResult exact = Simulated(scene, solvers::QuasistaticSolver(), kSteps);
  ASSERT_EQ(exact.status, solvers::Status::kOk) << exact.message;
  ASSERT_GT(exact.contact_force[kOpening].min, 0.0);
  const auto dynamic = [&](const engine::MotionLaw& law, double max_damping) {
    engine::Scene turning = scene;
    turning.motion = law;
    turning.contact.max_damping = max_damping;
    return Simulated(turning, solvers::DynamicSolver(), kSteps);
  };
  const solvers::SimulationResult step = dynamic(engine::ArticleLaw(), 1e5);
  const solvers::SimulationResult ramp = dynamic(engine::TestBenchLaw(), 1e5);
  const solvers::SimulationResult light = dynamic(engine::ArticleLaw(), 1e3);
  for (const solvers::SimulationResult* run : {&step, &ramp, &light}) {
    ASSERT_EQ(run->status, solvers::Status::kOk) << run->message;
  }
  EXPECT_GT(OpenShare(step.trajectory, kOpening, scene.rollers.size()), 0.2);
  EXPECT_GT(step.d_trajectory, exact.d_trajectory + 20e-6);
  EXPECT_NEAR(ramp.d_trajectory, step.d_trajectory, 2e-6);
  EXPECT_EQ(OpenShare(light.trajectory, kOpening, scene.rollers.size()), 0.0);
  EXPECT_NEAR(light.d_trajectory, exact.d_trajectory, 1e-6);
}

TEST(ContactOpening, OnThreeRollersAnOpeningIsStillLiftOffOnEveryRung) {
  engine::Scene scene = testing::PaperScene();
  scene.rollers[0].spring.preload = 0.2;  // too weak to hold the ring on order 3 at 0.15 mm
  testing::SetRing(scene, {{3, 150e-6, 0.0}});
  for (const solvers::Rung rung : {solvers::Rung::kLinear, solvers::Rung::kQuasistatic}) {
    solvers::SolverSettings settings;
    settings.rung = rung;
    EXPECT_EQ(Simulated(scene, *solvers::MakeSolver(settings), 360).status, solvers::Status::kLiftOff)
        << NameOf(solvers::kRungNames, rung);
  }
}

}  // namespace
}  // namespace ringtol
