// The auto rung's promise, checked sample by sample on draws of the catalogue's loosest and
// tightest classes: its status is the exact time-free model's (the quasistatic rung at
// 1 pm), and its D_trajectory and runout are within the error estimate it records of that
// model's on the same angles. The same for the linear rung alone, wherever its path is
// valid, whatever auto makes of it: its second-order path's D_trajectory, runout and swing
// are within its estimate of the exact model's. The estimate bounds the model's error at
// any set of angles, so the samples run at kSteps angles, far fewer than a campaign's, to
// keep the test quick; the sampling error the campaign's steps add is bounded apart
// (solvers::SamplingErrorBoundsAt, tests/validation/steps_convergence_test.cpp).
//
// A longer validation is this test with more draws (a power of two: a Sobol' net), and
// with RINGTOL_AUTO_RUNG_STEPS=0 the step rule's own angles, from the build directory:
//   RINGTOL_AUTO_RUNG_SAMPLES=16384 ./ringtol_jobs_campaign_tests --gtest_filter='AutoRung.*' --gtest_output=xml:auto_rung.xml
// which keeps the ratios it found (test properties) in the XML file.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "analysis/order_statistics.h"
#include "jobs/campaign/campaign.h"
#include "solvers/auto.h"
#include "solvers/linear.h"
#include "solvers/quasistatic.h"
#include "solvers/simulation.h"
#include "tests/support/longer_run.h"

