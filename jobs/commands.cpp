#include "jobs/commands.h"

#include <chrono>
#include <fstream>
#include <vector>

#include "jobs/input_error.h"
#include "jobs/results_output.h"
#include "jobs/scene_file.h"
#include "jobs/sweep_file.h"
#include "solvers/simulation.h"

namespace ringtol::jobs {
namespace {

std::unique_ptr<solvers::Solver> SolverByName(const std::string& name) {
  try {
    return solvers::MakeSolver(name);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("--solver: ") + e.what());
  }
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

Timed SimulateTimed(const engine::Scene& scene, const solvers::Solver& solver, int steps) {
  solvers::SimulationOptions options;
  options.steps = steps;
  const auto start = std::chrono::steady_clock::now();
  Timed timed{solvers::Simulate(scene, solver, options), 0.0};
  timed.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return timed;
}

}  // namespace

int RunSimulate(const SimulateCommand& command, std::ostream& out) {
  const engine::Scene scene = ReadScene(command.scene);
  const auto solver = SolverByName(command.solver);
  std::ofstream trajectory;
  if (!command.trajectory_csv.empty()) trajectory = OpenOutput(command.trajectory_csv, "--trajectory");
  const Timed run = SimulateTimed(scene, *solver, command.steps);
  if (command.json) {
    out << ResultJson(scene, run.result, solver->name(), run.seconds).dump(2) << "\n";
  } else {
    PrintResult(out, scene, run.result, solver->name(), run.seconds);
  }
  if (trajectory.is_open()) WriteTrajectoryCsv(trajectory, scene, run.result);
  return 0;
}

int RunSweep(const SweepCommand& command, std::ostream& out) {
  const Sweep sweep = ReadSweep(command.sweep);
  const auto solver = SolverByName(command.solver);
  std::ofstream csv;
  if (!command.csv.empty()) csv = OpenOutput(command.csv, "--csv");
  std::vector<nlohmann::json> rows;
  for (const SweepCase& c : sweep.cases) {
    const Timed run = SimulateTimed(c.scene, *solver, command.steps);
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

}  // namespace ringtol::jobs
