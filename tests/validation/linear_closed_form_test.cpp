// Closed-form paths of the linear model's first order (LinearSolver::Phasors; the rung adds
// the second order, which tests/validation/linear_vs_exact_test.cpp checks against the
// exact model) for the article's layout under rigid contact.
//
// Derivation. With rigid contact the two fixed rollers (at a1 = 210 deg, a2 = 330 deg,
// unit vectors e1, e2, e1.e2 = -1/2) fix the centre: to first order the bore must reach
// each fixed roller, c . e_i = dr_i + droller_i - dring(a_i - psi). A ring harmonic
// C cos(n theta + phi) gives c . e_i = -C cos(n a_i + phi - n psi). Because the rollers
// are 120 deg apart, n a_i differs between them by n * 120 deg, and:
//   n = 0 mod 3: both right-hand sides are equal, b = -C cos(n a1 + phi - n psi), so
//                c = 2 b (e1 + e2) / |e1 + e2|^2 ... with e1 + e2 = (0, -1): c = (0, -2b).
//                The path is a segment of length 4C on the y axis: D = 4C.
//   n = 1 mod 3: n a_i = a_i + (n-1) a1 (mod 360), so c = -C e(n psi - phi - (n-1) a1):
//                a circle of radius C run n times: D = 2C.
//   n = 2 mod 3: n a_i = -a_i + (n+1) a1 (mod 360), so c = -C e((n+1) a1 + phi - n psi):
//                a circle of radius C run n times backwards: D = 2C.
// Identical roller shapes with the radial phase reference present body angle -rho psi at
// every contact (rho = R/r_b), so c . e1 = c . e2 = C cos(m rho psi - phi): c = (0, -2 C cos(...)).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include <Eigen/LU>

#include "solvers/linear.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

using testing::kDeg;
constexpr double kAmplitude = 0.14e-3;  // [m] the article's C_n
constexpr double kPhase = 45.0 * kDeg;
constexpr int kSteps = 720;
// The nominal equilibrium the path is built on comes from contact geometry of 0.3 m
// quantities, so it carries ~ulp(0.3 m) = 5.6e-17 m of round-off; 64 ulp bounds it with
// the phasor recurrence's few-hundred-ulp error of 1e-4 m terms.
constexpr double kRoundOff = 64 * std::numeric_limits<double>::epsilon() * 0.302;

Eigen::Vector2d ClosedForm(int n, double psi) {
  const double a1 = 210.0 * kDeg;
  switch (n % 3) {
    case 0: return {0.0, 2.0 * kAmplitude * std::cos(n * a1 + kPhase - n * psi)};
    case 1: return -kAmplitude * engine::Direction(n * psi - kPhase - (n - 1) * a1);
    default: return -kAmplitude * engine::Direction((n + 1) * a1 + kPhase - n * psi);
  }
}

// The first-order centre path at psi_k = 2 pi k / steps, summed from the phasors.
struct FirstOrderPath {
  std::vector<double> psi;
  std::vector<Eigen::Vector2d> centre;
};

FirstOrderPath FirstOrder(const engine::Scene& scene, int steps) {
  const solvers::PhasorSum sum = solvers::LinearSolver().Phasors(scene);
  EXPECT_TRUE(sum.usable);
  FirstOrderPath path;
  for (int k = 0; k <= steps; ++k) {
    const double psi = 2.0 * std::numbers::pi * k / steps;
    Eigen::Vector2d centre = sum.offset.head<2>();
    for (std::size_t p = 0; p < sum.rates.size(); ++p) {
      const auto q = static_cast<Eigen::Index>(p);
      centre += sum.cosine.block<2, 1>(0, q) * std::cos(sum.rates[p] * psi) +
                sum.sine.block<2, 1>(0, q) * std::sin(sum.rates[p] * psi);
    }
    path.psi.push_back(psi);
    path.centre.push_back(centre);
  }
  return path;
}

class RingOrder : public ::testing::TestWithParam<int> {};

TEST_P(RingOrder, LinearRigidPathMatchesTheClosedFormAtEveryAngle) {
  const int n = GetParam();
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kRigid);
  testing::SetRing(scene, {{n, kAmplitude, kPhase}});
  const FirstOrderPath path = FirstOrder(scene, kSteps);
  for (std::size_t k = 0; k < path.psi.size(); ++k) {
    const Eigen::Vector2d expected = ClosedForm(n, path.psi[k]);
    EXPECT_NEAR(path.centre[k].x(), expected.x(), kRoundOff) << "psi index " << k;
    EXPECT_NEAR(path.centre[k].y(), expected.y(), kRoundOff) << "psi index " << k;
  }
}

INSTANTIATE_TEST_SUITE_P(ArticleOrders, RingOrder, ::testing::Values(1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 12, 15, 17, 20));

TEST(LinearClosedForm, IdenticalRollerShapesWithRadialReferenceMoveTheCentreAlongTheFixedRollersBisector) {
  constexpr int kOrder = 2;
  constexpr double kShapeAmplitude = 14e-6;  // [m] the article's roller shape error
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kRigid);
  testing::SetRollerShapes(scene, {{kOrder, kShapeAmplitude, kPhase}});
  const double rho = engine::SpinRatio(scene, 0);
  const FirstOrderPath path = FirstOrder(scene, kSteps);
  constexpr double kShapeRoundOff = kRoundOff;
  for (std::size_t k = 0; k < path.psi.size(); ++k) {
    const double expected_y = -2.0 * kShapeAmplitude * std::cos(kOrder * rho * path.psi[k] - kPhase);
    EXPECT_NEAR(path.centre[k].x(), 0.0, kShapeRoundOff);
    EXPECT_NEAR(path.centre[k].y(), expected_y, kShapeRoundOff);
  }
}

TEST(LinearClosedForm, PositionErrorsOnlyShiftTheCentreAndNeverMoveIt) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kRigid);
  testing::SetRollerPositions(scene, {{2, kAmplitude, kPhase}});
  const FirstOrderPath path = FirstOrder(scene, kSteps);
  // c . e_i = dr_i = C cos(2 a_i + phi) for both fixed rollers, solved directly.
  const Eigen::Vector2d e1 = engine::Direction(210.0 * kDeg);
  const Eigen::Vector2d e2 = engine::Direction(330.0 * kDeg);
  Eigen::Matrix2d normals;
  normals << e1.transpose(), e2.transpose();
  const Eigen::Vector2d rhs(kAmplitude * std::cos(2 * 210.0 * kDeg + kPhase),
                            kAmplitude * std::cos(2 * 330.0 * kDeg + kPhase));
  const Eigen::Vector2d expected = normals.inverse() * rhs;
  for (const Eigen::Vector2d& c : path.centre) {
    EXPECT_NEAR(c.x(), expected.x(), kRoundOff);
    EXPECT_NEAR(c.y(), expected.y(), kRoundOff);
  }
}

}  // namespace
}  // namespace ringtol
