#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include "solvers/linear.h"
#include "tests/support/paper_scene.h"

namespace ringtol {
namespace {

using testing::kDeg;

void ExpectSamePath(const solvers::Trajectory& a, const solvers::Trajectory& b) {
  ASSERT_EQ(a.status, b.status);
  ASSERT_EQ(a.centre.size(), b.centre.size());
  for (std::size_t k = 0; k < a.centre.size(); ++k) {
    EXPECT_EQ(a.centre[k], b.centre[k]) << "angle " << k;
  }
  EXPECT_EQ(a.contact_force, b.contact_force);
  EXPECT_EQ(a.travel, b.travel);
}

// The solver keeps the last error-free assembly's linearisation. Whatever it kept, a
// scene must give exactly what a fresh solver gives: a stale linearisation for a changed
// nominal (another preload, another contact law) would shift every number.
TEST(LinearSolver, ReusedSolverGivesWhatAFreshOneGives) {
  engine::Scene a = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(a, {{3, 0.1e-3, 20.0 * kDeg}});
  engine::Scene b = a;
  b.rollers[0].spring.preload *= 2.0;
  engine::Scene c = a;
  testing::SetRing(c, {{4, 0.05e-3, 0.0}});
  engine::Scene d = testing::PaperScene(engine::ContactLaw::Model::kRigid);
  testing::SetRing(d, {{3, 0.1e-3, 20.0 * kDeg}});
  const solvers::LinearSolver reused;
  for (const engine::Scene* scene : {&a, &b, &a, &c, &d, &a}) {
    ExpectSamePath(reused.SolveRevolution(*scene, 360), solvers::LinearSolver().SolveRevolution(*scene, 360));
  }
  const solvers::Equilibrium fresh = solvers::LinearSolver().SolveStatic(b);
  const solvers::Equilibrium again = reused.SolveStatic(b);
  EXPECT_EQ(again.centre, fresh.centre);
  EXPECT_EQ(again.contact_force, fresh.contact_force);
}

// The path is summed three ways, by the step count: with steps even the integer rates
// (ring orders) come from a quarter turn by symmetry, with steps odd from a half turn, and
// with too few steps for a lane group in the folded part every angle is summed. The same angle must get the same numbers whichever way,
// for ring orders of both parities beside roller lobes, whose rates are not integers.
TEST(LinearSolver, EveryWayOfSummingThePathGivesTheSameAngles) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{2, 60e-6, 0.5}, {3, 20e-6, 1.0}, {4, 9e-6, 2.0}, {7, 5e-6, 0.3}, {12, 2e-6, 1.1}});
  testing::SetRollerShapes(scene, {{1, 1e-6, 0.2}, {3, 2e-6, 0.4}});
  scene.rollers[1].radial_offset = 4e-6;
  // Each sum is exact to the phasor recurrence's round-off, ~1e-13 of a term (anchored
  // every 512 angles): 1e-17 m of 1e-4 m centre terms, 1e-12 N of ~10 N force terms.
  // A hundred times that leaves room for the different order of addition.
  constexpr double kPositionRoundOff = 1e-15;  // [m]
  constexpr double kForceRoundOff = 1e-10;     // [N]
  const solvers::LinearSolver solver;
  for (const int steps : {18, 723}) {
    // 18 steps: every angle, 723: a half turn; twice and four times as many: a quarter.
    const solvers::Trajectory once = solver.SolveRevolution(scene, steps);
    const solvers::Trajectory twice = solver.SolveRevolution(scene, 2 * steps);
    const solvers::Trajectory four_times = solver.SolveRevolution(scene, 4 * steps);
    ASSERT_EQ(once.status, solvers::Status::kOk) << once.message;
    for (std::size_t k = 0; k < once.centre.size(); ++k) {
      for (const auto& [finer, factor] : {std::pair{&twice, 2u}, std::pair{&four_times, 4u}}) {
        const std::size_t j = factor * k;
        EXPECT_NEAR(once.centre[k].x(), finer->centre[j].x(), kPositionRoundOff) << steps << " steps, angle " << k;
        EXPECT_NEAR(once.centre[k].y(), finer->centre[j].y(), kPositionRoundOff) << steps << " steps, angle " << k;
        for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
          const std::size_t z = scene.rollers.size();
          EXPECT_NEAR(once.travel[k * z + i], finer->travel[j * z + i], kPositionRoundOff);
          EXPECT_NEAR(once.contact_force[k * z + i], finer->contact_force[j * z + i], kForceRoundOff);
        }
      }
    }
  }
}

