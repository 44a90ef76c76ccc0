#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "solvers/dynamic.h"
#include "solvers/quasistatic.h"
#include "solvers/simulation.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

using testing::kDeg;

solvers::DynamicOptions FirstRevolutionOnly() {
  solvers::DynamicOptions options;
  options.steady_revolution = 0;
  return options;
}

// The article's start: centred, settling under the preload while the law holds the ring.
solvers::DynamicOptions ArticleStart(solvers::DynamicOptions options = {}) {
  options.start = solvers::DynamicStart::kArticleSettle;
  return options;
}

double LargestDistance(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b,
                       std::size_t from = 0) {
  double largest = 0.0;
  for (std::size_t k = from; k < std::min(a.size(), b.size()); ++k) largest = std::max(largest, (a[k] - b[k]).norm());
  return largest;
}

// The heavily damped contacts (c_max = 1e5 N s/m against a linearised stiffness of about
// 1.9e5 N/m) make the ring creep to rest with a time constant near c / k = 0.5 s. After
// 12 s of rest the remaining offset is e^-24 of the initial one (~0.2 mm): far below 1 nm,
// and the forces then carry no damping part.
TEST(DynamicSolver, SettlesToTheQuasistaticPenaltyEquilibrium) {
  constexpr double kCentreTolerance = 1e-9;       // [m] e^-24 * 0.2 mm, plus integration error
  constexpr double kForceRelativeTolerance = 1e-5;  // [-] k delta^1.5 with delta known to 1e-9 m of 1.5e-4 m
  for (const bool friction : {false, true}) {
    engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
    testing::SetRing(scene, {{3, 0.1e-3, 20.0 * kDeg}});
    scene.motion = engine::ArticleLaw(12.0);
    scene.dynamics.friction = friction;
    scene.dynamics.rolling_without_slip = !friction;
    solvers::DynamicOptions options = ArticleStart(FirstRevolutionOnly());
    options.relative_tolerance = 1e-9;  // absolute 1e-12 m: integration error far below the bound
    const solvers::Equilibrium settled = solvers::DynamicSolver(options).SolveStatic(scene);
    const solvers::Equilibrium reference = solvers::QuasistaticSolver().SolveStatic(scene);
    ASSERT_EQ(settled.status, solvers::Status::kOk) << settled.message;
    ASSERT_EQ(reference.status, solvers::Status::kOk) << reference.message;
    EXPECT_LT((settled.centre - reference.centre).norm(), kCentreTolerance) << "friction " << friction;
    for (std::size_t i = 0; i < reference.contact_force.size(); ++i) {
      EXPECT_NEAR(settled.contact_force[i], reference.contact_force[i],
                  kForceRelativeTolerance * reference.contact_force[i])
          << "roller " << i << " friction " << friction;
    }
  }
}

// At a slow steady rate the damping forces vanish with the velocities, and the dynamic
// path approaches the quasistatic one. The lag is about the creep time constant times the
// centre's speed: tau * rate * |dx/dpsi| ~ 0.5 s * 0.4 deg/s * 0.3 mm/rad ~ 1 um; the
// inertial force m x'' is 1e-6 of that. So the difference is first order in the rate:
// halving the rate must about halve it.
TEST(DynamicSolver, SlowRotationApproachesTheQuasistaticPath) {
  constexpr double kLagBound = 2e-6;        // [m] twice the estimate above at 0.4 deg/s
  constexpr double kFirstOrderSlack = 0.1;  // the ratio 0.5 up to the O(rate^2) part
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{3, 0.1e-3, 20.0 * kDeg}});
  scene.dynamics.friction = false;
  scene.dynamics.rolling_without_slip = true;
  const solvers::Trajectory quasistatic = solvers::QuasistaticSolver().SolveRevolution(scene, 72);
  ASSERT_EQ(quasistatic.status, solvers::Status::kOk) << quasistatic.message;
  double previous = 0.0;
  for (const double rate_deg : {0.4, 0.2}) {
    scene.motion = engine::ArticleLaw(12.0, rate_deg * kDeg, 1.2);
    const solvers::Trajectory path = solvers::DynamicSolver(FirstRevolutionOnly()).SolveRevolution(scene, 72);
    ASSERT_EQ(path.status, solvers::Status::kOk) << path.message;
    // From 30 degrees on: the start from rest is a transient of its own.
    const double largest = LargestDistance(path.centre, quasistatic.centre, 6);
    EXPECT_LT(largest, kLagBound) << rate_deg << " deg/s";
    if (previous > 0.0) {
      EXPECT_NEAR(largest / previous, 0.5, kFirstOrderSlack) << rate_deg << " deg/s";
    }
    previous = largest;
  }
}

