// The work behind each `ringtol` command, apart from argument parsing (jobs/main.cpp), so
// tests can call them directly. Each reads and validates every input and opens every
// output file before the first simulation, and throws InputError (jobs/input_error.h)
// when one is bad. Simulation failures are statuses in the output, not errors.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>

namespace ringtol::jobs {

struct SimulateCommand {
  std::filesystem::path scene;           // scene TOML file
  std::string solver = "quasistatic";    // a name from solvers::SolverNames()
  int steps = 0;                         // angles per revolution; 0 = automatic
  bool json = false;                     // one JSON object instead of text
  std::filesystem::path trajectory_csv;  // empty: no trajectory file
};
// Returns the process exit code (0).
int RunSimulate(const SimulateCommand& command, std::ostream& out);

struct SweepCommand {
  std::filesystem::path sweep;          // sweep TOML file
  std::string solver = "quasistatic";
  int steps = 0;
  bool json = false;                    // a JSON array instead of a table
  std::filesystem::path csv;            // empty: no CSV file
};
int RunSweep(const SweepCommand& command, std::ostream& out);

}  // namespace ringtol::jobs
