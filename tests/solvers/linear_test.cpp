#include <gtest/gtest.h>

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

}  // namespace
}  // namespace ringtol
