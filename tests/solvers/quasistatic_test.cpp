#include <gtest/gtest.h>

#include <cmath>

#include "engine/contact.h"
#include "solvers/equilibrium.h"
#include "solvers/quasistatic.h"
#include "solvers/simulation.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

using testing::kDeg;

// Potential energy of the penalty model [J]: contact energy k delta^(e+1) / (e+1) at every
// contact plus the spring energy (k s^2 / 2 - P s) of every spring roller. Its gradient is
// minus the force balance the solver zeroes, so the solver's equilibrium must be its minimum.
double PotentialEnergy(const engine::Scene& scene, const Eigen::Vector2d& centre, const std::vector<double>& travel) {
  double energy = 0.0;
  const double e = scene.contact.exponent;
  for (int i = 0; i < static_cast<int>(scene.rollers.size()); ++i) {
    const engine::Roller& roller = scene.rollers[static_cast<std::size_t>(i)];
    const double s = travel[static_cast<std::size_t>(i)];
    const engine::BodyPose ring_pose{centre, 0.0};
    const engine::BodyPose roller_pose{engine::RollerCentre(scene, i) + s * engine::SpringAxis(scene, i),
                                       engine::RollerBodyAngle(scene, i, 0.0)};
    const engine::Contact c = engine::FindContact(scene.ring.inner, ring_pose, roller.outline, roller_pose);
    const double delta = std::max(-c.gap, 0.0);
    energy += scene.contact.stiffness * std::pow(delta, e + 1.0) / (e + 1.0);
    if (roller.mount == engine::RollerMount::kSpring) {
      energy += 0.5 * roller.spring.stiffness * s * s - roller.spring.preload * s;
    }
  }
  return energy;
}

TEST(QuasistaticPenalty, EquilibriumIsTheMinimumOfThePotentialEnergy) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{3, 0.14e-3, 45.0 * kDeg}, {5, 0.03e-3, 10.0 * kDeg}});
  testing::SetRollerShapes(scene, {{2, 0.014e-3, 30.0 * kDeg}});
  const solvers::Equilibrium eq = solvers::QuasistaticSolver().SolveStatic(scene);
  ASSERT_EQ(eq.status, solvers::Status::kOk) << eq.message;
  const double minimum = PotentialEnergy(scene, eq.centre, eq.travel);
  // Probe along each coordinate and along diagonals by h: the energy must rise by about
  // K h^2 / 2 with K >= the spring stiffness (1334 N/m), i.e. >= 6e-10 J at h = 1 um,
  // far above the round-off of the energy (~1e-3 J * 1e-16).
  constexpr double kProbe = 1e-6;                // [m]
  constexpr double kSmallestRise = 0.5 * 1334.0 * kProbe * kProbe / 2.0;  // half the weakest curvature
  const Eigen::Vector2d directions[] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}, {0.6, 0.8}, {-0.8, 0.6}};
  for (const Eigen::Vector2d& d : directions) {
    EXPECT_GT(PotentialEnergy(scene, eq.centre + kProbe * d, eq.travel) - minimum, kSmallestRise);
  }
  for (double sign : {-1.0, 1.0}) {
    std::vector<double> travel = eq.travel;
    travel[0] += sign * kProbe;
    EXPECT_GT(PotentialEnergy(scene, eq.centre, travel) - minimum, kSmallestRise);
  }
  // The central-difference gradient vanishes. Its truncation error is U''' h^2 / 6 with
  // U''' ~ k e (e-1) delta^(e-2) ~ 6e8 N/m^2 at delta = 0.15 mm (1e-8 N at h = 10 nm), its
  // round-off the gap noise (~1e-17 m) times the contact force (20 N) over h (2e-8 N), and
  // the solver's own residual is below stiffness (2e5 N/m) times 1e-12 m.
  constexpr double kGradientProbe = 1e-8;      // [m]
  constexpr double kGradientTolerance = 1e-6;  // [N]
  for (int axis = 0; axis < 2; ++axis) {
    Eigen::Vector2d d = Eigen::Vector2d::Zero();
    d[axis] = kGradientProbe;
    const double gradient = (PotentialEnergy(scene, eq.centre + d, eq.travel) -
                             PotentialEnergy(scene, eq.centre - d, eq.travel)) / (2.0 * kGradientProbe);
    EXPECT_NEAR(gradient, 0.0, kGradientTolerance);
  }
}