// Round rollers need no torque once they roll, so at steady speed friction only keeps
// them rolling and the full model must give the path of the model that imposes rolling,
// to within the slip's effect on the spin phase (none: round rollers have no phase).
TEST(DynamicSolver, FrictionOnRoundRollersGivesTheRollingWithoutSlipPath) {
  constexpr double kAgreement = 0.05e-6;  // [m] integration tolerance 1e-11 m grown over ~2000 steps
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{2, 0.14e-3, 45.0 * kDeg}});
  const solvers::Trajectory full = solvers::DynamicSolver(FirstRevolutionOnly()).SolveRevolution(scene, 90);
  scene.dynamics.friction = false;
  scene.dynamics.rolling_without_slip = true;
  const solvers::Trajectory rolling = solvers::DynamicSolver(FirstRevolutionOnly()).SolveRevolution(scene, 90);
  ASSERT_EQ(full.status, solvers::Status::kOk) << full.message;
  ASSERT_EQ(rolling.status, solvers::Status::kOk) << rolling.message;
  // After the first 8 degrees: the rollers spin up within milliseconds of the step.
  EXPECT_LT(LargestDistance(full.centre, rolling.centre, 2), kAgreement);
}

// A spring roller of 2.5 g has a natural frequency of kHz on its contact; at 270 deg/s
// the path excites it at tens of Hz, so dropping its mass changes the path by the
// quasi-static inertial share m a / k_contact: 2.5e-3 kg * ~1 m/s^2 / 1.9e5 N/m ~ 1e-8 m.
// Both start at rest at the quasistatic equilibrium, which does not depend on the mass.
TEST(DynamicSolver, MasslessSpringRollerChangesThePathByItsInertialShareOnly) {
  constexpr double kInertialShare = 0.05e-6;  // [m] five times the estimate above
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{3, 0.14e-3, 45.0 * kDeg}});
  scene.motion = engine::ArticleLaw(6.0, 270.0 * kDeg, 1.0);
  scene.dynamics.friction = false;
  scene.dynamics.rolling_without_slip = true;
  const solvers::Trajectory massive = solvers::DynamicSolver(FirstRevolutionOnly()).SolveRevolution(scene, 90);
  scene.dynamics.massless_spring_rollers = true;
  const solvers::Trajectory massless = solvers::DynamicSolver(FirstRevolutionOnly()).SolveRevolution(scene, 90);
  ASSERT_EQ(massive.status, solvers::Status::kOk) << massive.message;
  ASSERT_EQ(massless.status, solvers::Status::kOk) << massless.message;
  EXPECT_LT(LargestDistance(massive.centre, massless.centre), kInertialShare);
}

// The steady revolution comes from the same run; after four revolutions (4 s of creep at
// tau ~ 0.5 s) the path repeats itself: the fourth and fifth revolutions agree far better
// than the first and the fourth.
TEST(DynamicSolver, SteadyRevolutionRepeatsWhileTheFirstCarriesTheArticleStartTransient) {
  constexpr double kRepeatTolerance = 0.5e-6;  // [m] e^-2.7 decay per revolution of a ~100 um transient at rev 4: ~0.05 um
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{3, 0.14e-3, 45.0 * kDeg}});
  scene.dynamics.friction = false;
  scene.dynamics.rolling_without_slip = true;
  scene.motion = engine::ArticleLaw(0.5, 270.0 * kDeg, 6.0);
  solvers::DynamicOptions fourth = ArticleStart();
  fourth.steady_revolution = 3;
  solvers::DynamicOptions fifth = ArticleStart();
  fifth.steady_revolution = 4;
  const solvers::Trajectory a = solvers::DynamicSolver(fourth).SolveRevolution(scene, 72);
  const solvers::Trajectory b = solvers::DynamicSolver(fifth).SolveRevolution(scene, 72);
  ASSERT_EQ(a.status, solvers::Status::kOk) << a.message;
  ASSERT_TRUE(a.steady && b.steady);
  EXPECT_LT(LargestDistance(a.steady->centre, b.steady->centre), kRepeatTolerance);
  EXPECT_GT(LargestDistance(a.centre, a.steady->centre), 100.0 * kRepeatTolerance);
}

