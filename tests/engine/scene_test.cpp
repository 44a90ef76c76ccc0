#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "engine/scene.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

// One change to a scene, and whether it changes only the scene's errors.
struct Change {
  std::string name;
  bool error;
  std::function<void(engine::Scene&)> apply;
};

// A change to every field of Scene, Ring and Roller (engine/scene.h), applied to a scene
// that has errors already.
std::vector<Change> EveryField() {
  const std::vector<engine::Harmonic> lobes = {{3, 1e-6, 0.2}};
  return {
      {"ring form", true, [lobes](engine::Scene& s) { testing::SetRing(s, lobes); }},
      {"ring form of zero amplitude", true, [](engine::Scene& s) { testing::SetRing(s, {{4, 0.0, 0.0}}); }},
      {"ring bore", false, [](engine::Scene& s) { s.ring.inner = engine::PolarProfile(0.303, 0.0, {}); }},
      {"ring outer radius", false, [](engine::Scene& s) { s.ring.outer_radius += 1e-3; }},
      {"ring thickness", false, [](engine::Scene& s) { s.ring.thickness += 1e-3; }},
      {"ring mass", false, [](engine::Scene& s) { s.ring.mass += 0.1; }},
      {"ring spin inertia", false, [](engine::Scene& s) { s.ring.spin_inertia += 0.01; }},
      {"ring material", false, [](engine::Scene& s) { s.ring.material.youngs_modulus = 70e9; }},
      {"roller name", false, [](engine::Scene& s) { s.rollers[1].name = "other"; }},
      {"roller angle", false, [](engine::Scene& s) { s.rollers[1].angle += 1e-3; }},
      {"roller centre radius", false, [](engine::Scene& s) { s.rollers[1].centre_radius += 1e-6; }},
      {"roller radial offset", true, [](engine::Scene& s) { s.rollers[1].radial_offset += 1e-6; }},
      {"roller tangential offset", true, [](engine::Scene& s) { s.rollers[1].tangential_offset += 1e-6; }},
      {"roller form", true,
       [lobes](engine::Scene& s) { s.rollers[1].outline = engine::PolarProfile(0.005, 0.0, lobes); }},
      {"roller mean diameter", true,
       [](engine::Scene& s) { s.rollers[1].outline = engine::PolarProfile(0.005, -2e-6, {}); }},
      {"roller radius", false, [](engine::Scene& s) { s.rollers[1].outline = engine::PolarProfile(0.006, 0.0, {}); }},
      {"roller phase reference", false,
       [](engine::Scene& s) { s.rollers[1].phase_reference = engine::ShapePhaseReference::kGlobal; }},
      {"roller spin phase", false, [](engine::Scene& s) { s.rollers[1].spin_phase += 0.1; }},
      {"roller mount", false, [](engine::Scene& s) { s.rollers[1].mount = engine::RollerMount::kSpring; }},
      {"roller spring", false, [](engine::Scene& s) { s.rollers[0].spring.stiffness *= 1.1; }},
      {"roller mass", false, [](engine::Scene& s) { s.rollers[1].mass *= 1.1; }},
      {"roller spin inertia", false, [](engine::Scene& s) { s.rollers[1].spin_inertia *= 1.1; }},
      {"roller material", false, [](engine::Scene& s) { s.rollers[1].material.poisson_ratio = 0.28; }},
      {"roller count", false, [](engine::Scene& s) { s.rollers.pop_back(); }},
      {"roller positions", true, [lobes](engine::Scene& s) { testing::SetRollerPositions(s, lobes); }},
      {"roller positions' radius", false,
       [](engine::Scene& s) { s.roller_positions = engine::PolarProfile(2.0, 0.0, {}); }},
      {"contact law", false, [](engine::Scene& s) { s.contact.stiffness *= 1.1; }},
      {"friction", false, [](engine::Scene& s) { s.friction.static_coefficient += 0.01; }},
      {"sensor angle", false, [](engine::Scene& s) { s.sensor_angle += 0.1; }},
      {"sensor swing", false, [](engine::Scene& s) { s.sensor_swing.cutoff_upr = 50.0; }},
      {"error motion filter", false, [](engine::Scene& s) { s.error_motion_filter.cutoff_upr = 15.0; }},
      {"motion", false, [](engine::Scene& s) { s.motion = engine::TestBenchLaw(); }},
      {"dynamics", false, [](engine::Scene& s) { s.dynamics.friction = false; }},
      {"phase-locked rollers", false, [](engine::Scene& s) { s.phase_locked_rollers = true; }},
  };
}

