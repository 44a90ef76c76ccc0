// The refined angle mode (solvers::AngleMode::kRefined) against the dense reference on the
// same grid. What it leaves unevaluated is certified not to change D_trajectory, runout,
// the contact-force range or the status, so on the same steps they must agree with the
// dense run to the rung's own accuracy at an angle: the linear rung evaluates the same
// closed form (round-off), the quasistatic rung the same equilibria to its Newton
// tolerance. The swing is not certified; it must stay within the sampling bounds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "solvers/linear.h"
#include "solvers/quasistatic.h"
#include "solvers/simulation.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

// Campaign resolution: a sampling budget of 1 um (jobs/campaign/campaign_file.h).
constexpr double kPathTolerance = 1e-6;  // [m]
// The quasistatic rung converges each angle to this (solvers::MakeSolver) [m].
constexpr double kNewtonTolerance = solvers::kAngleShareOfPathTolerance * kPathTolerance;
// The enclosing circle's radius and the signal's extremes move by at most the largest
// move of a point, so the refined and dense metrics differ by at most twice the
// tolerance on each of the two runs' points.
constexpr double kQuasistaticAgreement = 2.0 * 2.0 * kNewtonTolerance;  // [m]
// The linear rung evaluates the same closed form: ~1e3 ulp of a 0.3 m coordinate.
constexpr double kLinearAgreement = 1e-12;  // [m]

// The quasistatic rung as a campaign makes it (solvers::MakeSolver).
solvers::QuasistaticOptions CampaignOptions() {
  solvers::QuasistaticOptions options;
  options.position_tolerance = kNewtonTolerance;
  return options;
}

solvers::SimulationOptions Options(solvers::AngleMode angles, int steps = 0) {
  solvers::SimulationOptions options;
  options.path_tolerance = kPathTolerance;
  options.angles = angles;
  options.steps = steps;
  return options;
}

// The contact-force agreement at the quasistatic tolerance: a penetration error of the
// Newton tolerance moves a penalty force F = k delta^e by e F / delta times it.
double ForceAgreement(const engine::Scene& scene, const solvers::SimulationResult& dense) {
  double stiffest = 0.0;
  for (const solvers::RollerForceRange& range : dense.contact_force) {
    const double delta = std::pow(range.max / scene.contact.stiffness, 1.0 / scene.contact.exponent);
    stiffest = std::max(stiffest, scene.contact.exponent * range.max / delta);
  }
  return 2.0 * 2.0 * kNewtonTolerance * stiffest;
}

// |swing_refined - swing_dense| <= 4 (eta_coarse + eta_dense) (solvers::SamplingErrorBounds):
// both samplings lie on the continuous signal, the refined one never sparser than the
// coarse grid.
double SwingAllowance(const engine::Scene& scene, int steps, int stride) {
  return solvers::SamplingErrorBoundsAt(scene, steps / stride).swing + solvers::SamplingErrorBoundsAt(scene, steps).swing;
}

struct Agreement {
  double length = 0.0;  // [m]
  bool quasistatic = false;
};

void ExpectSameAnswer(const engine::Scene& scene, const solvers::Solver& solver, Agreement agreement, int draw,
                      int& failures) {
  const solvers::SimulationResult dense = solvers::Simulate(scene, solver, Options(solvers::AngleMode::kDense));
  const solvers::SimulationResult refined = solvers::Simulate(scene, solver, Options(solvers::AngleMode::kRefined));
  ASSERT_EQ(refined.status, dense.status) << "draw " << draw << ": " << refined.message << " / " << dense.message;
  EXPECT_EQ(refined.steps, dense.steps) << draw;
  if (dense.status != solvers::Status::kOk) {
    ++failures;
    EXPECT_EQ(refined.message, dense.message) << draw;
    return;
  }
  EXPECT_NEAR(refined.d_trajectory, dense.d_trajectory, agreement.length) << draw;
  EXPECT_NEAR(refined.runout, dense.runout, agreement.length) << draw;
  EXPECT_NEAR(refined.dist_init, dense.dist_init, 1e3 * agreement.length + 1e-9) << draw;
  // The quasistatic force range is read at the evaluated angles only: within twice the
  // first-order chord bound at the coarse step (solvers::AngleMode), plus the tolerance.
  const double force =
      agreement.quasistatic
          ? ForceAgreement(scene, dense) +
                2.0 * std::ranges::max(solvers::LinearSolver()
                                           .ChordStrayingAt(scene, 2.0 * std::numbers::pi * Options({}).refine_stride / dense.steps)
                                           .contact_force)
          : 1e-9;
  EXPECT_NEAR(refined.min_contact_force, dense.min_contact_force, force) << draw;
  for (std::size_t i = 0; i < dense.contact_force.size(); ++i) {
    EXPECT_NEAR(refined.contact_force[i].max, dense.contact_force[i].max, force) << draw << " roller " << i;
  }
  EXPECT_NEAR(refined.swing, dense.swing, SwingAllowance(scene, dense.steps, Options({}).refine_stride)) << draw;
  EXPECT_LT(refined.trajectory.psi.size(), dense.trajectory.psi.size()) << draw;
}

