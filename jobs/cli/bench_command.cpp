#include "jobs/cli/bench_command.h"

#include <fstream>

#include "engine/units.h"
#include "jobs/cli/results_output.h"
#include "jobs/inputs/scene_file.h"
#include "jobs/studies/dynamic_study.h"
#include "jobs/studies/solver_ladder.h"

namespace ringtol::jobs {
int RunBenchDynamics(const BenchDynamicsCommand& command, std::ostream& out) {
  const engine::Scene scene = ReadScene(command.scene);
  std::ofstream svg;
  if (!command.svg.empty()) svg = OpenOutput(command.svg, "--svg");
  DynamicStudyOptions options;
  if (!command.orders.empty()) options.orders = command.orders;
  if (!command.rates_deg_per_s.empty()) {
    options.rates.clear();
    for (const double rate : command.rates_deg_per_s) options.rates.push_back(rate * units::kRadiansPerDegree);
  }
  const DynamicStudy study = RunDynamicStudy(scene, options, nullptr);
  PrintDynamicStudy(out, study);
  if (svg.is_open()) WriteDynamicStudySvg(svg, study);
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

}  // namespace ringtol::jobs