// The path is summed through the contacts' gap series (each roller term reaches two series,
// not every output row), from phasor recurrences, folded over a quarter turn (steps even)
// or a half turn (steps odd). Whatever the route, every angle must be the closed form of
// LinearSolver::Phasors summed term by term with libm in long double, plus what
// LinearSolver::SecondOrder adds at that angle (which a caller summing the phasors at angles
// of its own relies on).
TEST(LinearSolver, SummedPathEqualsTheTermByTermSumOfItsPhasors) {
  // Relative to a row's scale |offset| + sum_p (|cosine| + |sine|): the phasor recurrence
  // is exact to ~1e-13 of a term (restarted from libm every 512 angles), and summing
  // ~100 terms in another order adds ~100 x 2^-53 ~ 1e-14; ten times the sum.
  constexpr double kRelativeRoundOff = 1e-12;
  const engine::Scene scene = testing::CampaignLikeScene();
  const solvers::LinearSolver solver;
  const solvers::PhasorSum phasors = solver.Phasors(scene);
  ASSERT_TRUE(phasors.usable);
  const solvers::SecondOrderTerms corrector = solver.SecondOrder(scene);
  ASSERT_TRUE(corrector.usable());
  const std::size_t z = scene.rollers.size();
  const auto terms = static_cast<std::size_t>(phasors.rates.size());
  // The rows the trajectory returns, with where each lands in it.
  struct Row {
    Eigen::Index o;
    double (*at)(const solvers::Trajectory&, std::size_t k, std::size_t i);
    std::size_t i;
  };
  std::vector<Row> rows = {{0, [](const solvers::Trajectory& t, std::size_t k, std::size_t) { return t.centre[k].x(); }, 0},
                           {1, [](const solvers::Trajectory& t, std::size_t k, std::size_t) { return t.centre[k].y(); }, 0}};
  for (std::size_t i = 0; i < z; ++i) {
    const auto force = [](const solvers::Trajectory& t, std::size_t k, std::size_t r) {
      return t.contact_force[k * t.initial.contact_force.size() + r];
    };
    const auto travel = [](const solvers::Trajectory& t, std::size_t k, std::size_t r) {
      return t.travel[k * t.initial.travel.size() + r];
    };
    rows.push_back({phasors.first_force_row + static_cast<Eigen::Index>(i), force, i});
    if (phasors.travel_row[i] >= 0) rows.push_back({phasors.travel_row[i], travel, i});
  }
  ASSERT_EQ(rows.size(), static_cast<std::size_t>(2 + z + 1));  // one spring roller
  for (const int steps : {3200, 3201, 3202}) {  // a quarter turn, a half, a quarter at 2 (mod 4)
    const solvers::Trajectory path = solver.SolveRevolution(scene, steps);
    ASSERT_EQ(path.status, solvers::Status::kOk) << path.message;
    std::vector<long double> cosines(terms), sines(terms);
    const auto outputs = static_cast<std::size_t>(phasors.offset.size());
    std::vector<double> first(outputs), scales(outputs), travel(z), force(z);
    solvers::SecondOrderAngle second;
    double worst = 0.0;  // the largest error relative to its row's scale
    for (std::size_t k = 0; k <= static_cast<std::size_t>(steps); ++k) {
      const long double psi = 2.0L * std::numbers::pi_v<long double> * static_cast<long double>(k) / steps;
      for (std::size_t p = 0; p < terms; ++p) {
        cosines[p] = std::cos(static_cast<long double>(phasors.rates[p]) * psi);
        sines[p] = std::sin(static_cast<long double>(phasors.rates[p]) * psi);
      }
      for (std::size_t o = 0; o < outputs; ++o) {
        const auto row = static_cast<Eigen::Index>(o);
        long double sum = phasors.offset[row];
        scales[o] = std::abs(phasors.offset[row]);
        for (std::size_t p = 0; p < terms; ++p) {
          const auto q = static_cast<Eigen::Index>(p);
          sum += phasors.cosine(row, q) * cosines[p] + phasors.sine(row, q) * sines[p];
          scales[o] += std::abs(phasors.cosine(row, q)) + std::abs(phasors.sine(row, q));
        }
        first[o] = static_cast<double>(sum);
      }
      for (std::size_t i = 0; i < z; ++i) {
        travel[i] = phasors.travel_row[i] >= 0 ? first[static_cast<std::size_t>(phasors.travel_row[i])] : 0.0;
        force[i] = first[static_cast<std::size_t>(phasors.first_force_row) + i];
      }
      const std::size_t first_slope = static_cast<std::size_t>(phasors.first_force_row) + z;
      corrector.At({Eigen::Vector2d(first[0], first[1]), travel, force,
                    std::span<const double>(first.data() + first_slope, 2 * z),
                    std::span<const double>(first.data() + first_slope + 2 * z, 2 * z)},
                   second);
      for (const Row& row : rows) {
        const auto o = static_cast<std::size_t>(row.o);
        double correction = 0.0;
        if (o < 2) {
          correction = second.centre[row.o];
        } else if (o >= static_cast<std::size_t>(phasors.first_force_row)) {
          correction = second.contact_force[row.i];
        } else {
          correction = second.travel[row.i];
        }
        const long double reference = static_cast<long double>(first[o]) + correction;
        const double scale = scales[o];
        const double error = std::abs(static_cast<double>(row.at(path, k, row.i) - reference));
        worst = std::max(worst, error / scale);
        ASSERT_LE(error, kRelativeRoundOff * scale) << steps << " steps, row " << row.o << ", angle " << k;
      }
    }
    std::ostringstream worst_text;
    worst_text << std::scientific << worst;
    RecordProperty("worst_relative_error_" + std::to_string(steps), worst_text.str());
  }
}

}  // namespace
}  // namespace ringtol
