#include "solvers/contact_compliance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "solvers/quasistatic.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

using testing::kDeg;

// The statics' 1 pm tolerance against the contacts' 0.15 mm penetration: far below this.
constexpr double kSolveRelative = 1e-6;

engine::Scene ArticleScene() {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);  // the article's law
  testing::SetRing(scene, {{3, 0.14e-3, 45.0 * kDeg}});
  return scene;
}

TEST(ContactCompliance, IsNotAssessedForRigidContact) {
  EXPECT_FALSE(solvers::AssessContactCompliance(testing::PaperScene(engine::ContactLaw::Model::kRigid)).assessed);
}

TEST(ContactCompliance, NamesTheDeepestContactOfTheErrorFreeAssembly) {
  const engine::Scene scene = ArticleScene();
  const solvers::ContactCompliance compliance = solvers::AssessContactCompliance(scene);
  ASSERT_TRUE(compliance.assessed);
  const solvers::Equilibrium at_rest = solvers::QuasistaticSolver().SolveStatic(engine::WithoutErrors(scene));
  const auto deepest = std::max_element(at_rest.contact_force.begin(), at_rest.contact_force.end());
  EXPECT_EQ(compliance.roller, deepest - at_rest.contact_force.begin());
  EXPECT_NEAR(compliance.force, *deepest, kSolveRelative * *deepest);
  const double penetration = std::pow(*deepest / scene.contact.stiffness, 1.0 / scene.contact.exponent);
  EXPECT_NEAR(compliance.penetration, penetration, kSolveRelative * penetration);
}

// The compliance enters through the spring (docs/model.md §4, "When the law matters"): an
// error that moves the spring roller changes the spring's force by k_b ds, and each
// contact sinks by its part of that over its linearised stiffness e F / delta. So the
// share is a part proportional to k_b delta / (e F), and a smaller one left without a
// spring rate, from the contacts' geometry.
TEST(ContactCompliance, GrowsAsTheSpringsRateAndAsThePenetration) {
  // The spring's travel (about twice the 0.15 mm penetration) changes the contact forces
  // by k_b s / P = 2 %, and the ratio delta / F with them: the proportions hold to 5 %.
  constexpr double kProportionRelative = 0.05;
  const engine::Scene scene = ArticleScene();
  const double share = solvers::AssessContactCompliance(scene).response_change;

  engine::Scene no_rate = scene;
  no_rate.rollers[0].spring.stiffness = 0.0;
  const double geometric = solvers::AssessContactCompliance(no_rate).response_change;
  EXPECT_LT(geometric, share / 5.0);

  engine::Scene twice_the_rate = scene;
  twice_the_rate.rollers[0].spring.stiffness *= 2.0;
  const double through_the_spring = share - geometric;
  EXPECT_NEAR(solvers::AssessContactCompliance(twice_the_rate).response_change - geometric, 2.0 * through_the_spring,
              kProportionRelative * 2.0 * through_the_spring);

  engine::Scene shallower = scene;
  shallower.contact.stiffness *= std::pow(10.0, scene.contact.exponent);  // a tenth of the penetration
  EXPECT_NEAR(solvers::AssessContactCompliance(shallower).response_change, share / 10.0,
              kProportionRelative * share / 10.0);
}

}  // namespace
}  // namespace ringtol