// The integrator's Newton matrix is the analytic Jacobian; check it column by column
// against central differences of the equations of motion, on a state taken from a real
// run (all contacts loaded, rollers rolling) with shape errors on ring and rollers so
// every geometric term is live, for the full model and for massless spring rollers.
TEST(DynamicSolver, AnalyticJacobianMatchesCentralDifferences) {
  // Central differences err by (h / depth)^2 <= 5e-5 of an entry at the steps below, and
  // rounding, divided by h, adds a few 1e-6 (see the steps): 1e-4 of the column's largest
  // entry holds while a missing term (the contact's slide along the surfaces alone is
  // ~100 % of the spin rows) fails it by orders.
  constexpr double kColumnTolerance = 1e-4;
  for (const bool massless : {false, true}) {
    engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
    testing::SetRing(scene, {{3, 0.14e-3, 45.0 * kDeg}, {5, 0.02e-3, 10.0 * kDeg}});
    testing::SetRollerShapes(scene, {{2, 0.007e-3, 30.0 * kDeg}});
    scene.dynamics.massless_spring_rollers = massless;
    // The state the steps below were sized on: 0.3 s after the step, from the article's
    // start (the ring still creeping).
    solvers::DynamicOptions options = ArticleStart();
    options.relative_tolerance = 1e-8;
    const solvers::DynamicHistory history = solvers::DynamicSolver(options).SolveHistory(scene, 0.1, 0.8);
    ASSERT_EQ(history.status, solvers::Status::kOk) << history.message;
    const solvers::DynamicSample& sample = history.samples.back();
    Eigen::VectorXd state = solvers::InitialDynamicState(scene);
    state.head<4>() << sample.centre.x(), sample.centre.y(), 2e-4, -1e-4;
    // Steps per state: ring position 1 um and roller travel 0.1 um (the depth is 150 um),
    // speeds 0.1 um/s, spin angles 0.1 urad, spin rates 1 mrad/s. The ring position's
    // column holds the largest entries (~1e5 in the spin rows, where friction's slope and
    // the rollers' small spin inertia amplify rounding in the slip, a difference of two
    // ~1.4 m/s surface speeds): its quotient carries ~2e-6 / h of rounding, measured, which
    // at 0.1 um is at the tolerance and at 1 um is 1/40 of it, while the truncation
    // (h / depth)^2 stays below 5e-5.
    std::vector<double> steps = {1e-6, 1e-6, 1e-7, 1e-7};
    for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
      if (scene.rollers[i].mount != engine::RollerMount::kSpring) continue;
      state[static_cast<Eigen::Index>(steps.size())] = sample.travel[i];
      steps.push_back(1e-7);
      if (!massless) {
        state[static_cast<Eigen::Index>(steps.size())] = 3e-4;
        steps.push_back(1e-7);
      }
    }
    for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
      state[static_cast<Eigen::Index>(steps.size())] = sample.spin_angle[i];
      steps.push_back(1e-7);
      state[static_cast<Eigen::Index>(steps.size())] = sample.spin_rate[i];
      steps.push_back(1e-3);
    }
    ASSERT_EQ(static_cast<Eigen::Index>(steps.size()), state.size());
    const solvers::DynamicsEvaluation at = solvers::EvaluateDynamics(scene, sample.time, state);
    ASSERT_EQ(at.status, solvers::Status::kOk) << at.message;
    for (Eigen::Index j = 0; j < state.size(); ++j) {
      const double h = steps[static_cast<std::size_t>(j)];
      Eigen::VectorXd plus = state;
      Eigen::VectorXd minus = state;
      plus[j] += h;
      minus[j] -= h;
      const Eigen::VectorXd numeric = (solvers::EvaluateDynamics(scene, sample.time, plus).rates -
                                       solvers::EvaluateDynamics(scene, sample.time, minus).rates) /
                                      (2.0 * h);
      const double scale = numeric.cwiseAbs().maxCoeff();
      EXPECT_LE((at.jacobian.col(j) - numeric).cwiseAbs().maxCoeff(), kColumnTolerance * scale)
          << "column " << j << (massless ? " (massless)" : "") << "\nanalytic " << at.jacobian.col(j).transpose()
          << "\nnumeric  " << numeric.transpose();
    }
  }
}

