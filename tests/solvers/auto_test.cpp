// The auto rung's choices: the linear rung's path where its estimate fits the budget, the
// quasistatic rung's where it does not or where the linear rung fails, and the dynamic
// rung's where the ring's inertia could open a contact. The sample-by-sample check of its
// estimate on the catalogue's classes is tests/jobs/campaign/auto_rung_test.cpp.
#include "solvers/auto.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "solvers/simulation.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

using solvers::Rung;
using solvers::Status;
using testing::kDeg;

constexpr int kSteps = 720;

solvers::AutoSolver WithBudget(double budget) {
  solvers::AutoOptions options;
  options.budget = budget;
  return solvers::AutoSolver(options);
}

engine::Scene OrderThree(double amplitude) {
  engine::Scene scene = testing::PaperScene();
  testing::SetRing(scene, {{3, amplitude, 45.0 * kDeg}});
  return scene;
}

solvers::SimulationResult Revolve(const engine::Scene& scene, const solvers::Solver& solver) {
  solvers::SimulationOptions options;
  options.steps = kSteps;
  return solvers::Simulate(scene, solver, options);
}

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

TEST(AutoRung, SettlesOnTheLinearRungWhereItsEstimateFitsTheBudgetWithItsNumbers) {
  const engine::Scene scene = OrderThree(0.05e-3);
  constexpr double kGenerousBudget = 1e-4;  // [m] far above any second-order error at 0.05 mm
  const solvers::SimulationResult chosen = Revolve(scene, WithBudget(kGenerousBudget));
  solvers::LinearOptions unlimited;
  unlimited.max_relative_error = 1.0;
  const solvers::SimulationResult linear = Revolve(scene, solvers::LinearSolver(unlimited));
  ASSERT_EQ(chosen.status, Status::kOk) << chosen.message;
  EXPECT_EQ(chosen.trajectory.rung, Rung::kLinear);
  EXPECT_TRUE(SameBits(chosen.d_trajectory, linear.d_trajectory));
  EXPECT_TRUE(SameBits(chosen.runout, linear.runout));
  EXPECT_TRUE(SameBits(chosen.trajectory.error_estimate, linear.trajectory.error_estimate));
  EXPECT_GT(chosen.trajectory.error_estimate, 0.0);
}

TEST(AutoRung, GoesToTheQuasistaticRungWhenTheEstimateExceedsTheBudget) {
  const engine::Scene scene = OrderThree(0.05e-3);
  const solvers::SimulationResult chosen = Revolve(scene, WithBudget(0.0));
  const solvers::SimulationResult exact = Revolve(scene, solvers::QuasistaticSolver());
  ASSERT_EQ(chosen.status, Status::kOk) << chosen.message;
  EXPECT_EQ(chosen.trajectory.rung, Rung::kQuasistatic);
  EXPECT_TRUE(SameBits(chosen.d_trajectory, exact.d_trajectory));
  EXPECT_EQ(chosen.trajectory.error_estimate, 0.0);
}

// Where the linear rung refuses (beyond its range) or fails (a lift-off or a travel its
// first-order path overstates), auto gives the exact model's verdict.
TEST(AutoRung, GivesTheQuasistaticStatusWhereverTheLinearRungFails) {
  constexpr double kAnyBudget = 1e-3;  // [m] so that only the failures and margins decide
  const solvers::AutoSolver automatic = WithBudget(kAnyBudget);
  struct Case {
    std::string name;
    engine::Scene scene;
    bool linear_fails;  // else the linear path may settle it, within the budget
  };
  std::vector<Case> cases;
  {
    engine::Scene scene = testing::PaperScene();
    testing::SetRing(scene, {{10, 1.0e-3, 45.0 * kDeg}});  // beyond the linear rung's own limit, valid
    cases.push_back({"order10_1.0mm", scene, false});
  }
  for (const double preload : {0.4, 1.0}) {  // lift-off, and a 0.4 N margin
    engine::Scene scene = OrderThree(0.14e-3);
    scene.rollers[0].spring.preload = preload;
    cases.push_back({"preload " + std::to_string(preload) + " N", scene, preload < 1.0});
  }
  {
    engine::Scene scene = OrderThree(0.14e-3);
    scene.rollers[0].spring.travel_limit = 0.3e-3;  // 0.42 mm of travel swing
    cases.push_back({"travel limit 0.3 mm", scene, true});
  }
  cases.push_back({"order3_2.0mm", OrderThree(2.0e-3), true});
  for (const Case& c : cases) {
    const solvers::SimulationResult chosen = Revolve(c.scene, automatic);
    const solvers::SimulationResult exact = Revolve(c.scene, solvers::QuasistaticSolver());
    EXPECT_EQ(solvers::StatusName(chosen.status), solvers::StatusName(exact.status)) << c.name << ": " << chosen.message;
    if (c.linear_fails) {
      EXPECT_EQ(chosen.trajectory.rung, Rung::kQuasistatic) << c.name;
    }
  }
}

