// The work behind each `ringtol` command, apart from argument parsing (jobs/cli/main.cpp), so
// tests can call them directly. Each reads and validates every input and opens every
// output file before the first simulation, and throws InputError (jobs/inputs/input_error.h)
// when one is bad. Simulation failures are statuses in the output, not errors.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "solvers/simulation.h"

namespace ringtol::jobs {

struct SimulateCommand {
  std::filesystem::path scene;           // scene TOML file
  solvers::SolverSettings solver;        // --solver, --steps, --relative-tolerance; no sampling budget
  bool json = false;                     // one JSON object instead of text
  std::filesystem::path trajectory_csv;  // empty: no trajectory file
  std::filesystem::path history_csv;     // dynamic solver only: time history over the motion law's span
  double history_interval_ms = 1.0;      // [ms] > 0, between history samples
};
// Returns the process exit code (0).
int RunSimulate(const SimulateCommand& command, std::ostream& out);

struct SweepCommand {
  std::filesystem::path sweep;          // sweep TOML file
  solvers::SolverSettings solver;
  bool json = false;                    // a JSON array instead of a table
  std::filesystem::path csv;            // empty: no CSV file
};
int RunSweep(const SweepCommand& command, std::ostream& out);

// `ringtol bench dynamics`: jobs/studies/dynamic_study.h on one scene.
struct BenchDynamicsCommand {
  std::filesystem::path scene;
  std::vector<int> orders;         // empty: the study's default (the article's orders)
  std::vector<double> rates_deg_per_s;  // empty: the study's default
};
int RunBenchDynamics(const BenchDynamicsCommand& command, std::ostream& out);

// `ringtol bench ladder`: jobs/studies/solver_ladder.h on one scene, as a table, a CSV and an SVG.
struct BenchLadderCommand {
  std::filesystem::path scene;
  std::string cases = "all";
  int repeats = 3;
  bool explicit_full_model = false;
  std::filesystem::path csv;  // empty: none
  std::filesystem::path svg;  // empty: none
};
int RunBenchLadder(const BenchLadderCommand& command, std::ostream& out, std::ostream& progress);

// `ringtol sample`: draw the assemblies of a sampling file (jobs/inputs/sampling_file.h) without
// simulating them, to inspect what the tolerances produce and to replay one sample.
struct SampleCommand {
  std::filesystem::path file;            // sampling file
  std::optional<std::int64_t> samples;   // overrides design.samples
  std::optional<std::uint64_t> seed;     // overrides seed
  std::filesystem::path csv;             // one row per sample: its drawn inputs; empty: none
  std::optional<std::int64_t> index;     // with `scene`: the sample to write
  std::filesystem::path scene;           // the assembly of sample `index` as a scene file
};

// Prints the design, the calibrated scales and how many drawn parts meet their
// tolerances; writes the CSV and the replayed scene. Returns 0; throws InputError for a
// bad file or option before anything is written.
int RunSample(const SampleCommand& command, std::ostream& out);

// `ringtol classes`: the catalogue's classes, one line each with their source, or the
// catalogue file itself.
int RunClasses(bool toml, std::ostream& out);

}  // namespace ringtol::jobs
