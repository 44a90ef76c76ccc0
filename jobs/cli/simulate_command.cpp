#include "jobs/cli/simulate_command.h"

#include <chrono>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "jobs/cli/results_output.h"
#include "jobs/inputs/input_error.h"
#include "jobs/inputs/scene_file.h"
#include "jobs/inputs/sweep_file.h"
#include "solvers/dynamic.h"

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
  std::ofstream trajectory = OpenOptionalOutput(command.trajectory_csv, "--trajectory");
  std::ofstream history_file = OpenOptionalOutput(command.history_csv, "--history");
  const Timed run = SimulateTimed(scene, *solver, command.solver.simulation);
  nlohmann::json json = ResultJson(scene, run.result, command.solver, run.seconds);
  if (!command.json) PrintResult(out, scene, run.result, command.solver, run.seconds);
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
  std::ofstream csv = OpenOptionalOutput(command.csv, "--csv");
  std::vector<nlohmann::json> rows;
  for (const SweepCase& c : sweep.cases) {
    const Timed run = SimulateTimed(c.scene, *solver, command.solver.simulation);
    rows.push_back(ResultJson(c.scene, run.result, command.solver, run.seconds, c.name));
  }
  if (command.json) {
    out << nlohmann::json(rows).dump(2) << "\n";
  } else {
    PrintSweepTable(out, rows);
  }
  if (csv.is_open()) WriteSweepCsv(csv, rows);
  return 0;
}

}  // namespace ringtol::jobs
