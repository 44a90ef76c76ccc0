// One revolution at 720 steps of the article's assembly with 8 ring harmonics and
// 3 rollers, per rung and contact law, beside the cost of the enclosing circle; and the
// dynamic rung's settle + revolution per setting; and the default campaign's sampler.
// Run: build/tests/ringtol_benchmarks --benchmark_repetitions=10 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "engine/enclosing_circle.h"
#include "engine/sensor.h"
#include "sampling/assembly_sampler.h"
#include "sampling/design.h"
#include "solvers/dynamic.h"
#include "solvers/life.h"
#include "solvers/linear.h"
#include "solvers/quasistatic.h"
#include "solvers/simulation.h"
#include "solvers/spectral.h"
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

std::unique_ptr<solvers::Solver> MakeSolver(solvers::Rung rung) {
  solvers::SolverSettings settings;
  settings.rung = rung;
  return solvers::MakeSolver(settings);
}

void Revolution(benchmark::State& state, solvers::Rung rung, engine::ContactLaw::Model law) {
  const engine::Scene scene = EightHarmonics(law);
  const auto solver = MakeSolver(rung);
  for (auto _ : state) {
    solvers::Trajectory path = solver->SolveRevolution(scene, kSteps);
    benchmark::DoNotOptimize(path.centre.data());
  }
}
BENCHMARK_CAPTURE(Revolution, linear_rigid, solvers::Rung::kLinear, engine::ContactLaw::Model::kRigid)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(Revolution, linear_penalty, solvers::Rung::kLinear, engine::ContactLaw::Model::kPenalty)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(Revolution, quasistatic_rigid, solvers::Rung::kQuasistatic, engine::ContactLaw::Model::kRigid)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(Revolution, quasistatic_penalty, solvers::Rung::kQuasistatic, engine::ContactLaw::Model::kPenalty)->Unit(benchmark::kMicrosecond);

// The static equilibrium alone: for the linear rung this is its linearisation of the
// error-free assembly plus one angle, the part of a revolution that is not the path.
void StaticEquilibrium(benchmark::State& state, solvers::Rung rung) {
  const engine::Scene scene = EightHarmonics(engine::ContactLaw::Model::kPenalty);
  const auto solver = MakeSolver(rung);
  for (auto _ : state) {
    solvers::Equilibrium equilibrium = solver->SolveStatic(scene);
    benchmark::DoNotOptimize(equilibrium.centre.data());
  }
}
BENCHMARK_CAPTURE(StaticEquilibrium, linear, solvers::Rung::kLinear)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(StaticEquilibrium, quasistatic, solvers::Rung::kQuasistatic)->Unit(benchmark::kMicrosecond);

void FullSimulation(benchmark::State& state, solvers::Rung rung) {
  const engine::Scene scene = EightHarmonics(engine::ContactLaw::Model::kPenalty);
  const auto solver = MakeSolver(rung);
  solvers::SimulationOptions options;
  options.steps = kSteps;
  for (auto _ : state) {
    solvers::SimulationResult result = solvers::Simulate(scene, *solver, options);
    benchmark::DoNotOptimize(result.d_trajectory);
  }
}
BENCHMARK_CAPTURE(FullSimulation, linear, solvers::Rung::kLinear)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(FullSimulation, quasistatic, solvers::Rung::kQuasistatic)->Unit(benchmark::kMicrosecond);

// One sample the way a campaign simulates it: a scene shaped like a draw of the default
// campaign (tests/support/paper_scene.h), the whole Simulate with the angles chosen for a
// 1 um sampling budget, at the solver's default 1 pm and at a campaign's 10 nm.
void CampaignSample(benchmark::State& state, solvers::Rung rung, double position_tolerance) {
  const engine::Scene scene = testing::CampaignLikeScene();
  solvers::QuasistaticOptions quasistatic;
  quasistatic.position_tolerance = position_tolerance;
  const std::unique_ptr<solvers::Solver> solver = rung == solvers::Rung::kQuasistatic
                                                      ? std::make_unique<solvers::QuasistaticSolver>(quasistatic)
                                                      : MakeSolver(rung);
  solvers::SimulationOptions options;
  options.path_tolerance = 1e-6;
  int steps = 0;
  for (auto _ : state) {
    solvers::SimulationResult result = solvers::Simulate(scene, *solver, options);
    benchmark::DoNotOptimize(result.d_trajectory);
    steps = result.steps;
  }
  state.counters["steps"] = steps;
}
BENCHMARK_CAPTURE(CampaignSample, linear, solvers::Rung::kLinear, 0.0)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(CampaignSample, quasistatic_1pm, solvers::Rung::kQuasistatic, 1e-12)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(CampaignSample, quasistatic_10nm, solvers::Rung::kQuasistatic, 1e-8)->Unit(benchmark::kMicrosecond);

