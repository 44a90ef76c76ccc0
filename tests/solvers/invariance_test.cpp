// Symmetries the physics has, so every solver must have them too.
#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>
#include <string>

#include <Eigen/Geometry>

#include "solvers/linear.h"
#include "solvers/quasistatic.h"
#include "solvers/simulation.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

using testing::kDeg;
constexpr int kSteps = 360;
// Every path coordinate is computed from ~0.3 m quantities: agreement to ~100 ulp of that.
constexpr double kPositionRoundOff = 1e-13;  // [m]
// Contact forces ~20 N depend on penetrations ~1e-4 m with stiffness ~2e5 N/m: 1e-13 m
// of round-off in position is ~2e-8 N.
constexpr double kForceRoundOff = 1e-7;      // [N]

// `scene` with errors of every kind, their amplitudes `scale` times the article's.
engine::Scene WithErrors(engine::Scene scene, double scale) {
  testing::SetRing(scene, {{2, scale * 0.05e-3, 10.0 * kDeg}, {3, scale * 0.14e-3, 45.0 * kDeg},
                           {7, scale * 0.02e-3, 80.0 * kDeg}});
  testing::SetRollerPositions(scene, {{2, scale * 0.03e-3, 20.0 * kDeg}});
  testing::SetRollerShapes(scene, {{2, scale * 0.014e-3, 45.0 * kDeg}});
  scene.rollers[1].tangential_offset = scale * 0.02e-3;
  scene.sensor_angle = 30.0 * kDeg;
  return scene;
}

engine::Scene ErrorScene(engine::ContactLaw::Model law) { return WithErrors(testing::PaperScene(law), 1.0); }

// Six rollers, two of them on springs, every contact loaded (EquallySpacedScene, 200 N at
// 1e8 N/m), with errors a 400th of the article's (0.7 um at most together), so none opens.
constexpr double kSixRollerStiffness = 1e8;  // [N/m]
engine::Scene SixRollerErrorScene() {
  return WithErrors(testing::EquallySpacedScene(6, 2, 2e-6, kSixRollerStiffness), 1.0 / 400.0);
}

// The scenes every symmetry is checked on, each with the force its position round-off makes.
struct SymmetryScene {
  engine::Scene scene;
  double force_round_off = 0.0;  // [N]
};
std::vector<SymmetryScene> SymmetryScenes() {
  return {{ErrorScene(engine::ContactLaw::Model::kRigid), kForceRoundOff},
          {ErrorScene(engine::ContactLaw::Model::kPenalty), kForceRoundOff},
          {SixRollerErrorScene(), kSixRollerStiffness * kPositionRoundOff}};
}

std::vector<engine::Harmonic> Rotated(const std::vector<engine::Harmonic>& harmonics, double angle) {
  std::vector<engine::Harmonic> out = harmonics;
  for (engine::Harmonic& h : out) h.phase -= h.order * angle;  // r'(theta) = r(theta - angle)
  return out;
}

// The same assembly turned by `angle` about the origin.
engine::Scene RotatedScene(const engine::Scene& scene, double angle) {
  engine::Scene turned = scene;
  testing::SetRing(turned, Rotated(scene.ring.inner.harmonics(), angle));
  testing::SetRollerPositions(turned, Rotated(scene.roller_positions.harmonics(), angle));
  for (engine::Roller& r : turned.rollers) {
    r.angle += angle;
    r.spring.axis_angle += angle;
  }
  turned.sensor_angle += angle;
  return turned;
}

class Invariance : public ::testing::TestWithParam<solvers::Rung> {
 protected:
  static std::unique_ptr<solvers::Solver> Make(solvers::Rung rung) {
    solvers::SolverSettings settings;
    settings.rung = rung;
    return solvers::MakeSolver(settings);
  }
  std::unique_ptr<solvers::Solver> solver_ = Make(GetParam());
};

