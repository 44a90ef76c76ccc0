// The linear rung against the exact quasi-static rung: they must agree to third order in
// amplitude / radius, the linear rung carrying the second order (solvers/linear.cpp).
//
// Where a first-order path drops terms: (1) the support function of a polar outline is
// h(phi) = r - r'^2 / (2 r) + ..., so a harmonic of order n and amplitude C errs by up to
// (n C)^2 / (2 R) in the gap; (2) the contact normals turn by |c| / R as the centre moves,
// which errs by |c|^2 / (2 R) in c . e_i, with |c| <= 2 C here. The response of the centre
// to a gap change is at most 2 for this layout (c . e_i = dg with e1 . e2 = -1/2), so
//   |c_first_order - c_exact| <= 2 ((n C)^2 + (2 C)^2) / (2 R) = ((n^2 + 4) C^2) / R,
// which the rung's path, carrying those terms, must stay well within.
#include <gtest/gtest.h>

#include <algorithm>

#include "solvers/linear.h"
#include "solvers/quasistatic.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

using testing::kDeg;
constexpr int kSteps = 360;

// The largest distance between the two paths [m]; it must lie within half the linear
// rung's estimate, which bounds every point's remainder (plus the reference's 1 pm).
double MaxDifference(const engine::Scene& scene) {
  constexpr double kReferenceError = 1e-12;  // [m] the quasistatic rung's Newton tolerance
  const solvers::Trajectory linear = solvers::LinearSolver().SolveRevolution(scene, kSteps);
  const solvers::Trajectory exact = solvers::QuasistaticSolver().SolveRevolution(scene, kSteps);
  EXPECT_EQ(linear.status, solvers::Status::kOk) << linear.message;
  EXPECT_EQ(exact.status, solvers::Status::kOk) << exact.message;
  double worst = 0.0;
  for (std::size_t k = 0; k < std::min(linear.centre.size(), exact.centre.size()); ++k) {
    worst = std::max(worst, (linear.centre[k] - exact.centre[k]).norm());
  }
  EXPECT_LE(worst, linear.error_estimate / 2.0 + kReferenceError);
  return worst;
}

// Halving C must divide the difference by 8 (third order); 6 to 16 allows for a fourth-order
// share at these amplitudes, and fails a second-order one (4).
constexpr double kLowestRatio = 6.0;
constexpr double kHighestRatio = 16.0;

struct Case {
  const char* name;
  engine::ContactLaw::Model law;
  int order;
};

class LinearVersusExact : public ::testing::TestWithParam<Case> {};

TEST_P(LinearVersusExact, AgreeToThirdOrderInAmplitude) {
  const Case c = GetParam();
  constexpr double kAmplitude = 0.14e-3;  // [m]
  constexpr double kRadius = 0.302;       // [m]
  auto scene_with = [&](double amplitude) {
    engine::Scene scene = testing::PaperScene(c.law);
    testing::SetRing(scene, {{c.order, amplitude, 45.0 * kDeg}});
    return scene;
  };
  const double full = MaxDifference(scene_with(kAmplitude));
  const double half = MaxDifference(scene_with(kAmplitude / 2.0));
  // What the first-order path alone missed (the header): the second order must beat it.
  const double first_order_bound = (c.order * c.order + 4) * kAmplitude * kAmplitude / kRadius;
  EXPECT_LE(full, first_order_bound);
  EXPECT_GE(full / half, kLowestRatio) << "full " << full << " half " << half;
  EXPECT_LE(full / half, kHighestRatio) << "full " << full << " half " << half;
}

INSTANTIATE_TEST_SUITE_P(
    RingOrders, LinearVersusExact,
    ::testing::Values(Case{"rigid_order2", engine::ContactLaw::Model::kRigid, 2},
                      Case{"rigid_order3", engine::ContactLaw::Model::kRigid, 3},
                      Case{"rigid_order7", engine::ContactLaw::Model::kRigid, 7},
                      Case{"penalty_order2", engine::ContactLaw::Model::kPenalty, 2},
                      Case{"penalty_order3", engine::ContactLaw::Model::kPenalty, 3},
                      Case{"penalty_order7", engine::ContactLaw::Model::kPenalty, 7}),
    [](const ::testing::TestParamInfo<Case>& param) { return std::string(param.param.name); });

TEST(LinearVersusExact, RollerShapeAndPositionErrorsAlsoAgreeToThirdOrder) {
  auto scene_with = [](double scale) {
    engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kRigid);
    testing::SetRing(scene, {{2, 0.14e-3 * scale, 45.0 * kDeg}});
    testing::SetRollerPositions(scene, {{5, 0.14e-3 * scale, 45.0 * kDeg}});
    testing::SetRollerShapes(scene, {{7, 0.014e-3 * scale, 45.0 * kDeg}});
    return scene;
  };
  const double full = MaxDifference(scene_with(1.0));
  const double half = MaxDifference(scene_with(0.5));
  EXPECT_GE(full / half, kLowestRatio) << "full " << full << " half " << half;
  EXPECT_LE(full / half, kHighestRatio) << "full " << full << " half " << half;
}

TEST(RigidVersusPenalty, PenaltyPathConvergesToTheRigidPathAsContactStiffens) {
  // Penetration under a load F is (F/k)^(1/e); its variation along the path shrinks with
  // it, so the gap between the laws must fall as k^(-1/e): by 1000^(2/3) = 100 here.
  engine::Scene rigid = testing::PaperScene(engine::ContactLaw::Model::kRigid);
  testing::SetRing(rigid, {{3, 0.14e-3, 45.0 * kDeg}});
  const solvers::Trajectory reference = solvers::QuasistaticSolver().SolveRevolution(rigid, kSteps);
  ASSERT_EQ(reference.status, solvers::Status::kOk);
  auto difference = [&](double stiffness) {
    engine::Scene penalty = rigid;
    penalty.contact.model = engine::ContactLaw::Model::kPenalty;
    penalty.contact.stiffness = stiffness;
    const solvers::Trajectory path = solvers::QuasistaticSolver().SolveRevolution(penalty, kSteps);
    EXPECT_EQ(path.status, solvers::Status::kOk) << path.message;
    // Compare shapes: remove the static compliance offset of the first point.
    double worst = 0.0;
    for (std::size_t k = 0; k < path.centre.size(); ++k) {
      const Eigen::Vector2d shape = path.centre[k] - path.centre[0];
      const Eigen::Vector2d rigid_shape = reference.centre[k] - reference.centre[0];
      worst = std::max(worst, (shape - rigid_shape).norm());
    }
    return worst;
  };
  const double soft = difference(1e7);
  const double stiff = difference(1e10);
  constexpr double kExpectedRatio = 100.0;  // 1000^(1/1.5)
  constexpr double kRatioSlack = 2.0;       // higher-order terms at the soft end
  EXPECT_GT(soft / stiff, kExpectedRatio / kRatioSlack) << soft << " " << stiff;
  EXPECT_LT(soft / stiff, kExpectedRatio * kRatioSlack) << soft << " " << stiff;
}

}  // namespace
}  // namespace ringtol