// A single ring harmonic's path is 2 A cos(n psi + phase) along one direction for the
// article's rollers (ring gain 2: both fixed contacts see the harmonic, sigma_min of their
// normals is 1/sqrt(2)), so the bound is the exact peak of m omega^2 |c''|.
TEST(AutoRung, InertiaForceBoundIsTheRingsMassTimesItsPeakAccelerationForOneHarmonic) {
  constexpr double kAmplitude = 0.14e-3;  // [m]
  constexpr int kOrder = 3;
  const engine::Scene scene = OrderThree(kAmplitude);
  const double rate = 1.5 * std::numbers::pi;  // [rad/s] the article's 270 deg/s
  const double expected = scene.ring.mass * rate * rate * 2.0 * kAmplitude * kOrder * kOrder;
  constexpr double kRigid = std::numeric_limits<double>::infinity();  // [N/m] no term is absorbed
  constexpr double kRoundOff = 1e-12;  // [-] relative: a few products and a 2x2 eigenvalue
  EXPECT_NEAR(solvers::AutoSolver::InertiaForceBound(scene, kRigid), expected, kRoundOff * expected);
  // 0.07 N against ~19 N of contact force: the article's speed needs no dynamic rung.
  constexpr double kNegligible = 0.01;  // [-] of the preload
  EXPECT_LT(solvers::AutoSolver::InertiaForceBound(scene, kRigid), kNegligible * scene.rollers[0].spring.preload);
}

// Against the dynamic rung: below the threshold (inertial force under the smallest contact
// force) the dynamic rung keeps every contact closed, as auto's choice of the
// quasistatic rung assumes; well above it the dynamic rung's ring leaves a roller, and
// auto, having gone to the dynamic rung, says so.
TEST(AutoRung, GoesToTheDynamicRungWhereTheDynamicRungShowsTheRingLeavingItsRollers) {
  const solvers::AutoSolver automatic = WithBudget(0.0);
  struct Speed {
    double rate;  // [rad/s]
    Rung rung;
    Status status;
  };
  // Threshold: m omega^2 2 A n^2 = F_min near 79 rad/s (F_min ~ 19 N), where the fixed
  // rollers unload completely.
  for (const Speed speed : {Speed{40.0, Rung::kQuasistatic, Status::kOk}, Speed{120.0, Rung::kDynamic, Status::kLiftOff}}) {
    engine::Scene scene = OrderThree(0.14e-3);
    scene.motion = engine::ArticleLaw(0.5, speed.rate, 3.0);
    const solvers::SimulationResult chosen = Revolve(scene, automatic);
    EXPECT_EQ(chosen.trajectory.rung, speed.rung) << speed.rate << " rad/s";
    EXPECT_EQ(solvers::StatusName(chosen.status), solvers::StatusName(speed.status)) << speed.rate << " rad/s: " << chosen.message;
    solvers::DynamicOptions options;
    options.steady_revolution = 0;
    const solvers::SimulationResult dynamic = Revolve(scene, solvers::DynamicSolver(options));
    EXPECT_EQ(solvers::StatusName(dynamic.status), solvers::StatusName(speed.status)) << speed.rate << " rad/s: " << dynamic.message;
  }
}

// Settled on the spectral linear rung, a sample's static offset is measured from the
// equilibrium that rung linearised at, not from a second static solve of the same
// error-free assembly; the quasistatic rung's own solve finds it again to its Newton
// tolerance.
TEST(AutoRung, MeasuresTheSpectralStaticOffsetFromTheLinearRungsNominal) {
  engine::Scene scene = OrderThree(0.05e-3);
  scene.rollers[0].spring.preload *= 1.07;  // a drawn spring
  scene.rollers[0].spring.stiffness *= 0.95;
  solvers::AutoOptions settings;
  settings.budget = 1e-4;  // [m] as above: the linear rung settles
  // As a campaign's auto solves its exact rung: to 1 % of a 1 um path tolerance.
  settings.quasistatic.position_tolerance = solvers::kAngleShareOfPathTolerance * 1e-6;
  const solvers::AutoSolver automatic(settings);
  solvers::SimulationOptions options;
  options.steps = kSteps;
  options.angles = solvers::AngleMode::kSpectral;
  const solvers::SimulationResult result = solvers::Simulate(scene, automatic, options);
  ASSERT_EQ(result.status, Status::kOk) << result.message;
  ASSERT_EQ(result.trajectory.rung, Rung::kLinear);
  const solvers::Equilibrium nominal = automatic.linear().SolveStatic(engine::WithoutErrors(scene));
  EXPECT_TRUE(SameBits(result.static_offset, (result.trajectory.initial.centre - nominal.centre).norm()));
  const engine::Scene perfect = engine::WithoutErrors(scene);
  const solvers::EquilibriumSystem system(perfect);
  Eigen::VectorXd x;
  std::vector<solvers::TrackedContact> contacts;
  const solvers::Equilibrium searched = solvers::QuasistaticSolver().SolveStatic(system, x, contacts);
  ASSERT_EQ(searched.status, Status::kOk) << searched.message;
  EXPECT_NEAR(result.static_offset, (result.trajectory.initial.centre - searched.centre).norm(),
              solvers::QuasistaticOptions{}.position_tolerance);
}

}  // namespace
}  // namespace ringtol