TEST(QuasistaticRigid, PerfectAssemblyRestsAtTheOriginWithForcesFromStatics) {
  const engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kRigid);
  const solvers::Equilibrium eq = solvers::QuasistaticSolver().SolveStatic(scene);
  ASSERT_EQ(eq.status, solvers::Status::kOk) << eq.message;
  constexpr double kPositionTolerance = 1e-12;  // [m] the solver's own tolerance
  constexpr double kForceTolerance = 1e-9;      // [N]
  EXPECT_NEAR(eq.centre.norm(), 0.0, kPositionTolerance);
  // Spring at 90 deg pushes up with P; fixed rollers at 210/330 deg push along their
  // normals: 2 F sin(30 deg) = P, so F = P.
  for (double f : eq.contact_force) EXPECT_NEAR(f, 19.3, kForceTolerance);
}

TEST(QuasistaticFailure, FixedRollersThatCannotHoldTheSpringLiftOff) {
  // The spring at 90 deg pushes the ring up; fixed rollers at 30 and 150 deg can only push
  // it up as well, so force balance needs a pulling contact.
  for (auto law : {engine::ContactLaw::Model::kRigid, engine::ContactLaw::Model::kPenalty}) {
    engine::Scene scene = testing::PaperScene(law);
    scene.rollers[1].angle = 30.0 * kDeg;
    scene.rollers[2].angle = 150.0 * kDeg;
    const solvers::Trajectory path = solvers::QuasistaticSolver().SolveRevolution(scene, 36);
    EXPECT_EQ(path.status, law == engine::ContactLaw::Model::kRigid ? solvers::Status::kLiftOff
                                                                     : path.status);
    EXPECT_NE(path.status, solvers::Status::kOk);
    EXPECT_FALSE(path.message.empty());
    EXPECT_TRUE(path.centre.empty());
  }
}

// A fourth roller the ring never reaches leaves it on the other three: the same path as
// without it, and no force on it at any angle (docs/model.md §7, "Contacts that open").
TEST(QuasistaticRevolution, ARedundantRollerThatNeverTouchesLeavesTheRingOnTheOthers) {
  engine::Scene three = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(three, {{3, 0.05e-3, 45.0 * kDeg}});
  engine::Scene four = three;
  engine::Roller extra = testing::PaperRoller("extra", 270.0, false);
  extra.radial_offset = -0.5e-3;  // mounted 0.5 mm too far in: the ring never reaches it
  four.rollers.push_back(extra);
  const solvers::Trajectory with = solvers::QuasistaticSolver().SolveRevolution(four, 36);
  const solvers::Trajectory without = solvers::QuasistaticSolver().SolveRevolution(three, 36);
  ASSERT_EQ(with.status, solvers::Status::kOk) << with.message;
  ASSERT_EQ(without.status, solvers::Status::kOk) << without.message;
  const double tolerance = 2.0 * solvers::QuasistaticOptions{}.position_tolerance;
  for (std::size_t k = 0; k < with.psi.size(); ++k) {
    EXPECT_LT((with.centre[k] - without.centre[k]).norm(), tolerance) << k;
    EXPECT_EQ(with.contact_force[k * 4 + 3], 0.0) << k;
  }
}

TEST(QuasistaticFailure, RigidContactWithThreeFixedRollersIsStaticallyIndeterminate) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kRigid);
  scene.rollers.push_back(testing::PaperRoller("extra", 270.0, false));
  const solvers::Trajectory path = solvers::QuasistaticSolver().SolveRevolution(scene, 36);
  EXPECT_EQ(path.status, solvers::Status::kStaticallyIndeterminate);
}

TEST(QuasistaticFailure, NonConvexRingIsAStatusNotANumber) {
  engine::Scene scene = testing::PaperScene();
  // (400 - 1) C / R = 1.98 > 1: inward bumps, yet the rollers still fit (1.5 mm < r_b).
  testing::SetRing(scene, {{20, 1.5e-3, 0.0}});
  const solvers::Trajectory path = solvers::QuasistaticSolver().SolveRevolution(scene, 36);
  EXPECT_EQ(path.status, solvers::Status::kRingNotConvex);
  EXPECT_TRUE(path.centre.empty());
}

TEST(QuasistaticFailure, ARollerLargerThanTheBoreDoesNotFit) {
  engine::Scene scene = testing::PaperScene();
  scene.rollers[1].outline = engine::PolarProfile(0.35, 0.0, {});
  const solvers::Trajectory path = solvers::QuasistaticSolver().SolveRevolution(scene, 36);
  EXPECT_EQ(path.status, solvers::Status::kRollerDoesNotFit);
}

