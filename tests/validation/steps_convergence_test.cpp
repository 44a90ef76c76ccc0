// Angular resolution. The sampled path's enclosing circle can only be smaller than the
// true one (it encloses a subset), and every true point lies within |c''|max dpsi^2 / 8 of
// a chord between neighbouring samples, which the sampled circle encloses (it is convex):
//   0 <= D_true - D_N <= |c''|max dpsi^2 / 4.
// Those are exact bounds, so they make a test that cannot pass by luck.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "solvers/linear.h"
#include "solvers/quasistatic.h"
#include "solvers/simulation.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

using testing::kDeg;

// max |c''| over the revolution, from second differences of a path sampled finely (the
// path need not close, so no wrap-around).
double MaxCurvatureOfPath(const solvers::Trajectory& fine) {
  const std::size_t n = fine.centre.size();
  const double dpsi = 2.0 * std::numbers::pi / static_cast<double>(n - 1);
  double worst = 0.0;
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const Eigen::Vector2d second = fine.centre[k + 1] - 2.0 * fine.centre[k] + fine.centre[k - 1];
    worst = std::max(worst, second.norm() / (dpsi * dpsi));
  }
  return worst;
}

double Diameter(const engine::Scene& scene, const solvers::Solver& solver, int steps) {
  solvers::SimulationOptions options;
  options.steps = steps;
  const solvers::SimulationResult result = solvers::Simulate(scene, solver, options);
  EXPECT_EQ(result.status, solvers::Status::kOk) << result.message;
  return result.d_trajectory;
}

// Against its definition, by brute force: the smallest count at least as large that is 8
// times a product of 2s, 3s and 5s.
TEST(FourierFriendlySteps, IsTheSmallestEightTimesAFiveSmoothCountAtLeastAsLarge) {
  const auto friendly = [](int n) {
    if (n % 8 != 0) return false;
    int rest = n / 8;
    for (const int factor : {2, 3, 5}) {
      while (rest % factor == 0) rest /= factor;
    }
    return rest == 1;
  };
  for (int at_least = 1; at_least <= 5000; ++at_least) {
    int expected = at_least;
    while (!friendly(expected)) ++expected;
    ASSERT_EQ(solvers::FourierFriendlySteps(at_least), expected) << at_least;
  }
  EXPECT_EQ(solvers::FourierFriendlySteps(3253), 3456);  // a prime count, at 3,456 = 8 x 2^4 x 3^3
  EXPECT_EQ(solvers::FourierFriendlySteps(360), 360);    // the automatic rule's floor is one
}

TEST(StepConvergence, DiameterErrorStaysWithinTheSamplingBoundAndShrinksQuadratically) {
  engine::Scene scene = testing::PaperScene();
  testing::SetRing(scene, {{5, 0.14e-3, 45.0 * kDeg}, {2, 0.05e-3, 0.0}});
  const solvers::LinearSolver solver;
  constexpr int kReferenceSteps = 1 << 16;
  const double reference = Diameter(scene, solver, kReferenceSteps);
  const double curvature = MaxCurvatureOfPath(solver.SolveRevolution(scene, kReferenceSteps));
  // The reference itself may sit below the truth by its own bound.
  const double reference_slack = curvature * std::pow(2.0 * std::numbers::pi / kReferenceSteps, 2) / 4.0;
  double previous_error = 0.0;
  for (int steps : {24, 48, 96, 192, 384}) {
    const double dpsi = 2.0 * std::numbers::pi / steps;
    const double bound = curvature * dpsi * dpsi / 4.0;
    const double error = reference - Diameter(scene, solver, steps);
    EXPECT_GE(error, -reference_slack) << steps;
    EXPECT_LE(error, bound + reference_slack) << steps;
    if (previous_error > 0.0 && error > 0.0) {
      // Quadratic convergence bounds each halving's error by a quarter of the previous
      // bound; support points moving between samples make single ratios noisy, so only
      // require that the error does not grow.
      EXPECT_LE(error, previous_error * 1.0001) << steps;
    }
    previous_error = error;
  }
}

