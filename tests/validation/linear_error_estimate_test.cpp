// The linear rung's estimate of its own error against its true error, the difference of
// its D_trajectory from the exact quasi-static rung's on the same angles: the estimate
// must bound it, and must stay within a known factor of it where the error is large
// enough to matter (at small amplitudes the true error is dominated by third-order terms
// and the estimate's bound by the phases' worst case, so no lower bound is asked there).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "solvers/linear.h"
#include "solvers/quasistatic.h"
#include "solvers/simulation.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

using testing::kDeg;
constexpr int kSteps = 720;
// The quasi-static rung converges each angle to 1 pm; its D_trajectory carries twice that.
constexpr double kExactRungError = 2e-12;  // [m]

struct Comparison {
  double true_error = 0.0;  // [m] |D_linear - D_quasistatic|
  double estimate = 0.0;    // [m]
  double d_trajectory = 0.0;  // [m] the quasi-static rung's
};

Comparison Compare(const engine::Scene& scene) {
  solvers::SimulationOptions options;
  options.steps = kSteps;
  solvers::LinearOptions unlimited;
  unlimited.max_relative_error = 1.0;  // measure the estimate even where the rung would refuse
  unlimited.min_error_limit = 1.0;
  const solvers::SimulationResult linear = solvers::Simulate(scene, solvers::LinearSolver(unlimited), options);
  const solvers::SimulationResult exact = solvers::Simulate(scene, solvers::QuasistaticSolver(), options);
  EXPECT_EQ(linear.status, solvers::Status::kOk) << linear.message;
  EXPECT_EQ(exact.status, solvers::Status::kOk) << exact.message;
  return {std::abs(linear.d_trajectory - exact.d_trajectory), linear.trajectory.error_estimate, exact.d_trajectory};
}

// Ring orders across the range the rollers pass, at amplitudes from the catalogue's
// classes up to where the spring roller's travel nears its limit.
TEST(LinearErrorEstimate, BoundsTheTrueErrorOfSingleRingHarmonics) {
  for (const int order : {2, 3, 5, 10, 20}) {
    for (const double amplitude : {0.05e-3, 0.14e-3, 0.5e-3, 1.0e-3}) {
      engine::Scene scene = testing::PaperScene();
      testing::SetRing(scene, {{order, amplitude, 45.0 * kDeg}});
      if (engine::CheckGeometry(scene).issue != engine::GeometryIssue::kNone) continue;
      const Comparison c = Compare(scene);
      EXPECT_LE(c.true_error, c.estimate + kExactRungError)
          << "order " << order << ", amplitude " << amplitude * 1e3 << " mm";
    }
  }
}

// A default campaign's draw (tests/support/paper_scene.h) and the same spectra scaled to
// the loosest ring class (ISO 2768-L, 0.5 mm: 2.5 times the waterjet's 0.2 mm) and beyond.
TEST(LinearErrorEstimate, BoundsTheTrueErrorOfCampaignLikeScenesUpToTheLoosestClass) {
  for (const double scale : {1.0, 2.5, 5.0}) {
    engine::Scene scene = testing::CampaignLikeScene();
    std::vector<engine::Harmonic> ring = scene.ring.inner.harmonics();
    for (engine::Harmonic& h : ring) h.amplitude *= scale;
    testing::SetRing(scene, std::move(ring));
    const Comparison c = Compare(scene);
    EXPECT_LE(c.true_error, c.estimate + kExactRungError) << "scale " << scale;
  }
}

// Where the error matters (tens of um, growing as C^2), the estimate is a bound of the
// right size. Not for order 3, whose second-order centre error runs mostly along the path
// (three rollers 120 deg apart see the same deviation), where it is ~40 times the effect
// on D_trajectory: the bound 2 |dc| then overstates it, on the safe side.
TEST(LinearErrorEstimate, IsOfTheTrueErrorsSizeWhereTheErrorIsLarge) {
  constexpr double kTightness = 4.0;  // measured 1.4 to 3.0 on these cases
  struct Large {
    int order;
    double amplitude;  // [m]
  };
  for (const Large large : {Large{2, 1.5e-3}, Large{5, 1.0e-3}, Large{10, 1.0e-3}}) {
    engine::Scene scene = testing::PaperScene();
    testing::SetRing(scene, {{large.order, large.amplitude, 45.0 * kDeg}});
    const Comparison c = Compare(scene);
    EXPECT_LE(c.true_error, c.estimate) << "order " << large.order;
    EXPECT_LE(c.estimate, kTightness * c.true_error) << "order " << large.order;
  }
}

TEST(LinearErrorEstimate, RefusesTheArticlesOrderThreeAtTwoMillimetres) {
  engine::Scene scene = testing::PaperScene();
  testing::SetRing(scene, {{3, 2.0e-3, 45.0 * kDeg}});
  solvers::SimulationOptions options;
  options.steps = kSteps;
  const solvers::SimulationResult linear = solvers::Simulate(scene, solvers::LinearSolver(), options);
  EXPECT_NE(linear.status, solvers::Status::kOk);
  EXPECT_EQ(linear.d_trajectory, 0.0);
}

}  // namespace
}  // namespace ringtol
