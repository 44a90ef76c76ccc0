// `ringtol simulate` and `ringtol sweep`: one scene, or every case of a sweep file, through
// one rung of the solver ladder.
//
// Reads and validates every input and opens every output file before the first
// simulation; throws InputError (jobs/inputs/input_error.h) when one is bad. Simulation
// failures are statuses in the output, not errors.
#pragma once

#include <filesystem>
#include <ostream>

#include "solvers/simulation.h"

namespace ringtol::jobs {

struct SimulateCommand {
  std::filesystem::path scene;           // scene TOML file
  solvers::SolverSettings solver;        // --solver, --steps, --relative-tolerance, --dynamic-start; no sampling budget
  bool json = false;                     // one JSON object instead of text
  std::filesystem::path trajectory_csv;  // empty: no trajectory file
  std::filesystem::path history_csv;     // dynamic solver only: time history over the motion law's span
  double history_interval_ms = 1.0;      // [ms] > 0, between history samples
  // >= 0: also the life metrics over this many revolutions (docs/model.md §9), each
  // solved from its turned roller phases; on the linear rung also over every revolution,
  // in closed form. 0: one revolution only.
  int revolutions = 0;
};
// Returns the process exit code (0). `warnings` (stderr) receives the contact law's warning
// (jobs/cli/contact_warning.h) before the simulation.
int RunSimulate(const SimulateCommand& command, std::ostream& out, std::ostream& warnings);

struct SweepCommand {
  std::filesystem::path sweep;          // sweep TOML file
  solvers::SolverSettings solver;
  bool json = false;                    // a JSON array instead of a table
  std::filesystem::path csv;            // empty: no CSV file
};
// The contact law's warning, from the base scene, goes to `warnings` once.
int RunSweep(const SweepCommand& command, std::ostream& out, std::ostream& warnings);

}  // namespace ringtol::jobs