// What the life over every revolution adds to a campaign-like sample on the linear rung
// (solvers::EveryRevolution with the phasors it reads), against CampaignSample/linear: the
// same scene, its rollers of three sizes so that their phases drift apart (`drawn_sizes`),
// or of one size, each roller's lobes then a curve in its own phase (`equal_sizes`); its
// error motion through the default 50 UPR filter, or unfiltered (`unfiltered`).
void LifeEveryRevolution(benchmark::State& state, bool drawn, double cutoff_upr) {
  engine::Scene scene = testing::CampaignLikeScene();
  scene.error_motion_filter.cutoff_upr = cutoff_upr;
  const double sizes[] = {-1.3e-6, 0.4e-6, -0.2e-6};
  for (std::size_t i = 0; i < scene.rollers.size() && drawn; ++i) {
    engine::Roller& roller = scene.rollers[i];
    roller.outline = engine::PolarProfile(roller.outline.radius(), sizes[i], roller.outline.harmonics());
  }
  const solvers::LinearSolver linear;
  solvers::SimulationOptions options;
  options.path_tolerance = 1e-6;
  const solvers::SimulationResult one = solvers::Simulate(scene, linear, options);
  for (auto _ : state) {
    const solvers::PhasorSum sum = linear.Phasors(scene);
    int cycle = 0;
    const solvers::LifeValues every = solvers::EveryRevolution(scene, one, sum, cycle);
    benchmark::DoNotOptimize(every.d_trajectory);
  }
  state.counters["steps"] = one.steps;
}
BENCHMARK_CAPTURE(LifeEveryRevolution, drawn_sizes, true, 50.0)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(LifeEveryRevolution, equal_sizes, false, 50.0)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(LifeEveryRevolution, drawn_sizes_unfiltered, true, 0.0)->Unit(benchmark::kMicrosecond);

// The sensor's swing (engine::Swing) over a campaign-like sample's signal at the default
// 0.1 um resolution: the one-revolution signal of the linear rung, roller ripple and all.
void SensorSwing(benchmark::State& state) {
  const engine::Scene scene = testing::CampaignLikeScene();
  solvers::SimulationOptions options;
  options.path_tolerance = 1e-6;
  const solvers::SimulationResult one = solvers::Simulate(scene, solvers::LinearSolver(), options);
  for (auto _ : state) {
    const double swing = engine::Swing(one.sensor, scene.sensor_swing.resolution);
    benchmark::DoNotOptimize(swing);
  }
  state.counters["steps"] = one.steps;
}
BENCHMARK(SensorSwing)->Unit(benchmark::kMicrosecond);

void EnclosingCircle(benchmark::State& state) {
  const engine::Scene scene = EightHarmonics(engine::ContactLaw::Model::kPenalty);
  const solvers::Trajectory path = solvers::LinearSolver().SolveRevolution(scene, kSteps);
  for (auto _ : state) {
    engine::Circle circle = engine::MinimumEnclosingCircle(path.centre);
    benchmark::DoNotOptimize(circle.radius);
  }
}
BENCHMARK(EnclosingCircle)->Unit(benchmark::kMicrosecond);

// The default campaign's sampler (examples/campaigns/default.toml: waterjet ring 0.20 mm as
// made, orders 2..50; Normal rollers at D 6-18 mm inspected, Kea 15 um, VDsp 10 um, mean
// diameter 0/-8 um; IT7 positions, zone 70 um; springs +-10 %), Realise per sample and the
// construction with its two calibrations, judging forms by bounds (the default) or by the
// exact measure on every part and every calibration draw (the reference path).
sampling::AssemblySampler DefaultCampaignSampler(bool exact) {
  sampling::AssemblyTolerances t;
  t.ring = sampling::RingFormTolerance{"waterjet", 200e-6, {}, {}};
  const sampling::Capability inspected{sampling::ToleranceMode::kInspected, 1.0};
  const engine::Scene scene = testing::PaperScene();
  for (std::size_t i = 0; i < scene.rollers.size(); ++i) {
    t.roller_shapes.push_back(sampling::RollerShapeTolerance{"Normal", 15e-6, 10e-6, -8e-6, 0.0, {2, 8, 1.0, {}},
                                                             inspected});
    t.roller_positions.push_back(sampling::PositionTolerance{"IT7", 70e-6, {}});
    t.springs.push_back(scene.rollers[i].mount == engine::RollerMount::kSpring
                            ? std::optional(sampling::SpringTolerance{"pm10", 0.1, 0.1, {}})
                            : std::nullopt);
  }
  sampling::AssemblySamplerOptions options;
  options.exact_form_inspection = exact;
  options.calibration.exact_every_draw = exact;
  // The Monte Carlo calibration, which a run of the default spectra now skips (their rows
  // are tabulated; ringtol_sample_benchmark's CampaignStartUp times that path).
  options.calibration.tabulated = false;
  return sampling::AssemblySampler(scene, t, options);
}

