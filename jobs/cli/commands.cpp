#include "jobs/cli/commands.h"

#include <chrono>
#include <fstream>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "jobs/campaign/campaign_file.h"
#include "jobs/inputs/catalogue_file.h"
#include "jobs/studies/dynamic_study.h"
#include "jobs/inputs/input_error.h"
#include "jobs/cli/results_output.h"
#include "jobs/inputs/sampling_file.h"
#include "jobs/inputs/scene_file.h"
#include "jobs/inputs/scene_writer.h"
#include "jobs/studies/solver_ladder.h"
#include "jobs/inputs/sweep_file.h"
#include "sampling/spectrum.h"
#include "solvers/dynamic.h"
#include "solvers/simulation.h"
#include "engine/units.h"

namespace ringtol::jobs {
namespace {

// The command line's settings, checked where CLI11 cannot: the dynamic rung's tolerance.
std::unique_ptr<solvers::Solver> CheckedSolver(const solvers::SolverSettings& settings) {
  if (!(settings.relative_tolerance > 0.0 && settings.relative_tolerance < 1.0)) {
    throw InputError("--relative-tolerance " + std::to_string(settings.relative_tolerance) +
                     ": allowed: > 0 and < 1");
  }
  return solvers::MakeSolver(settings);
}

// Opens an output file up front so a bad path fails before any work is done.
std::ofstream OpenOutput(const std::filesystem::path& file, const char* option) {
  std::ofstream out(file);
  if (!out) throw InputError(std::string(option) + " " + file.string() + ": cannot open for writing");
  return out;
}

struct Timed {
  solvers::SimulationResult result;
  double seconds = 0.0;
};

Timed SimulateTimed(const engine::Scene& scene, const solvers::Solver& solver,
                    const solvers::SimulationOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  Timed timed{solvers::Simulate(scene, solver, options), 0.0};
  timed.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return timed;
}

}  // namespace

int RunSimulate(const SimulateCommand& command, std::ostream& out) {
  const engine::Scene scene = ReadScene(command.scene);
  const auto solver = CheckedSolver(command.solver);
  const auto* dynamic = dynamic_cast<const solvers::DynamicSolver*>(solver.get());
  // Every option is checked before any output file is opened (and so emptied).
  if (!command.history_csv.empty()) {
    if (dynamic == nullptr) throw InputError("--history: only the dynamic solver has a time history (--solver dynamic)");
    if (!(command.history_interval_ms > 0.0)) {
      throw InputError("--history-interval-ms " + std::to_string(command.history_interval_ms) + ": allowed: > 0");
    }
  }
  std::ofstream trajectory;
  if (!command.trajectory_csv.empty()) trajectory = OpenOutput(command.trajectory_csv, "--trajectory");
  std::ofstream history_file;
  if (!command.history_csv.empty()) history_file = OpenOutput(command.history_csv, "--history");
  const Timed run = SimulateTimed(scene, *solver, command.solver.simulation);
  nlohmann::json json = ResultJson(scene, run.result, solver->name(), run.seconds);
  if (!command.json) PrintResult(out, scene, run.result, solver->name(), run.seconds);
  if (trajectory.is_open()) WriteTrajectoryCsv(trajectory, scene, run.result);
  if (history_file.is_open()) {
    const solvers::DynamicHistory history =
        dynamic->SolveHistory(scene, command.history_interval_ms * 1e-3, scene.motion.Duration());
    WriteHistoryCsv(history_file, scene, history);
    json["history_status"] = std::string(solvers::StatusName(history.status));
    if (history.status != solvers::Status::kOk) json["history_message"] = history.message;
    if (!command.json) {
      fmt::print(out, "history           {} samples to {}, {}{}\n", history.samples.size(), command.history_csv.string(),
                 solvers::StatusName(history.status), history.message.empty() ? "" : ": " + history.message);
    }
  }
  if (command.json) out << json.dump(2) << "\n";
  return 0;
}

int RunSweep(const SweepCommand& command, std::ostream& out) {
  const Sweep sweep = ReadSweep(command.sweep);
  const auto solver = CheckedSolver(command.solver);
  std::ofstream csv;
  if (!command.csv.empty()) csv = OpenOutput(command.csv, "--csv");
  std::vector<nlohmann::json> rows;
  for (const SweepCase& c : sweep.cases) {
    const Timed run = SimulateTimed(c.scene, *solver, command.solver.simulation);
    rows.push_back(ResultJson(c.scene, run.result, solver->name(), run.seconds, c.name));
  }
  if (command.json) {
    out << nlohmann::json(rows).dump(2) << "\n";
  } else {
    PrintSweepTable(out, rows);
  }
  if (csv.is_open()) WriteSweepCsv(csv, rows);
  return 0;
}

int RunBenchDynamics(const BenchDynamicsCommand& command, std::ostream& out) {
  const engine::Scene scene = ReadScene(command.scene);
  DynamicStudyOptions options;
  if (!command.orders.empty()) options.orders = command.orders;
  if (!command.rates_deg_per_s.empty()) {
    options.rates.clear();
    for (const double rate : command.rates_deg_per_s) options.rates.push_back(rate * units::kRadiansPerDegree);
  }
  const DynamicStudy study = RunDynamicStudy(scene, options, nullptr);
  PrintDynamicStudy(out, study);
  return 0;
}

int RunBenchLadder(const BenchLadderCommand& command, std::ostream& out, std::ostream& progress) {
  const engine::Scene scene = ReadScene(command.scene);
  std::ofstream csv;
  if (!command.csv.empty()) csv = OpenOutput(command.csv, "--csv");
  std::ofstream svg;
  if (!command.svg.empty()) svg = OpenOutput(command.svg, "--svg");
  LadderOptions options;
  options.cases = command.cases;
  options.repeats = command.repeats;
  options.explicit_full_model = command.explicit_full_model;
  const LadderResult result = RunLadder(scene, options, &progress);
  PrintLadder(out, result);
  if (csv.is_open()) WriteLadderCsv(csv, result);
  if (svg.is_open()) WriteLadderSvg(svg, result);
  return 0;
}

int RunSample(const SampleCommand& command, std::ostream& out) {
  const std::string source = command.file.string();
  // A campaign file is a sampling file too: its solver and spec are not needed here.
  SamplingPlan plan = ReadSamplingFile(command.file, kCampaignTables);
  OverridePlan(plan, command.samples, command.seed);
  if (command.index.has_value() != !command.scene.empty())
    throw InputError("--index and --scene go together: the sample to write and the file to write it to");
  if (command.index && (*command.index < 0 || *command.index >= plan.samples))
    throw InputError("--index " + std::to_string(*command.index) + ": allowed: 0.." + std::to_string(plan.samples - 1));
  if (!command.scene.empty()) {
    const std::filesystem::path folder = command.scene.parent_path().empty() ? "." : command.scene.parent_path();
    if (!std::filesystem::is_directory(folder))
      throw InputError(command.scene.string() + ": cannot be written: folder " + folder.string() + " does not exist");
  }
  Sampling sampling = MakeSampling(plan, source);
  std::ofstream csv;
  if (!command.csv.empty()) csv = OpenOutput(command.csv, "--csv");

  fmt::print(out, "sampling file     {}\n", source);
  fmt::print(out, "base scene        {}\n", plan.scene_file.string());
  fmt::print(out, "design            {}, {} samples, seed {}, {} coordinates\n",
             sampling::DesignName(plan.design.kind), plan.samples, plan.seed, sampling.sampler.dimension());
  fmt::print(out, "catalogue         {}\n", plan.catalogue.version);
  for (const sampling::ComponentScale& s : sampling.sampler.scales()) {
    fmt::print(out, "calibrated        {}: {} <= {:.4g} um for {:.4g} % of parts: scale {:.4g} um ({} draws)\n",
               s.component, sampling::FormMeasureName(s.measure), s.tolerance * units::kMicrometresPerMetre,
               100 * s.coverage, s.calibration.scale * units::kMicrometresPerMetre, s.calibration.draws);
  }

  const auto& inputs = sampling.sampler.inputs();
  if (csv.is_open()) {
    csv << "sample,redraws";
    for (const auto& input : inputs) csv << ',' << input.name;
    csv << '\n';
  }
  std::int64_t redraws = 0;
  for (std::int64_t i = 0; i < plan.samples; ++i) {
    const sampling::SampledAssembly a = sampling.sampler.Sample(sampling.design, i);
    redraws += a.redraws;
    if (csv.is_open()) {
      csv << i << ',' << a.redraws;
      for (const double v : a.values) csv << ',' << fmt::format("{}", v);
      csv << '\n';
    }
    if (command.index && *command.index == i) WriteSceneFile(a.scene, command.scene);
  }
  fmt::print(out, "drawn             {} assemblies, {} parts rejected by inspection and drawn again\n", plan.samples,
             redraws);
  if (csv.is_open()) fmt::print(out, "inputs            {} ({} columns)\n", command.csv.string(), inputs.size() + 2);
  if (command.index) fmt::print(out, "sample {}          {}\n", *command.index, command.scene.string());
  return 0;
}

int RunClasses(bool toml, std::ostream& out) {
  if (toml) {
    out << ShippedCatalogueText();
    return 0;
  }
  const sampling::ToleranceCatalogue c = ShippedCatalogue();
  auto names = [](const auto& k) {
    std::string text = k.name;
    for (const auto& a : k.aliases) text += ", " + a;
    return text;
  };
  fmt::print(out, "catalogue version {}\n", c.version);
  fmt::print(out, "\nrollers (ISO 492 outer ring), by outside diameter:\n");
  for (const auto& k : c.roller_classes) fmt::print(out, "  {:<20} {} ({} rows)\n", names(k), k.description, k.rows.size());
  fmt::print(out, "\nring bore circularity:\n");
  for (const auto& k : c.ring_classes) fmt::print(out, "  {:<20} {} ({} rows)\n", names(k), k.description, k.rows.size());
  fmt::print(out, "\nroller positions (zone diameter), by centre-circle diameter:\n");
  for (const auto& k : c.position_classes)
    fmt::print(out, "  {:<20} {} ({} rows)\n", names(k), k.description, k.rows.size());
  fmt::print(out, "\nsprings:\n");
  for (const auto& k : c.spring_classes) fmt::print(out, "  {:<20} {}\n", names(k), k.description);
  fmt::print(out, "\n`ringtol classes --toml` prints every row with its source.\n");
  return 0;
}

}  // namespace ringtol::jobs