// The explicit baseline above its stability limit: the ring against c_max alone (rolling
// imposed, massless spring roller) has |lambda| ~ 1e5 1/s, so a 100 us step is beyond
// 4th-order Runge-Kutta's 2.78 / |lambda| and ringtol must refuse it by name.
TEST(DynamicSolver, ExplicitStepAboveTheStabilityLimitIsRefused) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{2, 0.14e-3, 45.0 * kDeg}});
  scene.dynamics = {.friction = false, .rolling_without_slip = true, .massless_spring_rollers = true};
  solvers::DynamicOptions options = FirstRevolutionOnly();
  options.method = solvers::DynamicMethod::kExplicitRungeKutta;
  options.explicit_step = 1e-4;
  const solvers::Trajectory path = solvers::DynamicSolver(options).SolveRevolution(scene, 36);
  EXPECT_EQ(path.status, solvers::Status::kIntegrationFailed);
  EXPECT_NE(path.message.find("stability limit"), std::string::npos) << path.message;
}

// Below it, the explicit baseline and the default BDF integrate the same equations and
// must give the same path: both are converged far below the tolerance here (RK4 at
// 20 us: (h / tau)^4 with tau ~ 1e-5 s... measured 0.02 um on D_trajectory; BDF at its
// default tolerance: 1e-4 um).
TEST(DynamicSolver, ExplicitBaselineBelowItsLimitAgreesWithTheImplicitDefault) {
  constexpr double kAgreement = 0.2e-6;  // [m] ten times the measured RK4 error at 20 us
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{2, 0.14e-3, 45.0 * kDeg}});
  scene.dynamics = {.friction = false, .rolling_without_slip = true, .massless_spring_rollers = true};
  scene.motion = engine::ArticleLaw(0.2, 270.0 * kDeg, 1.0);
  solvers::DynamicOptions options = FirstRevolutionOnly();
  const solvers::Trajectory implicit = solvers::DynamicSolver(options).SolveRevolution(scene, 36);
  options.method = solvers::DynamicMethod::kExplicitRungeKutta;
  options.explicit_step = 2e-5;
  const solvers::Trajectory explicit_path = solvers::DynamicSolver(options).SolveRevolution(scene, 36);
  ASSERT_EQ(implicit.status, solvers::Status::kOk) << implicit.message;
  ASSERT_EQ(explicit_path.status, solvers::Status::kOk) << explicit_path.message;
  EXPECT_LT(LargestDistance(implicit.centre, explicit_path.centre), kAgreement);
}

// Turning the other way samples the revolution at psi_k = -2 pi k / steps. With one ring
// harmonic and the roller layout symmetric about the spring axis, mirroring the scene
// (x -> -x, phase -> -phase) maps a clockwise run onto a counter-clockwise one, so the
// two diameters agree to the integration tolerance.
TEST(DynamicSolver, AClockwiseLawIsTheMirrorOfACounterClockwiseOne) {
  constexpr double kMirror = 0.05e-6;  // [m] two runs at the default tolerance (~0.02 um each)
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  scene.dynamics = {.friction = false, .rolling_without_slip = true, .massless_spring_rollers = false};
  testing::SetRing(scene, {{3, 0.14e-3, 20.0 * kDeg}});
  scene.motion = engine::ArticleLaw(0.5, 270.0 * kDeg, 1.0);
  const solvers::Trajectory forward = solvers::DynamicSolver(FirstRevolutionOnly()).SolveRevolution(scene, 72);
  // Mirror about the y axis (the spring roller's axis): theta -> pi - theta turns
  // cos(3 theta + phi) into cos(3 theta - phi + 3 pi) = -cos(3 theta - phi).
  testing::SetRing(scene, {{3, 0.14e-3, 180.0 * kDeg - 20.0 * kDeg}});
  scene.motion = engine::ArticleLaw(0.5, -270.0 * kDeg, 1.0);
  const solvers::Trajectory backward = solvers::DynamicSolver(FirstRevolutionOnly()).SolveRevolution(scene, 72);
  ASSERT_EQ(forward.status, solvers::Status::kOk) << forward.message;
  ASSERT_EQ(backward.status, solvers::Status::kOk) << backward.message;
  EXPECT_DOUBLE_EQ(backward.psi.back(), -2.0 * std::numbers::pi);
  double largest = 0.0;
  for (std::size_t k = 0; k < forward.centre.size(); ++k) {
    largest = std::max(largest, (forward.centre[k] - Eigen::Vector2d(-backward.centre[k].x(), backward.centre[k].y())).norm());
  }
  EXPECT_LT(largest, kMirror);
}