void SamplerRealise(benchmark::State& state, bool exact) {
  const sampling::AssemblySampler sampler = DefaultCampaignSampler(exact);
  sampling::DesignOptions options;
  options.kind = sampling::DesignKind::kSobol;
  sampling::Design design(sampler.dimension(), options);
  std::int64_t index = 0, redraws = 0;
  for (auto _ : state) {
    const sampling::SampledAssembly a = sampler.Sample(design, index++ % 2048);
    redraws += a.redraws;
    benchmark::DoNotOptimize(a.scene.ring.inner.radius());
  }
  state.counters["redraws_per_sample"] = static_cast<double>(redraws) / static_cast<double>(index);
}
BENCHMARK_CAPTURE(SamplerRealise, bounded, false)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(SamplerRealise, exact, true)->Unit(benchmark::kMicrosecond);

// Draws of the default campaign read by the spectral rung (solvers/spectral.h), with and
// without the every-revolution life values it can add: what a campaign with spectral
// angles would pay for them, per sample over 64 draws in turn.
void SpectralLife(benchmark::State& state, bool life) {
  const sampling::AssemblySampler sampler = DefaultCampaignSampler(false);
  sampling::DesignOptions design_options;
  design_options.kind = sampling::DesignKind::kSobol;
  sampling::Design design(sampler.dimension(), design_options);
  std::vector<engine::Scene> scenes;
  for (std::int64_t index = 0; index < 64; ++index) scenes.push_back(sampler.Sample(design, index).scene);
  const solvers::LinearSolver linear;
  solvers::SimulationOptions options;
  options.path_tolerance = 1e-6;
  std::size_t next = 0;
  double evaluated = 0.0;
  for (auto _ : state) {
    const engine::Scene& scene = scenes[next++ % scenes.size()];
    const std::optional<solvers::SpectralResult> result =
        solvers::SimulateSpectral(scene, linear, solvers::ChooseSteps(scene, options), options.refine_stride,
                                  solvers::kAutoShareOfPathTolerance * options.path_tolerance, life);
    if (result) evaluated += result->evaluated;
    benchmark::DoNotOptimize(result);
  }
  state.counters["evaluated"] = evaluated / static_cast<double>(next);
}
BENCHMARK_CAPTURE(SpectralLife, one_revolution, false)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(SpectralLife, every_revolution, true)->Unit(benchmark::kMicrosecond);

void SamplerConstruction(benchmark::State& state, bool exact) {
  for (auto _ : state) benchmark::DoNotOptimize(DefaultCampaignSampler(exact).dimension());
}
BENCHMARK_CAPTURE(SamplerConstruction, bounded, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(SamplerConstruction, exact, true)->Unit(benchmark::kMillisecond);

// The dynamic rung at its speed target: the article's scene with an order-2
// ring error (0.14 mm at 45 deg), the article's law (settle 0.5 s, then 270 deg/s), and
// the time to settle and sample one revolution at 360 angles. Each setting's error in
// D_trajectory against a 1e-11 reference is in docs/usage.md, "Which rung when" (`ringtol bench ladder`).
struct DynamicSetting {
  bool friction = true;
  bool reduced = false;  // massless spring roller and rolling without slip
  solvers::DynamicMethod method = solvers::DynamicMethod::kImplicitBdf;
  double tolerance = 1e-6;
  double step = 0.0;  // [s] explicit only
};

void DynamicRevolution(benchmark::State& state, DynamicSetting setting) {
  engine::Scene scene = testing::PaperScene(engine::ContactLaw::Model::kPenalty);
  testing::SetRing(scene, {{2, 0.14e-3, 45.0 * testing::kDeg}});
  scene.dynamics.friction = setting.friction && !setting.reduced;
  scene.dynamics.rolling_without_slip = setting.reduced;
  scene.dynamics.massless_spring_rollers = setting.reduced;
  solvers::DynamicOptions options;
  options.start = solvers::DynamicStart::kArticleSettle;  // the settle docs/performance.md's timings include
  options.steady_revolution = 0;
  options.method = setting.method;
  options.relative_tolerance = setting.tolerance;
  options.explicit_step = setting.step;
  const solvers::DynamicSolver solver(options);
  for (auto _ : state) {
    solvers::Trajectory path = solver.SolveRevolution(scene, 360);
    if (path.status != solvers::Status::kOk) state.SkipWithError(path.message.c_str());
    benchmark::DoNotOptimize(path.centre.data());
  }
}
BENCHMARK_CAPTURE(DynamicRevolution, friction_default, DynamicSetting{})->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(DynamicRevolution, friction_rtol_1e-5, DynamicSetting{.tolerance = 1e-5})
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(DynamicRevolution, reduced_rtol_1e-5, DynamicSetting{.reduced = true, .tolerance = 1e-5})
    ->Unit(benchmark::kMillisecond);
// The explicit baseline at the largest step its stability allows that keeps D_trajectory
// within 1 um of the reference: the full model needs ~60 ns (about a minute a run, so it
// is measured by `ringtol bench ladder`), the reduced model 20 us.
BENCHMARK_CAPTURE(DynamicRevolution, reduced_explicit_20us,
                  DynamicSetting{.reduced = true, .method = solvers::DynamicMethod::kExplicitRungeKutta, .step = 2e-5})
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
