// `ringtol bench dynamics`, `ringtol bench ladder` and `ringtol bench campaign`: the
// studies of jobs/studies/ on one scene or on a campaign's samples, as tables, CSV and SVG.
//
// Reads and validates every input and opens every output file before the first
// simulation; throws InputError (jobs/inputs/input_error.h) when one is bad. Simulation
// failures are statuses in the output, not errors.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
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

// `ringtol bench campaign`: jobs/studies/campaign_speed.h on a campaign file's samples, then
// `ringtol report` timed on the results of its own settings (written to a temporary file
// unless `results` names one), beside the campaign's compute time.
struct BenchCampaignCommand {
  std::filesystem::path file;           // campaign file
  std::optional<std::int64_t> samples;  // overrides design.samples
  int threads = 0;                      // 0: one per core
  bool report = true;                   // time the report on the campaign mode's results
  std::filesystem::path results;        // empty: a temporary file, removed afterwards
  std::filesystem::path csv;            // empty: none
  std::filesystem::path svg;            // empty: none
};
int RunBenchCampaign(const BenchCampaignCommand& command, std::ostream& out, std::ostream& progress);

}  // namespace ringtol::jobs
