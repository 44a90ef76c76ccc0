// SparseRevolution: the coarse samples and every segment between them solve the same
// equilibria as the dense revolution, angle by angle.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "solvers/quasistatic.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

// Both runs converge each angle to this [m] (a campaign's 1 % of a 1 um budget); the
// same equilibrium reached from two starts differs by at most twice it.
constexpr double kTolerance = 1e-8;
constexpr double kAgreement = 2.0 * kTolerance;

TEST(SparseRevolution, EveryAngleMatchesTheDenseRevolution) {
  const engine::Scene scene = testing::CampaignLikeScene();
  solvers::QuasistaticOptions options;
  options.position_tolerance = kTolerance;
  const solvers::QuasistaticSolver solver(options);
  constexpr int kSteps = 1000;  // not a multiple of the stride: the last segment is short
  constexpr int kStride = 8;
  const solvers::Trajectory dense = solver.SolveRevolution(scene, kSteps);
  ASSERT_EQ(dense.status, solvers::Status::kOk) << dense.message;
  const std::unique_ptr<solvers::SparseRevolution> sparse = solver.SolveSparse(scene, kSteps, kStride);
  ASSERT_EQ(sparse->coarse().status, solvers::Status::kOk) << sparse->coarse().message;
  const std::vector<int>& coarse = sparse->coarse_indices();
  ASSERT_EQ(coarse.size(), sparse->coarse().psi.size());
  ASSERT_EQ(coarse.back(), kSteps);
  const std::size_t z = scene.rollers.size();
  double worst = 0.0;
  for (std::size_t s = 0; s < coarse.size(); ++s) {
    const auto k = static_cast<std::size_t>(coarse[s]);
    EXPECT_DOUBLE_EQ(sparse->coarse().psi[s], dense.psi[k]);
    worst = std::max(worst, (sparse->coarse().centre[s] - dense.centre[k]).norm());
  }
  for (std::size_t j = 0; j + 1 < coarse.size(); ++j) {
    const solvers::Trajectory segment = sparse->SolveSegment(static_cast<int>(j));
    ASSERT_EQ(segment.status, solvers::Status::kOk) << segment.message;
    ASSERT_EQ(segment.psi.size(), static_cast<std::size_t>(coarse[j + 1] - coarse[j] - 1));
    ASSERT_EQ(segment.travel.size(), segment.psi.size() * z);
    for (std::size_t s = 0; s < segment.psi.size(); ++s) {
      const auto k = static_cast<std::size_t>(coarse[j]) + 1 + s;
      EXPECT_DOUBLE_EQ(segment.psi[s], dense.psi[k]);
      worst = std::max(worst, (segment.centre[s] - dense.centre[k]).norm());
    }
  }
  EXPECT_LE(worst, kAgreement);
}

}  // namespace
}  // namespace ringtol