TEST(QuasistaticFailure, SpringTravelBeyondItsLimitMeansTheAssemblyCannotClose) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kRigid);
  testing::SetRing(scene, {{3, 0.14e-3, 45.0 * kDeg}});
  scene.rollers[0].spring.travel_limit = 0.1e-3;  // the order-3 lobe needs up to ~0.42 mm
  const solvers::Trajectory path = solvers::QuasistaticSolver().SolveRevolution(scene, 360);
  EXPECT_EQ(path.status, solvers::Status::kRollerDoesNotFit) << path.message;
  EXPECT_NE(path.message.find("travel"), std::string::npos) << path.message;
}

// Largest coordinate difference between two paths over the same angles [m].
double LargestCentreDifference(const solvers::Trajectory& a, const solvers::Trajectory& b) {
  double largest = 0.0;
  for (std::size_t k = 0; k < a.centre.size() && k < b.centre.size(); ++k) {
    largest = std::max(largest, (a.centre[k] - b.centre[k]).cwiseAbs().maxCoeff());
  }
  return largest;
}

// An angle is accepted after one Newton update when the measured quadratic convergence
// predicts the next update below the position tolerance. The claim to check: every
// point of the path is within that tolerance of the same path converged 100 times
// tighter, for both contact laws, bore harmonics up to order 9 and lobed rollers; and
// the shortcut is taken (about one update per angle), or the claim is vacuous. Both at
// the default 1 pm and at a campaign's 10 nm (1 % of a 1 um sampling budget).
TEST(QuasistaticRevolution, OneUpdatePerAngleStaysWithinThePositionTolerance) {
  const solvers::QuasistaticOptions defaults;
  solvers::QuasistaticOptions campaign = defaults;
  campaign.position_tolerance = 1e-8;
  campaign.force_tolerance = 1e-5;
  for (const solvers::QuasistaticOptions& options : {defaults, campaign}) {
    for (const auto law : {engine::ContactLaw::Model::kPenalty, engine::ContactLaw::Model::kRigid}) {
      engine::Scene scene = testing::PaperScene(law);
      std::vector<engine::Harmonic> ring;
      for (int n = 2; n <= 9; ++n) ring.push_back({n, 0.14e-3 / (n - 1), 0.3 * n});
      testing::SetRing(scene, ring);
      testing::SetRollerShapes(scene, {{2, 0.01e-3, 30.0 * kDeg}});
      solvers::QuasistaticOptions tight = options;
      tight.position_tolerance = options.position_tolerance / 100.0;
      tight.force_tolerance = options.force_tolerance / 100.0;
      // The automatic step count, and a coarse one where the predictor is poor (the
      // roller's lobes pass 120 times a revolution: 17 angles per lobe).
      const int automatic = solvers::ChooseSteps(scene, {});
      for (const int steps : {automatic, 2000}) {
        SCOPED_TRACE(::testing::Message() << "tolerance " << options.position_tolerance << " m, " << steps << " steps, "
                                          << (law == engine::ContactLaw::Model::kRigid ? "rigid" : "penalty"));
        const solvers::Trajectory path = solvers::QuasistaticSolver(options).SolveRevolution(scene, steps);
        const solvers::Trajectory reference = solvers::QuasistaticSolver(tight).SolveRevolution(scene, steps);
        ASSERT_EQ(path.status, solvers::Status::kOk) << path.message;
        ASSERT_EQ(reference.status, solvers::Status::kOk) << reference.message;
        ASSERT_EQ(path.centre.size(), reference.centre.size());
        EXPECT_LE(LargestCentreDifference(path, reference), options.position_tolerance);
        // Most angles take the shortcut. At 1 pm how many do depends on the step count
        // (round-off in the measured convergence: 1.06 updates an angle at 7,732 angles,
        // 1.32 at the automatic rule's 7,776, 1.68 at 8,000), so the bound only says most.
        if (steps == automatic) {
          EXPECT_LT(path.total_iterations, 1.5 * steps);
        }
      }
    }
  }
}

