// Supports of four to eight rollers, one or two of them on springs, against the closed form
// of their first-order paths (tests/support/paper_scene.h, EquallySpacedScene).
//
// Derivation. Let roller i sit at angle a_i (unit vector e_i) and its contact have the
// linearised normal stiffness k_i: the contact law's k for a fixed roller, k k_b / (k + k_b)
// for a spring roller (contact and spring in series). A ring harmonic C cos(n theta + phi)
// turned by psi brings the bore at roller i out by d_i = C cos(n (a_i - psi) + phi), and
// moving the centre by c changes roller i's penetration by -(c . e_i + d_i). The ring's
// force balance, to first order, is then
//   K c = -sum_i k_i d_i e_i,  K = sum_i k_i e_i e_i^T.
// With Z equally spaced fixed rollers all k_i are equal, K = (Z k / 2) I, and the sum
// over the rollers of cos(n a_i + beta) e_i vanishes unless n = +-1 (mod Z), where it is
// (Z / 2) C times a unit vector turning n times a revolution: the centre runs a circle of
// radius C (D_trajectory = 2 C) for those orders and stands still for every other order.
// Left out of the closed form: the preload F_i acting through the bore's slope and the
// normals' turn, first order in C but smaller by F / (k R) ~ n interference / R (< 2e-4
// here), and second-order terms (C / R ~ 2e-6).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include <Eigen/LU>

#include "engine/motion_law.h"
#include "solvers/dynamic.h"
#include "solvers/quasistatic.h"
#include "solvers/simulation.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

using testing::kDeg;
constexpr double kInterference = 2e-6;  // [m] fixed rollers beyond a plain fit: ~200 N each
constexpr double kStiffness = 1e8;      // [N/m] linear contact law
constexpr double kAmplitude = 0.5e-6;   // [m] C: every contact stays closed (|d| + |c| < kInterference)
constexpr double kPhase = 30.0 * kDeg;
constexpr int kSteps = 360;
// The closed form's neglected terms (see above) bound the agreement: 1e-3 C.
constexpr double kClosedFormMiss = 1e-3 * kAmplitude;

// The first-order centre path of the derivation, relative to the error-free equilibrium.
Eigen::Vector2d ClosedForm(const engine::Scene& scene, int order, double psi) {
  Eigen::Matrix2d stiffness = Eigen::Matrix2d::Zero();
  Eigen::Vector2d load = Eigen::Vector2d::Zero();
  for (const engine::Roller& roller : scene.rollers) {
    const double k = roller.mount == engine::RollerMount::kFixed
                         ? kStiffness
                         : kStiffness * roller.spring.stiffness / (kStiffness + roller.spring.stiffness);
    const Eigen::Vector2d e = engine::Direction(roller.angle);
    stiffness += k * e * e.transpose();
    load -= k * kAmplitude * std::cos(order * (roller.angle - psi) + kPhase) * e;
  }
  return stiffness.inverse() * load;
}

std::unique_ptr<solvers::Solver> Make(solvers::Rung rung) {
  solvers::SolverSettings settings;
  settings.rung = rung;
  return solvers::MakeSolver(settings);
}

struct Support {
  int rollers = 0;
  int springs = 0;
};

std::string Name(solvers::Rung rung, Support support) {
  return std::string(NameOf(solvers::kRungNames, rung)) + "_" + std::to_string(support.rollers) + "_rollers_" +
         std::to_string(support.springs) + "_springs";
}

class EquallySpacedRollers : public ::testing::TestWithParam<std::tuple<solvers::Rung, Support>> {
 protected:
  solvers::Rung rung_ = std::get<0>(GetParam());
  Support support_ = std::get<1>(GetParam());
  engine::Scene scene_ =
      testing::EquallySpacedScene(support_.rollers, support_.springs, kInterference, kStiffness);
  std::unique_ptr<solvers::Solver> solver_ = Make(rung_);
};

TEST_P(EquallySpacedRollers, EveryRingOrderMovesTheCentreAsTheContactStiffnessesSay) {
  const Eigen::Vector2d rest = solver_->SolveStatic(engine::WithoutErrors(scene_)).centre;
  for (int order = 1; order <= 2 * support_.rollers + 1; ++order) {
    engine::Scene scene = scene_;
    testing::SetRing(scene, {{order, kAmplitude, kPhase}});
    const solvers::Trajectory path = solver_->SolveRevolution(scene, kSteps);
    ASSERT_EQ(path.status, solvers::Status::kOk) << "order " << order << ": " << path.message;
    for (std::size_t k = 0; k < path.psi.size(); k += 9) {
      const Eigen::Vector2d expected = ClosedForm(scene, order, path.psi[k]);
      EXPECT_LT((path.centre[k] - rest - expected).norm(), kClosedFormMiss)
          << "order " << order << ", psi " << path.psi[k] / kDeg << " deg: expected (" << expected.transpose()
          << ") m";
    }
  }
}