TEST_P(Invariance, RotatingTheWholeSceneRotatesThePath) {
  for (const auto& [scene, force_round_off] : SymmetryScenes()) {
    constexpr double kTurn = 73.0 * kDeg;
    const solvers::Trajectory original = solver_->SolveRevolution(scene, kSteps);
    const solvers::Trajectory turned = solver_->SolveRevolution(RotatedScene(scene, kTurn), kSteps);
    ASSERT_EQ(original.status, solvers::Status::kOk) << original.message;
    ASSERT_EQ(turned.status, solvers::Status::kOk) << turned.message;
    const Eigen::Matrix2d rotation = Eigen::Rotation2Dd(kTurn).toRotationMatrix();
    for (std::size_t k = 0; k < original.centre.size(); ++k) {
      EXPECT_LT((rotation * original.centre[k] - turned.centre[k]).norm(), kPositionRoundOff) << k;
    }
    for (std::size_t k = 0; k < original.contact_force.size(); ++k) {
      EXPECT_NEAR(original.contact_force[k], turned.contact_force[k], force_round_off);
    }
  }
}

TEST_P(Invariance, RelabellingRollersChangesNothing) {
  for (const auto& [scene, force_round_off] : SymmetryScenes()) {
    if (scene.contact.model == engine::ContactLaw::Model::kRigid) continue;
    engine::Scene relabelled = scene;
    std::rotate(relabelled.rollers.begin(), relabelled.rollers.begin() + 1, relabelled.rollers.end());
    const solvers::Trajectory a = solver_->SolveRevolution(scene, kSteps);
    const solvers::Trajectory b = solver_->SolveRevolution(relabelled, kSteps);
    ASSERT_EQ(a.status, solvers::Status::kOk) << a.message;
    ASSERT_EQ(b.status, solvers::Status::kOk) << b.message;
    const std::size_t z = scene.rollers.size();
    for (std::size_t k = 0; k < a.centre.size(); ++k) {
      EXPECT_LT((a.centre[k] - b.centre[k]).norm(), kPositionRoundOff);
      for (std::size_t i = 0; i < z; ++i) {
        EXPECT_NEAR(a.contact_force[k * z + (i + 1) % z], b.contact_force[k * z + i], force_round_off);
      }
    }
  }
}

TEST_P(Invariance, ShiftingTheRingPhaseOnlyShiftsWhereThePathStarts) {
  // r(theta) with phases phi_n + n delta is r(theta + delta): the ring has simply been
  // turned back by delta, so with circular rollers the path at psi is the original path
  // at psi - delta. With delta a whole number of steps the sampled paths coincide.
  constexpr int kShift = 37;
  const double delta = 2.0 * std::numbers::pi * kShift / kSteps;
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  const std::vector<engine::Harmonic> ring = {{2, 0.05e-3, 10.0 * kDeg}, {5, 0.14e-3, 45.0 * kDeg}};
  testing::SetRing(scene, ring);
  engine::Scene shifted = scene;
  testing::SetRing(shifted, Rotated(ring, -delta));
  const solvers::Trajectory a = solver_->SolveRevolution(scene, kSteps);
  const solvers::Trajectory b = solver_->SolveRevolution(shifted, kSteps);
  ASSERT_EQ(a.status, solvers::Status::kOk) << a.message;
  ASSERT_EQ(b.status, solvers::Status::kOk) << b.message;
  // Newton stops within its tolerance at each angle; different starting points give
  // answers that differ by up to that tolerance.
  const double tolerance = solvers::QuasistaticOptions{}.position_tolerance + kPositionRoundOff;
  for (int k = 0; k < kSteps; ++k) {
    const auto from = static_cast<std::size_t>((k - kShift + kSteps) % kSteps);
    EXPECT_LT((b.centre[static_cast<std::size_t>(k)] - a.centre[from]).norm(), tolerance) << k;
  }
}

INSTANTIATE_TEST_SUITE_P(Solvers, Invariance, ::testing::Values(solvers::Rung::kLinear, solvers::Rung::kQuasistatic),
                         [](const auto& rung) { return std::string(NameOf(solvers::kRungNames, rung.param)); });

}  // namespace
}  // namespace ringtol
