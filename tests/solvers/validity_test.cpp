// The rungs' verdicts on scenes at the edge of the model's domain: every rung must give
// the same status, and none may return a number where another refuses. The table states
// each scene's expected status per rung; where a rung genuinely cannot agree, its row
// says which status it gives instead and why.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "solvers/dynamic.h"
#include "solvers/linear.h"
#include "solvers/quasistatic.h"
#include "solvers/simulation.h"
#include "solvers/validity.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

using solvers::Status;
using testing::kDeg;

// Angles per revolution: every scene's fastest term (ring order 40) is sampled 9 times a
// period, so a two-point contact at a lobe's crest is seen; the dynamic rung's cost is its
// integration, which the sample count barely changes.
constexpr int kSteps = 360;

// A rung that genuinely cannot give the scene's status, the one it gives instead, and why.
struct Exception {
  solvers::Rung rung;
  Status status;
  const char* why;
};

struct EdgeScene {
  std::string name;
  engine::Scene scene;
  Status expected;
  std::vector<Exception> exceptions;
};

engine::Scene WithRing(std::vector<engine::Harmonic> harmonics) {
  engine::Scene scene = testing::PaperScene();
  testing::SetRing(scene, std::move(harmonics));
  return scene;
}

engine::Scene WithSpring(engine::Scene scene, double preload, double travel_limit) {
  scene.rollers[0].spring.preload = preload;
  scene.rollers[0].spring.travel_limit = travel_limit;
  return scene;
}

// Order 3 on three rollers 120 deg apart: every contact sees the same deviation, so the
// fixed rollers lift the centre by 2 C and the spring roller travels 3 C (C the
// amplitude) about its preloaded position.
std::vector<EdgeScene> Table() {
  std::vector<EdgeScene> table;
  auto add = [&](std::string name, engine::Scene scene, Status expected, std::vector<Exception> exceptions = {}) {
    table.push_back({std::move(name), std::move(scene), expected, std::move(exceptions)});
  };
  add("error_free", testing::PaperScene(), Status::kOk);
  add("order3_0.14mm", WithRing({{3, 0.14e-3, 45.0 * kDeg}}), Status::kOk);
  add("order20_0.05mm", WithRing({{20, 0.05e-3, 10.0 * kDeg}}), Status::kOk);
  // A valid scene beyond the linear rung's range: its second-order error (~12 um of the
  // 2.06 mm D_trajectory, estimated at 30 um) is no longer small. The rung refuses its
  // approximation, not the scene: the exact rungs' numbers stand.
  add("order10_1.0mm", WithRing({{10, 1.0e-3, 45.0 * kDeg}}), Status::kOk,
      {{solvers::Rung::kLinear, Status::kBeyondLinearRange,
        "its first-order error, not the scene, is out of range"}});
  // 3 C = 6 mm of travel against a 5 mm limit: the exact rungs meet it at -5.06 mm, the
  // linear rung, whose first-order travel differs by ~0.1 mm, at -5.02 mm.
  add("order3_2.0mm", WithRing({{3, 2.0e-3, 45.0 * kDeg}}), Status::kRollerDoesNotFit);
  // A spring roller flattened by a second-order lobe (curvature radius
  // (r - C)^2 / (r - 5 C) = 322 mm at its valleys, convex while C < r / 5) against the
  // 302 mm bore: its flat side bridges the bore and touches it at two points. With the
  // valley facing the bore at psi = 0 the scene is mirror-symmetric about the roller's
  // axis, so both points touch equally in the static equilibrium.
  {
    engine::Scene scene = testing::PaperScene();
    scene.rollers[0].outline = engine::PolarProfile(5e-3, 0.0, {{2, 0.99e-3, 180.0 * kDeg}});
    add("flat_spring_roller", scene, Status::kTwoPointContact);
  }
  // C > R / (n^2 + 1) = 0.189 mm: the bore has inward bumps.
  add("order40_0.3mm", WithRing({{40, 0.3e-3, 0.0}}), Status::kRingNotConvex);
  {
    engine::Scene scene = testing::PaperScene();
    testing::SetRollerShapes(scene, {{8, 0.1e-3, 0.0}});  // > r / (m^2 + 1) = 0.077 mm
    add("roller_order8_0.1mm", scene, Status::kRollerNotConvex);
  }
  // 3 C = 0.42 mm of travel swing against a 0.3 mm limit.
  add("travel_limit_0.3mm", WithSpring(WithRing({{3, 0.14e-3, 45.0 * kDeg}}), 19.3, 0.3e-3),
      Status::kRollerDoesNotFit);
  // Preload 0.4 N = 0.30 mm of spring travel: the 0.42 mm swing unloads it completely.
  add("preload_0.4N", WithSpring(WithRing({{3, 0.14e-3, 45.0 * kDeg}}), 0.4, 5e-3), Status::kLiftOff);
  // Preload 1.0 N = 0.75 mm of spring travel: the swing leaves about 0.4 N at its lightest.
  add("preload_1.0N", WithSpring(WithRing({{3, 0.14e-3, 45.0 * kDeg}}), 1.0, 5e-3), Status::kOk);
  return table;
}

