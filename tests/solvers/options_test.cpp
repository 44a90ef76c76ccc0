#include <gtest/gtest.h>

#include "solvers/dynamic.h"
#include "solvers/simulation.h"
#include "tests/support/invalid_options.h"

namespace ringtol::solvers {
namespace {

using testing::ExpectEachRefusedByName;

TEST(SimulationOptions, DefaultsAreValid) { EXPECT_TRUE(SimulationOptions{}.IsValid()); }

TEST(SimulationOptions, EachFieldOutsideItsRangeIsRefusedNamingTheField) {
  ExpectEachRefusedByName<SimulationOptions>({
      {"steps", [](SimulationOptions& o) { o.steps = -1; }},
      {"steps", [](SimulationOptions& o) { o.steps = kMaxSteps + 1; }},
      {"refine_stride", [](SimulationOptions& o) { o.refine_stride = 1; }},
      {"samples_per_undulation", [](SimulationOptions& o) { o.samples_per_undulation = 2.0; }},
      {"min_steps", [](SimulationOptions& o) { o.min_steps = 0; }},
      {"max_steps", [](SimulationOptions& o) { o.max_steps = kMaxSteps + 1; }},
      {"max_steps", [](SimulationOptions& o) { o.max_steps = o.min_steps - 1; }},  // below the floor
      {"path_tolerance", [](SimulationOptions& o) { o.path_tolerance = -1e-9; }},
  });
}

TEST(DynamicOptions, DefaultsAreValid) { EXPECT_TRUE(DynamicOptions{}.IsValid()); }

TEST(DynamicOptions, EachFieldOutsideItsRangeIsRefusedNamingTheField) {
  ExpectEachRefusedByName<DynamicOptions>({
      {"explicit_step", [](DynamicOptions& o) { o.explicit_step = 0.0; }},
      {"steady_revolution", [](DynamicOptions& o) { o.steady_revolution = -1; }},
      {"relative_tolerance", [](DynamicOptions& o) { o.relative_tolerance = 0.0; }},
      {"relative_tolerance", [](DynamicOptions& o) { o.relative_tolerance = 1.0; }},
      {"max_steps", [](DynamicOptions& o) { o.max_steps = 0; }},
  });
}

// The settings a file or the command line gives: the simulation's fields under its name,
// and the dynamic rung's tolerance in DynamicOptions' range.
TEST(SolverSettings, NamesTheSimulationsFieldsUnderItsNameAndChecksTheDynamicTolerance) {
  ExpectEachRefusedByName<SolverSettings>({
      {"simulation.steps", [](SolverSettings& s) { s.simulation.steps = -5; }},
      {"simulation.path_tolerance", [](SolverSettings& s) { s.simulation.path_tolerance = -1.0; }},
      {"relative_tolerance", [](SolverSettings& s) { s.relative_tolerance = 1.5; }},
  });
}

}  // namespace
}  // namespace ringtol::solvers