// A campaign's sample resolved for a 1 um sampling budget: the rollers' eight lobe orders
// pass up to 480 times a revolution, about 7 angles per period, too fast for the
// predictor (its first update is ~1e-7 m). At 1 pm every angle then takes a second
// update; at the campaign's 10 nm the first one is certified, and the path stays within
// the tolerance of one converged 100 times tighter.
TEST(QuasistaticRevolution, ACampaignsToleranceTakesOneUpdatePerAngleWhereTheLobesOutrunThePredictor) {
  const engine::Scene scene = testing::CampaignLikeScene();
  solvers::SimulationOptions budget;
  budget.path_tolerance = 1e-6;
  const int steps = solvers::ChooseSteps(scene, budget);
  solvers::QuasistaticOptions campaign;
  campaign.position_tolerance = 1e-8;
  solvers::QuasistaticOptions tight;
  tight.position_tolerance = 1e-10;
  const solvers::Trajectory path = solvers::QuasistaticSolver(campaign).SolveRevolution(scene, steps);
  const solvers::Trajectory reference = solvers::QuasistaticSolver(tight).SolveRevolution(scene, steps);
  const solvers::Trajectory exact = solvers::QuasistaticSolver().SolveRevolution(scene, steps);
  ASSERT_EQ(path.status, solvers::Status::kOk) << path.message;
  ASSERT_EQ(reference.status, solvers::Status::kOk) << reference.message;
  ASSERT_EQ(exact.status, solvers::Status::kOk) << exact.message;
  ASSERT_EQ(path.centre.size(), reference.centre.size());
  EXPECT_LE(LargestCentreDifference(path, reference), campaign.position_tolerance);
  EXPECT_LT(path.total_iterations, 1.2 * steps) << steps << " steps";
  EXPECT_GT(exact.total_iterations, 1.8 * steps) << steps << " steps: the predictor follows the lobes after all";
}

// A scene's static equilibrium continues the error-free assembly's with the joint Newton
// iteration of a revolution; it must land where a search from scratch lands, within the
// position tolerance, for both contact laws, small and large ring errors, lobed rollers
// and position errors.
TEST(QuasistaticStatic, ContinuedFromTheErrorFreeAssemblyItMatchesASearchFromScratch) {
  const solvers::QuasistaticOptions options;
  for (const auto law : {engine::ContactLaw::Model::kPenalty, engine::ContactLaw::Model::kRigid}) {
    for (const double amplitude : {0.01e-3, 0.14e-3, 0.7e-3}) {
      engine::Scene scene = testing::PaperScene(law);
      testing::SetRing(scene, {{2, amplitude, 45.0 * kDeg}, {5, 0.2 * amplitude, 10.0 * kDeg}});
      testing::SetRollerShapes(scene, {{3, 2e-6, 0.4}});
      scene.rollers[2].radial_offset = 20e-6;
      SCOPED_TRACE(::testing::Message() << (law == engine::ContactLaw::Model::kRigid ? "rigid" : "penalty") << ", "
                                        << amplitude * 1e3 << " mm");
      const solvers::Equilibrium continued = solvers::QuasistaticSolver(options).SolveStatic(scene);
      const solvers::EquilibriumSystem system(scene);
      Eigen::VectorXd x;
      std::vector<solvers::TrackedContact> contacts;
      const solvers::Equilibrium searched = solvers::QuasistaticSolver(options).SolveStatic(system, x, contacts);
      ASSERT_EQ(continued.status, solvers::Status::kOk) << continued.message;
      ASSERT_EQ(searched.status, solvers::Status::kOk) << searched.message;
      EXPECT_LE((continued.centre - searched.centre).norm(), options.position_tolerance);
      for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
        EXPECT_LE(std::abs(continued.travel[i] - searched.travel[i]), options.position_tolerance);
        // Under the penalty law a force follows its gap: the article's contacts are about
        // 2e5 N/m stiff, so 1 pm of position is 2e-7 N.
        EXPECT_NEAR(continued.contact_force[i], searched.contact_force[i], 2e5 * options.position_tolerance + options.force_tolerance);
      }
    }
  }
}

// What a solver kept from earlier scenes only saves work: a scene's static equilibrium
// and path are the same bits whether the solver is new, last saw another error-free
// assembly, or last saw the same one with other errors. Campaigns rely on it for results
// that do not depend on the order samples are computed in.
TEST(QuasistaticStatic, AResultDoesNotDependOnWhatTheSolverSolvedBefore) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{3, 0.05e-3, 20.0 * kDeg}});
  engine::Scene other_nominal = scene;
  other_nominal.rollers[0].spring.preload = 25.0;
  engine::Scene same_nominal = scene;
  testing::SetRing(same_nominal, {{4, 0.08e-3, 0.0}});
  const solvers::Trajectory fresh = solvers::QuasistaticSolver().SolveRevolution(scene, 90);
  for (const engine::Scene* before : {&other_nominal, &same_nominal, &scene}) {
    const solvers::QuasistaticSolver solver;
    solver.SolveRevolution(*before, 90);
    const solvers::Trajectory again = solver.SolveRevolution(scene, 90);
    ASSERT_EQ(again.status, solvers::Status::kOk) << again.message;
    EXPECT_EQ(again.initial.centre, fresh.initial.centre);
    EXPECT_EQ(again.initial.contact_force, fresh.initial.contact_force);
    EXPECT_EQ(again.centre, fresh.centre);
    EXPECT_EQ(again.contact_force, fresh.contact_force);
  }
}

}  // namespace
}  // namespace ringtol