// Stiction with a transition velocity 100 times smaller (0.1 mm/s) still integrates and
// barely moves the path of round rollers, which need no torque once rolling (measured
// 0.012 um on D). At 10000 times smaller (1 um/s) the friction law's slope, 1.5 mu_s /
// v_s, makes the spin-up after the step a stiff and nearly discontinuous switch that
// BDF cannot step through (at 10 um/s it sometimes can): the run must stop with the
// integrator's reason within its step budget, not hang and not return a number.
TEST(DynamicSolver, StictionWithATinyTransitionVelocityStopsWithAReason) {
  constexpr double kStictionShare = 0.1e-6;  // [m] eight times the measured change
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{2, 0.14e-3, 45.0 * kDeg}});
  const solvers::Trajectory reference = solvers::DynamicSolver(FirstRevolutionOnly()).SolveRevolution(scene, 36);
  scene.friction.stiction_velocity = 1e-4;
  scene.friction.transition_velocity = 5e-4;
  const solvers::Trajectory sharper = solvers::DynamicSolver(FirstRevolutionOnly()).SolveRevolution(scene, 36);
  ASSERT_EQ(reference.status, solvers::Status::kOk) << reference.message;
  ASSERT_EQ(sharper.status, solvers::Status::kOk) << sharper.message;
  EXPECT_LT(LargestDistance(reference.centre, sharper.centre), kStictionShare);
  scene.friction.stiction_velocity = 1e-6;
  scene.friction.transition_velocity = 5e-6;
  const solvers::Trajectory sharpest = solvers::DynamicSolver(FirstRevolutionOnly()).SolveRevolution(scene, 36);
  EXPECT_EQ(sharpest.status, solvers::Status::kIntegrationFailed);
  EXPECT_NE(sharpest.message.find("CV_TOO_MUCH_WORK"), std::string::npos) << sharpest.message;
}

// A spring roller a million times lighter (2.5 ug) against c_max puts an eigenvalue near
// -c_max / m = -4e13 1/s into the system. The BDF default is L-stable, so it steps over
// that mode at no extra cost and lands on the massless model (measured 0.02 um apart);
// the explicit baseline would need steps below 1e-13 s and is refused by name.
TEST(DynamicSolver, ANearlyMasslessSpringRollerIsTheMasslessLimitForBdfAndRefusedExplicitly) {
  constexpr double kMasslessLimit = 0.1e-6;  // [m] five times the measured gap
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{3, 0.14e-3, 45.0 * kDeg}});
  scene.rollers[0].mass = 2.47e-9;
  const solvers::Trajectory light = solvers::DynamicSolver(FirstRevolutionOnly()).SolveRevolution(scene, 90);
  solvers::DynamicOptions explicit_options = FirstRevolutionOnly();
  explicit_options.method = solvers::DynamicMethod::kExplicitRungeKutta;
  explicit_options.explicit_step = 1e-9;
  const solvers::Trajectory refused = solvers::DynamicSolver(explicit_options).SolveRevolution(scene, 90);
  scene.dynamics.massless_spring_rollers = true;
  const solvers::Trajectory massless = solvers::DynamicSolver(FirstRevolutionOnly()).SolveRevolution(scene, 90);
  ASSERT_EQ(light.status, solvers::Status::kOk) << light.message;
  ASSERT_EQ(massless.status, solvers::Status::kOk) << massless.message;
  EXPECT_LT(LargestDistance(light.centre, massless.centre), kMasslessLimit);
  EXPECT_EQ(refused.status, solvers::Status::kIntegrationFailed);
  EXPECT_NE(refused.message.find("stability limit"), std::string::npos) << refused.message;
}

TEST(DynamicSolver, ScenesWithoutMassOrWithRigidContactAreAStatus) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  scene.ring.mass = 0.0;
  const solvers::Trajectory massless = solvers::DynamicSolver().SolveRevolution(scene, 36);
  EXPECT_EQ(massless.status, solvers::Status::kIntegrationFailed);
  EXPECT_NE(massless.message.find("mass"), std::string::npos) << massless.message;
  const engine::Scene rigid = testing::PaperScene(engine::ContactLaw::Model::kRigid);
  EXPECT_EQ(solvers::DynamicSolver().SolveStatic(rigid).status, solvers::Status::kIntegrationFailed);
}