TEST(SameWithoutErrors, AgreesWithComparingTheScenesWithoutErrorsForAChangeToEveryField) {
  const engine::Scene base = testing::CampaignLikeScene();
  for (const Change& change : EveryField()) {
    engine::Scene changed = base;
    change.apply(changed);
    const bool reference = engine::WithoutErrors(base) == engine::WithoutErrors(changed);
    EXPECT_EQ(reference, change.error) << change.name;
    EXPECT_EQ(engine::SameWithoutErrors(base, changed), reference) << change.name;
    EXPECT_EQ(engine::SameWithoutErrors(changed, base), reference) << change.name;
    EXPECT_EQ(engine::SameWithoutErrors(engine::WithoutErrors(base), changed), reference) << change.name;
  }
}

TEST(HasErrors, AgreesWithComparingTheSceneWithItselfWithoutErrors) {
  const engine::Scene perfect = testing::PaperScene();
  EXPECT_FALSE(engine::HasErrors(perfect));
  EXPECT_TRUE(engine::HasErrors(testing::CampaignLikeScene()));
  for (const Change& change : EveryField()) {
    engine::Scene changed = perfect;
    change.apply(changed);
    EXPECT_EQ(engine::HasErrors(changed), !(engine::WithoutErrors(changed) == changed)) << change.name;
    EXPECT_EQ(engine::HasErrors(changed), change.error) << change.name;
  }
}

// Two rollers of radius r on one centre circle of radius rho, an angle apart, have their
// centres 2 rho sin(angle / 2) apart: they touch at angle* = 2 asin(r / rho).
TEST(CheckGeometry, FindsTwoRollersThatOverlapFromTheAngleAtWhichTheyTouch) {
  engine::Scene scene = testing::PaperScene();
  const engine::Roller& spring = scene.rollers[0];
  const double rho = spring.centre_radius;
  const double r = spring.outline.radius();
  const double touching = 2.0 * std::asin(r / rho);
  // Well above the angle's rounding (~1e-16 rad) and well below any overlap that matters.
  constexpr double kAngleStep = 1e-9;

  scene.rollers[1].angle = spring.angle + touching + kAngleStep;
  EXPECT_EQ(engine::CheckGeometry(scene).issue, engine::GeometryIssue::kNone);

  const double angle = touching - 1e-3;
  scene.rollers[1].angle = spring.angle + angle;
  const engine::GeometryCheck check = engine::CheckGeometry(scene);
  ASSERT_EQ(check.issue, engine::GeometryIssue::kRollersOverlap) << check.message;
  EXPECT_EQ(check.roller, 1);
  EXPECT_EQ(check.other_roller, 0);
  // A sine and a difference of nearby numbers of ~10 mm: a few ulp of 10 mm.
  constexpr double kRounding = 1e-15;
  EXPECT_NEAR(check.overlap, 2.0 * r - 2.0 * rho * std::sin(angle / 2.0), kRounding);

  // A roller turns, so its largest radius faces the other roller at some point: a lobe's
  // amplitude adds to its reach.
  scene.rollers[1].angle = spring.angle + touching + kAngleStep;
  scene.rollers[1].outline = engine::PolarProfile(r, 0.0, {{1, 1e-6, 0.0}});
  EXPECT_EQ(engine::CheckGeometry(scene).issue, engine::GeometryIssue::kRollersOverlap);
}

}  // namespace
}  // namespace ringtol
