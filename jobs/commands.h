// The work behind each `ringtol` command, apart from argument parsing (jobs/main.cpp), so
// tests can call them directly. Each reads and validates every input and opens every
// output file before the first simulation, and throws InputError (jobs/input_error.h)
// when one is bad. Simulation failures are statuses in the output, not errors.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

namespace ringtol::jobs {

struct SimulateCommand {
  std::filesystem::path scene;           // scene TOML file
  std::string solver = "quasistatic";    // a name from solvers::SolverNames()
  int steps = 0;                         // angles per revolution; 0 = automatic
  bool json = false;                     // one JSON object instead of text
  std::filesystem::path trajectory_csv;  // empty: no trajectory file
  double relative_tolerance = 1e-6;      // dynamic solver only: solvers::DynamicOptions
  std::filesystem::path history_csv;     // dynamic solver only: time history over the motion law's span
  double history_interval_ms = 1.0;      // [ms] > 0, between history samples
};
// Returns the process exit code (0).
int RunSimulate(const SimulateCommand& command, std::ostream& out);

struct SweepCommand {
  std::filesystem::path sweep;          // sweep TOML file
  std::string solver = "quasistatic";
  int steps = 0;
  bool json = false;                    // a JSON array instead of a table
  std::filesystem::path csv;            // empty: no CSV file
  double relative_tolerance = 1e-6;     // dynamic solver only
};
int RunSweep(const SweepCommand& command, std::ostream& out);

// `ringtol bench dynamics`: jobs/dynamic_study.h on one scene.
struct BenchDynamicsCommand {
  std::filesystem::path scene;
  std::vector<int> orders;         // empty: the study's default (the article's orders)
  std::vector<double> rates_deg_per_s;  // empty: the study's default
};
int RunBenchDynamics(const BenchDynamicsCommand& command, std::ostream& out);

// `ringtol bench ladder`: jobs/solver_ladder.h on one scene, as a table, a CSV and an SVG.
struct BenchLadderCommand {
  std::filesystem::path scene;
  std::string cases = "all";
  int repeats = 3;
  bool explicit_full_model = false;
  std::filesystem::path csv;  // empty: none
  std::filesystem::path svg;  // empty: none
};
int RunBenchLadder(const BenchLadderCommand& command, std::ostream& out, std::ostream& progress);

}  // namespace ringtol::jobs