// Where the physics fails, ringtol must say so. A 5 N preload against an order-3 ring
// error of 0.14 mm turning at 10 rev/s: the centre must accelerate at about
// (3 omega)^2 x 0.28 mm ~ 10 m/s^2, which takes ~12 N on the 1.24 kg ring, more than the
// spring roller can push. A contact opens during the revolution and the run reports
// lift-off instead of a path.
TEST(DynamicSolver, AContactThatOpensIsReportedAsLiftOff) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{3, 0.14e-3, 45.0 * kDeg}});
  scene.rollers[0].spring.preload = 5.0;
  scene.dynamics = {.friction = false, .rolling_without_slip = true, .massless_spring_rollers = false};
  scene.motion = engine::ArticleLaw(2.0, 10.0 * 360.0 * kDeg, 1.0);
  // The article's start, on which the one opening below was located.
  const solvers::DynamicSolver solver(ArticleStart(FirstRevolutionOnly()));
  const solvers::Trajectory path = solver.SolveRevolution(scene, 360);
  ASSERT_EQ(path.status, solvers::Status::kLiftOff) << solvers::StatusName(path.status) << ": " << path.message;
  EXPECT_GT(path.failure_angle, 0.0);
  // The integrator watches every contact's push between samples, so four samples a
  // revolution find the same opening at the same moment (to the root finder's
  // tolerance, ~1e-10 s of 0.1 s), where sampling alone would place it only to 90 deg.
  constexpr double kSameMoment = 1e-6;  // [rad]
  const solvers::Trajectory coarse = solver.SolveRevolution(scene, 3);
  ASSERT_EQ(coarse.status, solvers::Status::kLiftOff) << coarse.message;
  EXPECT_NEAR(coarse.failure_angle, path.failure_angle, kSameMoment);
  EXPECT_NE(coarse.message.find("opens at t ="), std::string::npos) << coarse.message;
}

// A velocity step with no settle from the article's start: the ring starts centred and at
// rest, touching its fixed rollers with zero force, and is turned at once. The contacts are
// open at the first sample, and ringtol must say so rather than report a path from an
// unloaded start. From the quasistatic equilibrium, with the rollers already rolling at
// the step's rate, every contact is loaded from the start and the revolution is usable.
TEST(DynamicSolver, AStepWithoutSettleLiftsOffFromTheArticleStartOnly) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{3, 0.14e-3, 45.0 * kDeg}});
  scene.motion = engine::ArticleLaw(0.0, 270.0 * kDeg, 1.0);
  const solvers::Trajectory path = solvers::DynamicSolver(ArticleStart(FirstRevolutionOnly())).SolveRevolution(scene, 72);
  EXPECT_EQ(path.status, solvers::Status::kLiftOff) << path.message;
  EXPECT_EQ(path.failure_angle, 0.0);
  const solvers::Trajectory loaded = solvers::DynamicSolver(FirstRevolutionOnly()).SolveRevolution(scene, 72);
  EXPECT_EQ(loaded.status, solvers::Status::kOk) << loaded.message;
}

// The default start is the quasistatic equilibrium, at rest: a dynamic equilibrium too
// (damping and friction vanish with the velocities), so the settle leaves it where it is.
TEST(DynamicSolver, TheDefaultStartIsTheQuasistaticEquilibriumAndStaysThere) {
  // [m] CVODE's absolute tolerance 1e-11 m at rtol 1e-8, with the equilibrium's 1 pm
  // Newton tolerance: a residual force of k_c * 1 pm ~ 2e-7 N moves nothing visibly.
  constexpr double kCentreTolerance = 1e-10;
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{3, 0.14e-3, 45.0 * kDeg}});
  const solvers::Equilibrium reference = solvers::QuasistaticSolver().SolveStatic(scene);
  ASSERT_EQ(reference.status, solvers::Status::kOk) << reference.message;
  const Eigen::VectorXd start = solvers::InitialDynamicState(scene);
  EXPECT_EQ(Eigen::Vector2d(start(0), start(1)), reference.centre);
  solvers::DynamicOptions options = FirstRevolutionOnly();
  options.relative_tolerance = 1e-8;
  const solvers::Equilibrium settled = solvers::DynamicSolver(options).SolveStatic(scene);
  ASSERT_EQ(settled.status, solvers::Status::kOk) << settled.message;
  EXPECT_LT((settled.centre - reference.centre).norm(), kCentreTolerance);
}

