// One revolution at 720 steps of the article's assembly with 8 ring harmonics and
// 3 rollers, per rung and contact law, beside the cost of the enclosing circle.
// Run: build/tests/ringtol_benchmarks --benchmark_repetitions=10 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <vector>

#include "engine/enclosing_circle.h"
#include "solvers/linear.h"
#include "solvers/quasistatic.h"
#include "solvers/simulation.h"
#include "tests/support/paper_scene.h"

namespace {

using namespace ringtol;
constexpr int kSteps = 720;

engine::Scene EightHarmonics(engine::ContactLaw::Model law) {
  engine::Scene scene = testing::PaperScene(law);
  std::vector<engine::Harmonic> ring;
  for (int n = 2; n <= 9; ++n) ring.push_back({n, 0.14e-3 / (n - 1), 0.3 * n});
  testing::SetRing(scene, ring);
  return scene;
}

void Revolution(benchmark::State& state, const char* solver_name, engine::ContactLaw::Model law) {
  const engine::Scene scene = EightHarmonics(law);
  const auto solver = solvers::MakeSolver(solver_name);
  for (auto _ : state) {
    solvers::Trajectory path = solver->SolveRevolution(scene, kSteps);
    benchmark::DoNotOptimize(path.centre.data());
  }
}
BENCHMARK_CAPTURE(Revolution, linear_rigid, "linear", engine::ContactLaw::Model::kRigid)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(Revolution, linear_penalty, "linear", engine::ContactLaw::Model::kPenalty)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(Revolution, quasistatic_rigid, "quasistatic", engine::ContactLaw::Model::kRigid)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(Revolution, quasistatic_penalty, "quasistatic", engine::ContactLaw::Model::kPenalty)->Unit(benchmark::kMicrosecond);

// The static equilibrium alone: for the linear rung this is its linearisation of the
// error-free assembly plus one angle, the part of a revolution that is not the path.
void StaticEquilibrium(benchmark::State& state, const char* solver_name) {
  const engine::Scene scene = EightHarmonics(engine::ContactLaw::Model::kPenalty);
  const auto solver = solvers::MakeSolver(solver_name);
  for (auto _ : state) {
    solvers::Equilibrium equilibrium = solver->SolveStatic(scene);
    benchmark::DoNotOptimize(equilibrium.centre.data());
  }
}
BENCHMARK_CAPTURE(StaticEquilibrium, linear, "linear")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(StaticEquilibrium, quasistatic, "quasistatic")->Unit(benchmark::kMicrosecond);

void FullSimulation(benchmark::State& state, const char* solver_name) {
  const engine::Scene scene = EightHarmonics(engine::ContactLaw::Model::kPenalty);
  const auto solver = solvers::MakeSolver(solver_name);
  solvers::SimulationOptions options;
  options.steps = kSteps;
  for (auto _ : state) {
    solvers::SimulationResult result = solvers::Simulate(scene, *solver, options);
    benchmark::DoNotOptimize(result.d_trajectory);
  }
}
BENCHMARK_CAPTURE(FullSimulation, linear, "linear")->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(FullSimulation, quasistatic, "quasistatic")->Unit(benchmark::kMicrosecond);

void EnclosingCircle(benchmark::State& state) {
  const engine::Scene scene = EightHarmonics(engine::ContactLaw::Model::kPenalty);
  const solvers::Trajectory path = solvers::LinearSolver().SolveRevolution(scene, kSteps);
  for (auto _ : state) {
    engine::Circle circle = engine::MinimumEnclosingCircle(path.centre);
    benchmark::DoNotOptimize(circle.radius);
  }
}
BENCHMARK(EnclosingCircle)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
