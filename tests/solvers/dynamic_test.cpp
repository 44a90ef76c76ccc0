#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "solvers/dynamic.h"
#include "solvers/quasistatic.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

using testing::kDeg;

// The heavily damped contacts (c_max = 1e5 N s/m against a linearised stiffness of about
// 1.9e5 N/m) make the ring creep to rest with a time constant near c / k = 0.5 s. After
// 12 s of rest the remaining offset is e^-24 of the initial one (~0.2 mm): far below 1 nm.
TEST(DynamicSolver, SettlesToTheQuasistaticPenaltyEquilibrium) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{3, 0.1e-3, 20.0 * kDeg}});
  solvers::DynamicOptions options;
  options.law = solvers::ArticleLaw(12.0);
  options.rolling_without_slip = true;
  const solvers::Equilibrium settled = solvers::DynamicSolver(options).SolveStatic(scene);
  const solvers::Equilibrium reference = solvers::QuasistaticSolver().SolveStatic(scene);
  ASSERT_EQ(settled.status, solvers::Status::kOk) << settled.message;
  ASSERT_EQ(reference.status, solvers::Status::kOk) << reference.message;
  EXPECT_LT((settled.centre - reference.centre).norm(), 1e-9);
  for (std::size_t i = 0; i < reference.contact_force.size(); ++i) {
    EXPECT_NEAR(settled.contact_force[i], reference.contact_force[i], 1e-5 * reference.contact_force[i]) << "roller " << i;
  }
}

// At a slow steady rate the damping forces vanish with the velocities, and the dynamic
// path approaches the quasistatic one. The lag is about the creep time constant times the
// centre's speed: tau * rate * |dx/dpsi| ~ 0.5 s * 0.2 deg/s * 0.3 mm/rad ~ 0.5 um; the
// inertial force m x'' is 1e-6 of that. Halving the rate must about halve the difference.
TEST(DynamicSolver, SlowRotationApproachesTheQuasistaticPath) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{3, 0.1e-3, 20.0 * kDeg}});
  const solvers::Trajectory quasistatic = solvers::QuasistaticSolver().SolveRevolution(scene, 72);
  ASSERT_EQ(quasistatic.status, solvers::Status::kOk) << quasistatic.message;
  double previous = 0.0;
  for (const double rate_deg : {0.4, 0.2}) {
    solvers::DynamicOptions options;
    options.law = solvers::ArticleLaw(12.0, rate_deg * kDeg, 1.2);
    options.rolling_without_slip = true;
    const solvers::Trajectory path = solvers::DynamicSolver(options).SolveRevolution(scene, 72);
    ASSERT_EQ(path.status, solvers::Status::kOk) << path.message;
    double largest = 0.0;
    // Skip the first 30 degrees: the start from rest is a transient of its own.
    for (std::size_t k = 6; k < path.centre.size(); ++k) {
      largest = std::max(largest, (path.centre[k] - quasistatic.centre[k]).norm());
    }
    EXPECT_LT(largest, 2e-6) << rate_deg << " deg/s";
    if (previous > 0.0) {
      EXPECT_NEAR(largest / previous, 0.5, 0.1) << rate_deg << " deg/s";
    }
    previous = largest;
  }
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

}  // namespace
}  // namespace ringtol