namespace ringtol::jobs {
namespace {

constexpr int kSteps = 256;
// Under the sanitizers every solve is ~20 times slower: a tenth of the draws still meets
// both classes' extremes.
constexpr std::int64_t kSamplesPerClass = testing::kSanitized ? 256 : 2048;

// A longer run's count and steps (the header's command), else the constants above.
std::int64_t SamplesPerClass() { return testing::LongerRun("RINGTOL_AUTO_RUNG_SAMPLES", kSamplesPerClass); }
int Steps() { return static_cast<int>(testing::LongerRun("RINGTOL_AUTO_RUNG_STEPS", kSteps)); }
// The campaigns' default budget: half of a 1 um path tolerance.
constexpr double kBudget = solvers::kAutoShareOfPathTolerance * 1e-6;  // [m]
// The reference converges each angle to 1 pm; a diameter and a max - min carry twice that,
// and the auto rung's quasistatic samples (same tolerance) as much again.
constexpr double kReferenceError = 4e-12;  // [m]

const std::string kSceneLine =
    "scene = \"" + (std::filesystem::path(RINGTOL_SOURCE_DIR) / "examples/paper/scene.toml").string() + "\"\n";

struct Classes {
  const char* name;
  const char* tables;
};

// ISO 2768-L (0.5 mm at 604 mm) and IT5/2 (16 um) rings; ISO 492 Normal and 2 rollers,
// inspected; IT9 and IT6 position zones; +-20 % and +-5 % springs.
constexpr std::array<Classes, 2> kExtremes = {{
    {"loosest", R"([tolerances.ring]
class = "ISO2768-L"
[tolerances.rollers]
class = "Normal"
mode = "inspected"
[tolerances.roller_positions]
class = "IT9"
[tolerances.springs]
class = "pm20"
)"},
    {"tightest", R"([tolerances.ring]
class = "IT5/2"
[tolerances.rollers]
class = "2"
mode = "inspected"
[tolerances.roller_positions]
class = "IT6"
[tolerances.springs]
class = "pm5"
)"},
}};

struct Tally {
  std::array<std::int64_t, 3> settled{};  // by solvers::Rung number
  double largest_ratio = 0.0;             // true error over estimate, linear samples
  // The linear rung alone, every valid path: true error over estimate of D_trajectory,
  // runout and swing.
  std::array<std::vector<double>, 3> linear_ratios;
};

Tally CheckClasses(const Classes& classes) {
  const std::int64_t samples = SamplesPerClass();
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / (std::string("ringtol_AutoRung_") + classes.name + ".toml");
  std::ofstream(file) << kSceneLine << "seed = 3\n[design]\nkind = \"sobol\"\nsamples = " << samples << "\n"
                      << classes.tables;
  const Campaign campaign(file, std::nullopt, std::nullopt);
  std::filesystem::remove(file);

  solvers::AutoOptions options;
  options.budget = kBudget;
  const solvers::AutoSolver automatic(options);
  const solvers::QuasistaticSolver reference;
  solvers::LinearOptions unlimited;  // judged by its estimate, as auto judges it
  unlimited.max_relative_error = 1.0;
  unlimited.min_error_limit = std::numeric_limits<double>::infinity();
  const solvers::LinearSolver linear(unlimited);
  solvers::SimulationOptions angles;
  angles.steps = Steps();
  sampling::Design design(campaign.sampling().design.dimension(), campaign.sampling().design.options());
  std::vector<double> u(static_cast<std::size_t>(design.dimension()));
  Tally tally;
  for (std::int64_t index = 0; index < samples; ++index) {
    design.Point(index, u);
    engine::Scene scene;
    try {
      scene = campaign.sampling().sampler.Realise(index, u).scene;
    } catch (const std::exception&) {
      continue;  // the sampler's own failure (redraws used up): no scene to judge
    }
    const solvers::SimulationResult fast = solvers::Simulate(scene, automatic, angles);
    const solvers::SimulationResult exact = solvers::Simulate(scene, reference, angles);
    const std::string where = std::string(classes.name) + " sample " + std::to_string(index);
    const solvers::SimulationResult first = solvers::Simulate(scene, linear, angles);
    if (first.status == solvers::Status::kOk && exact.status == solvers::Status::kOk) {
      const double estimate = first.trajectory.error_estimate;
      const std::array<double, 3> errors = {std::abs(first.d_trajectory - exact.d_trajectory),
                                            std::abs(first.runout - exact.runout), std::abs(first.swing - exact.swing)};
      const std::array<const char*, 3> metric = {"D_trajectory", "runout", "swing"};
      for (std::size_t m = 0; m < errors.size(); ++m) {
        EXPECT_LE(errors[m], estimate + kReferenceError) << where << ", linear rung, " << metric[m];
        if (estimate > 0.0) tally.linear_ratios[m].push_back(errors[m] / estimate);
      }
    }
    EXPECT_EQ(solvers::StatusName(fast.status), solvers::StatusName(exact.status)) << where << ": " << fast.message;
    if (!fast.trajectory.rung) {
      EXPECT_NE(fast.status, solvers::Status::kOk) << where;  // the scene's geometry refused it
      continue;
    }
    const solvers::Rung rung = *fast.trajectory.rung;
    ++tally.settled[static_cast<std::size_t>(rung)];
    if (fast.status != solvers::Status::kOk || exact.status != solvers::Status::kOk) continue;
    const double estimate = fast.trajectory.error_estimate;
    const double d_error = std::abs(fast.d_trajectory - exact.d_trajectory);
    const double runout_error = std::abs(fast.runout - exact.runout);
    EXPECT_LE(d_error, estimate + kReferenceError) << where << " on the " << NameOf(solvers::kRungNames, rung) << " rung";
    EXPECT_LE(runout_error, estimate + kReferenceError) << where << " on the " << NameOf(solvers::kRungNames, rung) << " rung";
    if (rung == solvers::Rung::kLinear) {
      EXPECT_LE(estimate, kBudget) << where;
      if (estimate > 0.0) tally.largest_ratio = std::max(tally.largest_ratio, std::max(d_error, runout_error) / estimate);
    }
  }
  return tally;
}

// At the article's 270 deg/s the ring's inertial force stays below the contact forces for
// every class, so no sample needs the dynamic rung; and both rungs of the time-free model
// take part, so both branches are checked: the loosest class's rings (0.5 mm) put every
// linear estimate above the budget, the tightest settle on the linear rung.
TEST(AutoRung, StatusesAreTheExactModelsAndErrorsStayWithinTheRecordedEstimate) {
  for (const Classes& classes : kExtremes) {
    const Tally tally = CheckClasses(classes);
    const auto linear = tally.settled[static_cast<std::size_t>(solvers::Rung::kLinear)];
    const auto quasistatic = tally.settled[static_cast<std::size_t>(solvers::Rung::kQuasistatic)];
    const auto dynamic = tally.settled[static_cast<std::size_t>(solvers::Rung::kDynamic)];
    EXPECT_EQ(dynamic, 0) << classes.name;
    EXPECT_GT(std::string_view(classes.name) == "tightest" ? linear : quasistatic, 0) << classes.name;
    RecordProperty(std::string(classes.name) + "_linear", std::to_string(linear));
    RecordProperty(std::string(classes.name) + "_quasistatic", std::to_string(quasistatic));
    RecordProperty(std::string(classes.name) + "_largest_error_over_estimate", std::to_string(tally.largest_ratio));
    const std::array<const char*, 3> metric = {"d_trajectory", "runout", "swing"};
    for (std::size_t m = 0; m < metric.size(); ++m) {
      const std::vector<double>& ratios = tally.linear_ratios[m];
      const double largest = ratios.empty() ? 0.0 : *std::max_element(ratios.begin(), ratios.end());
      const std::string key = std::string(classes.name) + "_linear_" + metric[m];
      RecordProperty(key + "_largest_error_over_estimate", std::to_string(largest));
      RecordProperty(key + "_median_error_over_estimate", std::to_string(analysis::Median(ratios)));
      RecordProperty(key + "_samples", std::to_string(ratios.size()));
    }
  }
}

}  // namespace
}  // namespace ringtol::jobs