std::unique_ptr<solvers::Solver> Make(solvers::Rung rung) {
  if (rung == solvers::Rung::kDynamic) {
    solvers::DynamicOptions options;
    options.steady_revolution = 0;  // the first revolution decides; a later one costs 3 more
    return std::make_unique<solvers::DynamicSolver>(options);
  }
  solvers::SolverSettings settings;
  settings.rung = rung;
  return solvers::MakeSolver(settings);
}

TEST(EdgeScenes, EveryRungGivesTheTablesStatusAndNoNumberWhereItRefuses) {
  solvers::SimulationOptions options;
  options.steps = kSteps;
  for (const EdgeScene& edge : Table()) {
    for (const auto& [rung, rung_name] : solvers::kRungNames) {
      const solvers::SimulationResult result = solvers::Simulate(edge.scene, *Make(rung), options);
      Status expected = edge.expected;
      for (const Exception& exception : edge.exceptions) {
        if (exception.rung == rung) expected = exception.status;
      }
      EXPECT_EQ(solvers::StatusName(result.status), solvers::StatusName(expected))
          << edge.name << " on the " << rung_name << " rung: " << result.message;
      if (result.status != Status::kOk) {
        EXPECT_EQ(result.d_trajectory, 0.0) << edge.name << " on the " << rung_name << " rung";
      }
    }
  }
}

TEST(ValidityCheck, FlagsATravelBeyondTheLimitInAnyRungsPath) {
  const engine::Scene scene = testing::PaperScene();
  solvers::Trajectory path;
  path.initial.centre = Eigen::Vector2d::Zero();
  path.initial.travel = {0.0, 0.0, 0.0};
  path.initial.contact_force = {10.0, 10.0, 10.0};
  path.psi = {0.0, 1.0};
  path.centre = {Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  const double limit = scene.rollers[0].spring.travel_limit;
  path.travel = {0.0, 0.0, 0.0, -1.01 * limit, 0.0, 0.0};
  path.contact_force = {10.0, 10.0, 10.0, 10.0, 10.0, 10.0};
  solvers::ValidityCheck(scene).Check(path);
  EXPECT_EQ(path.status, Status::kRollerDoesNotFit) << path.message;
  EXPECT_EQ(path.failure_angle, 1.0);
}

TEST(ValidityCheck, FlagsAContactThatCarriesNoForce) {
  const engine::Scene scene = testing::PaperScene();
  solvers::Equilibrium equilibrium;
  equilibrium.travel = {0.0, 0.0, 0.0};
  equilibrium.contact_force = {10.0, 0.0, 10.0};
  solvers::ValidityCheck(scene).Check(equilibrium);
  EXPECT_EQ(equilibrium.status, Status::kLiftOff) << equilibrium.message;
}

// The two-point search's Blaschke test reads the profiles' bounds first and their exact
// curvature radii only where the bounds cannot decide: its verdict must be the exact
// radii's at every gap, from far inside the certificate to either side of its threshold
// (where only the exact radii can decide) and for rollers from round to bore-flat lobes.
TEST(ValidityCheck, TwoPointSearchIsNeededExactlyWhereTheExactCurvatureRadiiSay) {
  const std::vector<std::vector<engine::Harmonic>> shapes = {
      {}, {{3, 2e-6, 0.4}, {5, 1e-6, 1.0}}, {{2, 0.03 * 5e-3, 0.2}}, {{4, 0.055 * 5e-3, -0.3}, {6, 1e-5, 0.7}}};
  for (const std::vector<engine::Harmonic>& shape : shapes) {
    engine::Scene scene = testing::CampaignLikeScene();
    testing::SetRollerShapes(scene, shape);
    const solvers::ValidityCheck check(scene);
    for (int i = 0; i < static_cast<int>(scene.rollers.size()); ++i) {
      const engine::PolarProfile& roller = scene.rollers[static_cast<std::size_t>(i)].outline;
      const double roller_radius = 1.0 / roller.MinCurvature();
      const double ring_radius = 1.0 / scene.ring.inner.MaxCurvature();
      const double threshold = ring_radius - roller_radius;  // [m] the gap where the verdict turns
      for (const double gap : {-1e-3, -1e-6, 0.0, threshold, std::nextafter(threshold, -1.0),
                               std::nextafter(threshold, 1.0), 2.0 * threshold}) {
        EXPECT_EQ(check.NeedsTwoPointSearch(i, gap), roller_radius + gap >= ring_radius)
            << "roller " << i << " of shape " << shape.size() << " gap " << gap;
      }
    }
  }
}

}  // namespace
}  // namespace ringtol