// Draws of three lobe sizes, 1, 5 and 9 times the campaign-like scene's; most must solve.
void ExpectSameAnswerOnDraws(const solvers::Solver& solver, std::uint64_t seed, int draws, Agreement agreement) {
  std::mt19937_64 random(seed);
  int failures = 0;
  for (int draw = 0; draw < draws; ++draw) {
    ExpectSameAnswer(testing::RandomCampaignLikeScene(random, 1.0 + 4.0 * (draw % 3)), solver, agreement, draw, failures);
  }
  EXPECT_LT(failures, draws / 2);
}

TEST(RefinedAngles, LinearRungMatchesTheDenseGridOnRandomCampaignDraws) {
  ExpectSameAnswerOnDraws(solvers::LinearSolver(), 21, 60, {kLinearAgreement, false});
}

TEST(RefinedAngles, QuasistaticRungMatchesTheDenseGridOnRandomCampaignDraws) {
  ExpectSameAnswerOnDraws(solvers::QuasistaticSolver(CampaignOptions()), 7, 40, {kQuasistaticAgreement, true});
}

// Large spring-roller lobes and a weak spring: the assembly lifts off for some draws, at
// angles the coarse grid need not contain.
TEST(RefinedAngles, StatusesAreTheDenseGridsWhereTheAssemblyLiftsOff) {
  std::mt19937_64 random(3);
  const solvers::QuasistaticSolver quasistatic(CampaignOptions());
  const solvers::LinearSolver linear;
  int lifted = 0;
  for (int draw = 0; draw < 24; ++draw) {
    const engine::Scene scene = testing::LiftingCampaignLikeScene(random, draw);
    for (const solvers::Solver* solver : {static_cast<const solvers::Solver*>(&quasistatic),
                                          static_cast<const solvers::Solver*>(&linear)}) {
      const solvers::SimulationResult dense = solvers::Simulate(scene, *solver, Options(solvers::AngleMode::kDense));
      const solvers::SimulationResult refined =
          solvers::Simulate(scene, *solver, Options(solvers::AngleMode::kRefined));
      ASSERT_EQ(refined.status, dense.status) << draw << " " << solver->name() << ": " << refined.message;
      EXPECT_EQ(refined.message, dense.message) << draw;
      lifted += dense.status == solvers::Status::kLiftOff;
    }
  }
  EXPECT_GT(lifted, 0) << "no draw lifted off: the test shows nothing";
}

// Lobes fast enough that the path's and the signal's extremes fall between coarse angles;
// the refinement must still find the dense grid's extremes, exactly (the linear rung's
// points are the same numbers in both modes).
TEST(RefinedAngles, ExtremesBetweenCoarseAnglesAreFound) {
  const engine::Scene scene = testing::FastLobeScene();
  const solvers::LinearSolver linear;
  const solvers::QuasistaticSolver quasistatic(CampaignOptions());
  for (const auto& [solver, agreement] : {std::pair<const solvers::Solver*, double>{&linear, kLinearAgreement},
                                          std::pair<const solvers::Solver*, double>{&quasistatic, kQuasistaticAgreement}}) {
    const solvers::SimulationResult dense = solvers::Simulate(scene, *solver, Options(solvers::AngleMode::kDense));
    const solvers::SimulationResult refined = solvers::Simulate(scene, *solver, Options(solvers::AngleMode::kRefined));
    ASSERT_EQ(dense.status, solvers::Status::kOk) << dense.message;
    ASSERT_EQ(refined.status, solvers::Status::kOk) << refined.message;
    const int stride = Options({}).refine_stride;
    const auto off_grid = [stride](std::ptrdiff_t k) { return k % stride != 0; };
    const auto signal_max = std::max_element(dense.sensor.begin(), dense.sensor.end()) - dense.sensor.begin();
    const auto signal_min = std::min_element(dense.sensor.begin(), dense.sensor.end()) - dense.sensor.begin();
    EXPECT_TRUE(off_grid(signal_max) || off_grid(signal_min)) << solver->name() << ": the scene does not test what it claims";
    std::ptrdiff_t farthest = 0;
    double largest = 0.0;
    for (std::size_t k = 0; k < dense.trajectory.centre.size(); ++k) {
      const double distance = (dense.trajectory.centre[k] - dense.enclosing_circle.centre).norm();
      if (distance > largest) {
        largest = distance;
        farthest = static_cast<std::ptrdiff_t>(k);
      }
    }
    EXPECT_TRUE(off_grid(farthest)) << solver->name() << ": the scene does not test what it claims";
    EXPECT_NEAR(refined.d_trajectory, dense.d_trajectory, agreement) << solver->name();
    EXPECT_NEAR(refined.runout, dense.runout, agreement) << solver->name();
  }
}

}  // namespace
}  // namespace ringtol