// The same supports without springs: all stiffnesses equal, so the orders' rule holds.
class FixedRollersOnly : public EquallySpacedRollers {};

TEST_P(FixedRollersOnly, OnlyOrdersNextToAMultipleOfTheirCountMoveTheCentre) {
  for (int order = 1; order <= 2 * support_.rollers + 1; ++order) {
    engine::Scene scene = scene_;
    testing::SetRing(scene, {{order, kAmplitude, kPhase}});
    solvers::SimulationOptions options;
    options.steps = kSteps;
    const solvers::SimulationResult result = solvers::Simulate(scene, *solver_, options);
    ASSERT_EQ(result.status, solvers::Status::kOk) << "order " << order << ": " << result.message;
    const int remainder = order % support_.rollers;
    const bool moves = remainder == 1 || remainder == support_.rollers - 1;
    EXPECT_NEAR(result.d_trajectory, moves ? 2.0 * kAmplitude : 0.0, 2.0 * kClosedFormMiss) << "order " << order;
  }
}

const std::vector<Support> kFixedOnly = {{4, 0}, {5, 0}, {6, 0}, {7, 0}, {8, 0}};
const std::vector<Support> kWithSprings = {{4, 1}, {5, 1}, {5, 2}, {6, 2}, {7, 1}, {8, 2}};
const auto kRungs = ::testing::Values(solvers::Rung::kLinear, solvers::Rung::kQuasistatic);
const auto kNamed = [](const auto& instance) { return Name(std::get<0>(instance.param), std::get<1>(instance.param)); };

// The dynamic rung on the spring supports (kWithSprings), every order: at 0.4 deg/s, rolling
// without slip and without friction, the ring's inertia and the contacts' damping move it
// by picometres, and what is left is the integrator's error at its default tolerance
// (DynamicOptions; 1.7 nm at most over these 76 paths, 0.34 % of C), so from 30 degrees on
// (the start from rest is a transient of its own) it follows the quasistatic path within
// kDynamicMiss and the closed form within that and the closed form's own miss.
constexpr double kDynamicMiss = 3e-9;  // [m]

TEST(EquallySpacedRollersDynamic, EveryRingOrderMovesTheCentreAsOnTheTimeFreeRungs) {
  for (const Support support : kWithSprings) {
    for (int order = 1; order <= 2 * support.rollers + 1; ++order) {
      engine::Scene scene = testing::EquallySpacedScene(support.rollers, support.springs, kInterference, kStiffness);
      scene.dynamics.friction = false;
      scene.dynamics.rolling_without_slip = true;
      scene.motion = engine::ArticleLaw(12.0, 0.4 * kDeg, 1.2);
      const Eigen::Vector2d rest = solvers::QuasistaticSolver().SolveStatic(engine::WithoutErrors(scene)).centre;
      testing::SetRing(scene, {{order, kAmplitude, kPhase}});
      solvers::DynamicOptions options;
      options.steady_revolution = 0;
      const solvers::Trajectory path = solvers::DynamicSolver(options).SolveRevolution(scene, kSteps);
      const solvers::Trajectory time_free = solvers::QuasistaticSolver().SolveRevolution(scene, kSteps);
      const std::string where = Name(solvers::Rung::kDynamic, support) + ", order " + std::to_string(order);
      ASSERT_EQ(path.status, solvers::Status::kOk) << where << ": " << path.message;
      ASSERT_EQ(time_free.status, solvers::Status::kOk) << where << ": " << time_free.message;
      for (std::size_t k = kSteps / 12; k < path.psi.size(); k += 5) {
        EXPECT_LT((path.centre[k] - time_free.centre[k]).norm(), kDynamicMiss) << where << ", psi " << path.psi[k] / kDeg;
        EXPECT_LT((path.centre[k] - rest - ClosedForm(scene, order, path.psi[k])).norm(), kClosedFormMiss + kDynamicMiss)
            << where << ", psi " << path.psi[k] / kDeg;
      }
    }
  }
}


INSTANTIATE_TEST_SUITE_P(FixedRollers, EquallySpacedRollers, ::testing::Combine(kRungs, ::testing::ValuesIn(kFixedOnly)),
                         kNamed);
INSTANTIATE_TEST_SUITE_P(SpringRollers, EquallySpacedRollers,
                         ::testing::Combine(kRungs, ::testing::ValuesIn(kWithSprings)), kNamed);
INSTANTIATE_TEST_SUITE_P(Rungs, FixedRollersOnly, ::testing::Combine(kRungs, ::testing::ValuesIn(kFixedOnly)), kNamed);

}  // namespace
}  // namespace ringtol
