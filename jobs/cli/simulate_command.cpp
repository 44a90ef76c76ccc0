#include "jobs/cli/simulate_command.h"

#include <array>
#include <chrono>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "jobs/cli/contact_warning.h"
#include "jobs/cli/option_flags.h"
#include "jobs/cli/results_output.h"
#include "jobs/inputs/input_error.h"
#include "jobs/inputs/scene_file.h"
#include "jobs/inputs/sweep_file.h"
#include "jobs/inputs/toml_fields.h"
#include "jobs/report/report_text.h"
#include "engine/units.h"
#include "solvers/dynamic.h"
#include "solvers/life.h"
#include "solvers/linear.h"

namespace ringtol::jobs {
namespace {

// The flags that set SolverSettings' fields (jobs/cli/main.cpp, AddSolverOptions).
constexpr std::array<OptionName, 2> kSolverFlags{{
    {"simulation.steps", "--steps"},
    {"relative_tolerance", "--relative-tolerance"},
}};

// The command line's settings, checked by their IsValid (CLI11 reads --steps in its range).
std::unique_ptr<solvers::Solver> CheckedSolver(const solvers::SolverSettings& settings) {
  RequireValid(settings, kSolverFlags);
  return solvers::MakeSolver(settings);
}

// A step count the user gives has no error budget: below engine::MinimumSteps of the
// scene's fastest term it aliases that term, and the metrics read it as slower or still.
void RequireEnoughSteps(const engine::Scene& scene, int steps, std::string_view scene_name) {
  if (steps == 0) return;
  const engine::FastestHarmonic fastest = engine::FindFastestHarmonic(scene);
  if (steps >= engine::MinimumSteps(fastest.rate)) return;
  throw InputError(fmt::format("--steps {}: too few for {}: allowed: {}", steps, scene_name, StepsRule(scene, fastest)));
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

nlohmann::json ValuesJson(const solvers::LifeValues& values) {
  const auto mm = [](double metres) { return metres * units::kMillimetresPerMetre; };
  return {{"d_trajectory_mm", mm(values.d_trajectory)},
          {"runout_mm", mm(values.runout)},
          {"error_motion_total_mm", mm(values.error_motion.total)},
          {"error_motion_synchronous_mm", mm(values.error_motion.synchronous)},
          {"error_motion_asynchronous_mm", mm(values.error_motion.asynchronous)},
          {"error_motion_fundamental_mm", mm(values.error_motion.fundamental)}};
}

nlohmann::json LifeJson(const engine::Scene& scene, const solvers::LifeResult& life) {
  nlohmann::json json = {{"status", std::string(solvers::StatusName(life.status))}, {"revolutions", life.revolutions}};
  if (life.status != solvers::Status::kOk) {
    json["message"] = life.message;
    return json;
  }
  const engine::ErrorMotionFilter& filter = scene.error_motion_filter;
  json["error_motion_filter_cutoff_upr"] = filter.cutoff_upr;
  json["over_revolutions"] = ValuesJson(life.values);
  json["over_revolutions"]["error_motion_reading"] =
      ErrorMotionConditions({.filter = filter, .revolutions = life.revolutions});
  json["artefact_mm"] = life.artefact * units::kMillimetresPerMetre;
  if (life.asymptotic) {
    json["every_revolution"] = ValuesJson(*life.asymptotic);
    json["every_revolution"]["error_motion_reading"] = ErrorMotionConditions({.filter = filter});
    json["phase_locked_rollers"] = scene.phase_locked_rollers;
    json["cycle"] = life.cycle;
    json["allowance_um"] = life.error_estimate * units::kMicrometresPerMetre;
  }
  return json;
}

void PrintLife(std::ostream& out, const engine::Scene& scene, const solvers::LifeResult& life) {
  if (life.status != solvers::Status::kOk) {
    fmt::print(out, "life              {}: {}\n", solvers::StatusName(life.status), life.message);
    return;
  }
  const auto um = [](double metres) { return metres * units::kMicrometresPerMetre; };
  // Which life the every-revolution column is (docs/model.md §9): every phase of each
  // roller, or phase-locked rollers' revolutions, which repeat after a cycle where their
  // spin ratios are commensurate and otherwise drift through every phase.
  const std::string heading = !scene.phase_locked_rollers ? std::string("every phase")
                              : life.cycle > 0            ? fmt::format("locked: cycle {}", life.cycle)
                                                          : std::string("locked: drifts");
  const std::string every = life.asymptotic ? fmt::format("{:>16}", heading) : std::string();
  fmt::print(out, "life              {:>16}{}   revolutions (docs/model.md §9)\n", life.revolutions, every);
  const auto row = [&](const char* name, double over, std::optional<double> asymptotic) {
    fmt::print(out, "  {:<16}{:>16.3f}{}   um\n", name, um(over),
               asymptotic ? fmt::format("{:>16.3f}", um(*asymptotic)) : std::string());
  };
  const auto of = [&](auto field) -> std::optional<double> {
    return life.asymptotic ? std::optional<double>(field(*life.asymptotic)) : std::nullopt;
  };
  row("D_trajectory", life.values.d_trajectory, of([](const solvers::LifeValues& v) { return v.d_trajectory; }));
  row("runout", life.values.runout, of([](const solvers::LifeValues& v) { return v.runout; }));
  row("error motion", life.values.error_motion.total,
      of([](const solvers::LifeValues& v) { return v.error_motion.total; }));
  row("  synchronous", life.values.error_motion.synchronous,
      of([](const solvers::LifeValues& v) { return v.error_motion.synchronous; }));
  row("  asynchronous", life.values.error_motion.asynchronous,
      of([](const solvers::LifeValues& v) { return v.error_motion.asynchronous; }));
  fmt::print(out, "  {:<16}{:>16.3f}   um, the bore's own form at the sensor, fundamental removed\n", "artefact",
             um(life.artefact));
  fmt::print(out, "  error motion: ISO 230-7 in the sensor's direction, fundamental removed, {}\n",
             ErrorMotionFilterName(scene.error_motion_filter));
  if (life.asymptotic) {
    fmt::print(out, "  {:<16}{:>16.3f}   um on the every-revolution values\n", "allowance", um(life.error_estimate));
  }
}

}  // namespace

int RunSimulate(const SimulateCommand& command, std::ostream& out, std::ostream& warnings) {
  const engine::Scene scene = ReadScene(command.scene);
  RequireEnoughSteps(scene, command.solver.simulation.steps, command.scene.string());
  const auto solver = CheckedSolver(command.solver);
  const auto* dynamic = dynamic_cast<const solvers::DynamicSolver*>(solver.get());
  // Every option is checked before any output file is opened (and so emptied).
  if (!command.history_csv.empty()) {
    if (dynamic == nullptr) throw InputError("--history: only the dynamic solver has a time history (--solver dynamic)");
    if (!(command.history_interval_ms > 0.0)) {
      throw InputError("--history-interval-ms " + std::to_string(command.history_interval_ms) + ": allowed: > 0");
    }
  }
  if (command.revolutions < 0) {
    throw InputError("--revolutions " + std::to_string(command.revolutions) + ": allowed: >= 0");
  }
  std::ofstream trajectory = OpenOptionalOutput(command.trajectory_csv, "--trajectory");
  std::ofstream history_file = OpenOptionalOutput(command.history_csv, "--history");
  WarnAboutContactLaw(scene, command.scene, warnings);
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
  if (command.revolutions > 0) {
    const auto* linear = dynamic_cast<const solvers::LinearSolver*>(solver.get());
    const solvers::LifeResult life =
        linear != nullptr ? solvers::LinearLife(scene, *linear, command.solver.simulation, command.revolutions)
                          : solvers::SimulateLife(scene, *solver, command.solver.simulation, command.revolutions);
    json["life"] = LifeJson(scene, life);
    if (!command.json) PrintLife(out, scene, life);
  }
  if (command.json) out << json.dump(2) << "\n";
  return 0;
}

int RunSweep(const SweepCommand& command, std::ostream& out, std::ostream& warnings) {
  const Sweep sweep = ReadSweep(command.sweep);
  for (const SweepCase& c : sweep.cases) {
    RequireEnoughSteps(c.scene, command.solver.simulation.steps,
                       fmt::format("case \"{}\" of {}", c.name, command.sweep.string()));
  }
  const auto solver = CheckedSolver(command.solver);
  std::ofstream csv = OpenOptionalOutput(command.csv, "--csv");
  // The cases differ in their errors only: one error-free assembly, one law.
  WarnAboutContactLaw(sweep.cases.front().scene, sweep.scene_file, warnings);
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
