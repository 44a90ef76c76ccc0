// The campaign's step rule against the continuous revolution, on assemblies drawn from the
// catalogue's loosest classes (the default campaign: waterjet-cut ring, Normal rollers,
// IT7 positions). At the steps the rule picks for a budget, and at every finer grid, each
// metric must lie within its stated sampling bound (solvers::SamplingErrorBounds: D_trajectory
// and runout within the budget, the swing within twice it) of the same sample resolved far
// beyond every undulation; Dist_init, which has no such bound, within the budget. A metric that jumped when an undulation was resolved or not (as the
// old "peak to nearest valley" runout did by up to 78 um) fails here.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "jobs/campaign/campaign.h"
#include "solvers/simulation.h"

namespace ringtol::jobs {
namespace {

constexpr int kSamples = 8;  // two points of each of the four Sobol' replicates
// The quasistatic rung converges each angle to 1 pm: two paths differ by at most 2 pm in
// every metric beyond sampling (4 pm for the swing, whose rise and counter-move both move).
constexpr double kSolverTolerance = 4e-12;  // [m]

TEST(MetricConvergence, EveryMetricStaysWithinItsSamplingBoundFromTheBudgetToFullResolution) {
  const Campaign campaign(std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/campaigns/default.toml",
                          kSamples, std::nullopt);
  const solvers::SolverSettings exact{solvers::Rung::kQuasistatic, {}, 1e-6};
  const std::unique_ptr<solvers::Solver> solver = solvers::MakeSolver(exact);
  const double budget = campaign.simulation().path_tolerance;
  ASSERT_GT(budget, 0.0);
  Sampling sampling = MakeSampling(campaign.plan().sampling, "default campaign");
  for (std::int64_t index = 0; index < kSamples; ++index) {
    const engine::Scene scene = sampling.sampler.Sample(sampling.design, index).scene;
    const int chosen = solvers::ChooseSteps(scene, campaign.simulation());
    // Twice the undulation rule: every term sampled 64 times per period of twice its rate.
    solvers::SimulationOptions full;
    full.samples_per_undulation = 64.0;
    const int reference_steps = solvers::ChooseSteps(scene, full);
    ASSERT_GT(reference_steps, 2 * chosen) << "sample " << index;
    solvers::SimulationOptions at_reference;
    at_reference.steps = reference_steps;
    const solvers::SimulationResult reference = solvers::Simulate(scene, *solver, at_reference);
    ASSERT_EQ(reference.status, solvers::Status::kOk) << reference.message;
    const solvers::SamplingErrorBounds reference_bounds = solvers::SamplingErrorBoundsAt(scene, reference_steps);

    for (const double refinement : {1.0, 1.25, 1.5, 2.0}) {
      solvers::SimulationOptions options;
      options.steps = static_cast<int>(std::lround(refinement * chosen));
      const solvers::SimulationResult result = solvers::Simulate(scene, *solver, options);
      ASSERT_EQ(result.status, solvers::Status::kOk) << result.message;
      const solvers::SamplingErrorBounds bounds = solvers::SamplingErrorBoundsAt(scene, options.steps);
      if (refinement == 1.0) {
        EXPECT_LE(std::max(bounds.d_trajectory, bounds.runout), budget) << "sample " << index;
        EXPECT_LE(bounds.swing, 2.0 * budget) << "sample " << index;
      }
      const std::string where = "sample " + std::to_string(index) + ", " + std::to_string(options.steps) + " steps";
      // The reference itself sits within its own (tiny) bound of the continuous answer.
      EXPECT_LE(std::abs(result.d_trajectory - reference.d_trajectory),
                bounds.d_trajectory + reference_bounds.d_trajectory + kSolverTolerance)
          << where;
      EXPECT_LE(std::abs(result.runout - reference.runout), bounds.runout + reference_bounds.runout + kSolverTolerance)
          << where;
      EXPECT_LE(std::abs(result.swing - reference.swing), bounds.swing + reference_bounds.swing + kSolverTolerance)
          << where;
      EXPECT_LE(std::abs(result.dist_init - reference.dist_init), budget) << where;
      // Static offset is a single equilibrium: no sampling at all.
      EXPECT_NEAR(result.static_offset, reference.static_offset, kSolverTolerance) << where;
    }
  }
}

}  // namespace
}  // namespace ringtol::jobs