// Order 2 is filtered by three rollers 120 deg apart: the ring runs a circle of radius C,
// and what the speed adds is the lag of the contacts' compliance. Over the path the spring
// force swings by k_s * 2C = 1334 N/m * 0.28 mm = 0.37 N, so each contact's deflection by
// 0.37 N / 1.9e5 N/m = 2 um: no lag of it, and so no start that sits on the quasistatic
// path, can move the centre further from the steady orbit, nor D_trajectory by more than
// twice that. The article's settle leaves the ring ~150 um e^-1 short of its equilibrium
// when rotation starts, a creep whose remainder over the first revolution is tens of um.
TEST(DynamicSolver, TheDefaultStartHasNoCreepTransientWhileTheArticleSettleHasOne) {
  constexpr double kComplianceSwing = 2e-6;              // [m] derived above
  constexpr double kSpeedEffectBound = 2.0 * kComplianceSwing;  // [m] on a diameter
  constexpr double kCreepTransient = 10.0 * kSpeedEffectBound;  // [m] the article's start exceeds it
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{2, 0.14e-3, 45.0 * kDeg}});
  scene.motion = engine::ArticleLaw(0.5, 270.0 * kDeg, 4.0);
  constexpr int kSteps = 72;  // order 2: 36 samples per undulation
  const solvers::SimulationResult from_equilibrium = solvers::Simulate(scene, solvers::DynamicSolver(), {.steps = kSteps});
  const solvers::SimulationResult from_article =
      solvers::Simulate(scene, solvers::DynamicSolver(ArticleStart()), {.steps = kSteps});
  const solvers::SimulationResult quasistatic = solvers::Simulate(scene, solvers::QuasistaticSolver(), {.steps = kSteps});
  for (const solvers::SimulationResult* result : {&from_equilibrium, &from_article}) {
    ASSERT_EQ(result->status, solvers::Status::kOk) << result->message;
    ASSERT_TRUE(result->steady);
    ASSERT_EQ(result->steady->status, solvers::Status::kOk) << result->steady->message;
  }
  ASSERT_EQ(quasistatic.status, solvers::Status::kOk) << quasistatic.message;
  EXPECT_NEAR(from_equilibrium.d_trajectory, from_equilibrium.steady->d_trajectory, kSpeedEffectBound);
  EXPECT_NEAR(from_equilibrium.d_trajectory, quasistatic.d_trajectory, kSpeedEffectBound);
  EXPECT_NEAR(from_equilibrium.steady->d_trajectory, from_article.steady->d_trajectory, kSpeedEffectBound);
  EXPECT_GT(from_article.d_trajectory - from_article.steady->d_trajectory, kCreepTransient);
}

// A time history samples the law's whole span and carries each contact's loads: at rest
// after the settle, friction is nil and the normal forces balance the preload.
TEST(DynamicSolver, HistoryCoversTheSpanWithContactLoads) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  scene.motion = engine::ArticleLaw(3.0, 270.0 * kDeg, 0.25);
  const solvers::DynamicHistory history = solvers::DynamicSolver(ArticleStart()).SolveHistory(scene, 0.01, 3.0);
  ASSERT_EQ(history.status, solvers::Status::kOk) << history.message;
  ASSERT_EQ(history.samples.size(), 301u);
  const solvers::DynamicSample& rest = history.samples.back();
  EXPECT_NEAR(rest.time, 3.0, 1e-12);
  // Three rollers 120 deg apart on a round ring: at rest each carries what the spring
  // pushes, preload - k_s s. The creep has decayed to e^-5 of ~20 N by t = 3 s: 0.1 N.
  constexpr double kCreepRemainder = 0.2;   // [N]
  constexpr double kStillFriction = 1e-3;   // [N] mu(v) F_n with v the creep speed ~ um/s
  const engine::Spring& spring = scene.rollers[0].spring;
  const double pushed = spring.preload - spring.stiffness * rest.travel[0];
  for (const double f : rest.normal_force) EXPECT_NEAR(f, pushed, kCreepRemainder);
  for (const double f : rest.friction_force) EXPECT_LT(std::abs(f), kStillFriction);
}

}  // namespace
}  // namespace ringtol