TEST(StepConvergence, AutomaticStepsResolveRollerLobesThatPassSixtyTimesFaster) {
  // An order-7 roller lobe passes 7 R / r_b ~ 423 times per revolution. The automatic
  // resolution samples it 32 times per period of twice that rate; a fixed 360 steps
  // samples it less than once per period and aliases.
  engine::Scene scene = testing::PaperScene();
  testing::SetRing(scene, {{2, 0.14e-3, 45.0 * kDeg}});
  testing::SetRollerShapes(scene, {{7, 0.014e-3, 45.0 * kDeg}});
  const solvers::SimulationOptions automatic;
  const int steps = solvers::ChooseSteps(scene, automatic);
  EXPECT_GE(steps, static_cast<int>(2 * 32 * 7 * engine::SpinRatio(scene, 0)));
  const solvers::LinearSolver solver;
  const double reference = Diameter(scene, solver, 4 * steps);
  const double curvature = MaxCurvatureOfPath(solver.SolveRevolution(scene, 4 * steps));
  const double dpsi = 2.0 * std::numbers::pi / steps;
  const double at_automatic = Diameter(scene, solver, steps);
  EXPECT_LE(reference - at_automatic, curvature * dpsi * dpsi / 4.0);
  // Aliasing: the coarse grid misses more than the automatic grid's whole error bound.
  const double at_coarse = Diameter(scene, solver, 360);
  EXPECT_GT(reference - at_coarse, curvature * dpsi * dpsi / 4.0) << "a 360-step grid should miss the lobes";
}

TEST(StepConvergence, QuasistaticAtAutomaticStepsAgreesWithFourTimesFinerWithinTheBound) {
  engine::Scene scene = testing::PaperScene();
  testing::SetRing(scene, {{3, 0.14e-3, 45.0 * kDeg}});
  testing::SetRollerShapes(scene, {{2, 0.014e-3, 45.0 * kDeg}});
  const solvers::QuasistaticSolver solver;
  const int steps = solvers::ChooseSteps(scene, {});
  const solvers::Trajectory fine = solver.SolveRevolution(scene, 4 * steps);
  ASSERT_EQ(fine.status, solvers::Status::kOk) << fine.message;
  const double dpsi = 2.0 * std::numbers::pi / steps;
  const double bound = MaxCurvatureOfPath(fine) * dpsi * dpsi / 4.0;
  const double error = Diameter(scene, solver, 4 * steps) - Diameter(scene, solver, steps);
  constexpr double kNewtonTolerance = 2e-12;  // [m] two paths, each within 1 pm per point
  EXPECT_GE(error, -kNewtonTolerance);
  EXPECT_LE(error, bound + kNewtonTolerance);
}

// Campaigns choose steps from an error budget (SimulationOptions::path_tolerance) rather
// than resolving every roller lobe. The budget must hold against a path resolved in full,
// and the choice must be the fewest steps whose bound meets it.
TEST(StepConvergence, PathToleranceStepsKeepTheDiameterWithinTheirBudget) {
  engine::Scene scene = testing::PaperScene();
  testing::SetRing(scene, {{3, 0.05e-3, 10.0 * kDeg}, {17, 4e-6, 0.0}});
  // Roller lobes pass order x R / r_b (about 60) times per revolution: the expensive terms.
  scene.rollers[0].outline = engine::PolarProfile(0.005, 0.0, {{1, 3e-6, 0.2}, {5, 1e-6, 1.0}});
  scene.rollers[1].outline = engine::PolarProfile(0.005, 0.0, {{7, 0.5e-6, 2.0}});
  scene.rollers[2].outline = engine::PolarProfile(0.005, 0.0, {{3, 1.5e-6, 0.5}});
  const solvers::LinearSolver solver;
  const int resolved = solvers::ChooseSteps(scene, {});
  const double reference = Diameter(scene, solver, 4 * resolved);
  for (const double budget : {2e-6, 0.5e-6, 0.1e-6}) {
    solvers::SimulationOptions options;
    options.path_tolerance = budget;
    const int steps = solvers::ChooseSteps(scene, options);
    EXPECT_LT(steps, resolved) << budget;
    EXPECT_LE(solvers::SamplingErrorBound(scene, steps), budget);
    // The fewest Fourier-friendly count that meets the budget: the one before it does not.
    if (steps > options.min_steps) {
      int previous = steps - 8;
      while (solvers::FourierFriendlySteps(previous) != previous) previous -= 8;
      EXPECT_GT(solvers::SamplingErrorBound(scene, previous), budget);
    }
    EXPECT_EQ(solvers::FourierFriendlySteps(steps), steps);
    EXPECT_LE(std::abs(reference - Diameter(scene, solver, steps)), budget) << steps;
  }
}

}  // namespace
}  // namespace ringtol
