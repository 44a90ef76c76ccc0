#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "solvers/linear.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

using testing::kDeg;

void ExpectSamePath(const solvers::Trajectory& a, const solvers::Trajectory& b) {
  ASSERT_EQ(a.status, b.status);
  ASSERT_EQ(a.centre.size(), b.centre.size());
  for (std::size_t k = 0; k < a.centre.size(); ++k) {
    EXPECT_EQ(a.centre[k], b.centre[k]) << "angle " << k;
  }
  EXPECT_EQ(a.contact_force, b.contact_force);
  EXPECT_EQ(a.travel, b.travel);
}

// The solver keeps the last error-free assembly's linearisation. Whatever it kept, a
// scene must give exactly what a fresh solver gives: a stale linearisation for a changed
// nominal (another preload, another contact law) would shift every number.
TEST(LinearSolver, ReusedSolverGivesWhatAFreshOneGives) {
  engine::Scene a = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(a, {{3, 0.1e-3, 20.0 * kDeg}});
  engine::Scene b = a;
  b.rollers[0].spring.preload *= 2.0;
  engine::Scene c = a;
  testing::SetRing(c, {{4, 0.05e-3, 0.0}});
  engine::Scene d = testing::PaperScene(engine::ContactLaw::Model::kRigid);
  testing::SetRing(d, {{3, 0.1e-3, 20.0 * kDeg}});
  const solvers::LinearSolver reused;
  for (const engine::Scene* scene : {&a, &b, &a, &c, &d, &a}) {
    ExpectSamePath(reused.SolveRevolution(*scene, 360), solvers::LinearSolver().SolveRevolution(*scene, 360));
  }
  const solvers::Equilibrium fresh = solvers::LinearSolver().SolveStatic(b);
  const solvers::Equilibrium again = reused.SolveStatic(b);
  EXPECT_EQ(again.centre, fresh.centre);
  EXPECT_EQ(again.contact_force, fresh.contact_force);
}

// The path is summed three ways, by the step count's factors: with steps divisible by
// four the integer rates (ring orders) come from a quarter turn by symmetry, with other
// counts every angle is summed. The same angle must get the same numbers whichever way,
// for ring orders of both parities beside roller lobes, whose rates are not integers.
TEST(LinearSolver, EveryWayOfSummingThePathGivesTheSameAngles) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{2, 60e-6, 0.5}, {3, 20e-6, 1.0}, {4, 9e-6, 2.0}, {7, 5e-6, 0.3}, {12, 2e-6, 1.1}});
  testing::SetRollerShapes(scene, {{1, 1e-6, 0.2}, {3, 2e-6, 0.4}});
  scene.rollers[1].radial_offset = 4e-6;
  // Each sum is exact to the phasor recurrence's round-off, ~1e-13 of a term (anchored
  // every 512 angles): 1e-17 m of 1e-4 m centre terms, 1e-12 N of ~10 N force terms.
  // A hundred times that leaves room for the different order of addition.
  constexpr double kPositionRoundOff = 1e-15;  // [m]
  constexpr double kForceRoundOff = 1e-10;     // [N]
  const solvers::LinearSolver solver;
  for (const int steps : {18, 723}) {
    // steps: every angle; 2 steps (= 2 mod 4): every angle; 4 steps: folded.
    const solvers::Trajectory once = solver.SolveRevolution(scene, steps);
    const solvers::Trajectory twice = solver.SolveRevolution(scene, 2 * steps);
    const solvers::Trajectory four_times = solver.SolveRevolution(scene, 4 * steps);
    ASSERT_EQ(once.status, solvers::Status::kOk) << once.message;
    for (std::size_t k = 0; k < once.centre.size(); ++k) {
      for (const auto& [finer, factor] : {std::pair{&twice, 2u}, std::pair{&four_times, 4u}}) {
        const std::size_t j = factor * k;
        EXPECT_NEAR(once.centre[k].x(), finer->centre[j].x(), kPositionRoundOff) << steps << " steps, angle " << k;
        EXPECT_NEAR(once.centre[k].y(), finer->centre[j].y(), kPositionRoundOff) << steps << " steps, angle " << k;
        for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
          const std::size_t z = scene.rollers.size();
          EXPECT_NEAR(once.travel[k * z + i], finer->travel[j * z + i], kPositionRoundOff);
          EXPECT_NEAR(once.contact_force[k * z + i], finer->contact_force[j * z + i], kForceRoundOff);
        }
      }
    }
  }
}

}  // namespace
}  // namespace ringtol
