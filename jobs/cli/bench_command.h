// `ringtol bench dynamics` and `ringtol bench ladder`: the studies of jobs/studies/ on one
// scene, as tables, CSV and SVG.
//
// Reads and validates every input and opens every output file before the first
// simulation; throws InputError (jobs/inputs/input_error.h) when one is bad. Simulation
// failures are statuses in the output, not errors.
#pragma once

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

namespace ringtol::jobs {

// `ringtol bench dynamics`: jobs/studies/dynamic_study.h on one scene.
struct BenchDynamicsCommand {
  std::filesystem::path scene;
  std::vector<int> orders;         // empty: the study's default (the article's orders)
  std::vector<double> rates_deg_per_s;  // empty: the study's default
  std::filesystem::path svg;            // empty: none; else the start table's chart
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

}  // namespace ringtol::jobs
