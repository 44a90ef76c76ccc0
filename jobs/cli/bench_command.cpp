#include "jobs/cli/bench_command.h"

#include <unistd.h>

#include <chrono>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "engine/units.h"
#include "jobs/campaign/campaign.h"
#include "jobs/cli/contact_warning.h"
#include "jobs/cli/report_command.h"
#include "jobs/cli/results_output.h"
#include "jobs/inputs/input_error.h"
#include "jobs/inputs/scene_file.h"
#include "jobs/store/campaign_store.h"
#include "jobs/studies/campaign_speed.h"
#include "jobs/studies/dynamic_study.h"
#include "jobs/studies/solver_ladder.h"

namespace ringtol::jobs {
int RunBenchDynamics(const BenchDynamicsCommand& command, std::ostream& out) {
  const engine::Scene scene = ReadScene(command.scene);
  std::ofstream svg = OpenOptionalOutput(command.svg, "--svg");
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
  std::ofstream csv = OpenOptionalOutput(command.csv, "--csv");
  std::ofstream svg = OpenOptionalOutput(command.svg, "--svg");
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

namespace {

// Writes the campaign's records as `ringtol campaign` would and times `ringtol report` on
// them (HTML page included), so the two are compared as a user meets them.
double TimeReport(const Campaign& campaign, const std::vector<SampleRecord>& records,
                  const std::filesystem::path& results) {
  {
    CampaignStore store = CampaignStore::Create(results, campaign.identity(), campaign.samples());
    for (const SampleRecord& record : records) store.Add(record);
    store.Commit();
  }
  ReportCommand report;
  report.results = results;
  report.out = std::filesystem::path(results).replace_extension(".html");
  std::ostringstream ignored;
  const auto start = std::chrono::steady_clock::now();
  RunReport(report, ignored);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::filesystem::remove(report.out);
  return seconds;
}

}  // namespace

int RunBenchCampaign(const BenchCampaignCommand& command, std::ostream& out, std::ostream& progress) {
  const Campaign campaign(command.file, command.samples, std::nullopt);
  WarnAboutContactLaw(campaign.plan().sampling.scene, campaign.plan().sampling.scene_file, progress);
  if (!command.results.empty() && std::filesystem::exists(command.results)) {
    throw InputError(fmt::format("--results {}: the file exists; a results file is never overwritten",
                                 command.results.string()));
  }
  std::ofstream csv = OpenOptionalOutput(command.csv, "--csv");
  std::ofstream svg = OpenOptionalOutput(command.svg, "--svg");
  CampaignSpeedOptions options;
  options.threads = command.threads;
  CampaignSpeedResult result = RunCampaignSpeed(campaign.plan(), options, &progress);
  PrintCampaignSpeed(out, result);
  if (command.report) {
    const bool temporary = command.results.empty();
    const std::filesystem::path results =
        temporary ? std::filesystem::temp_directory_path() / fmt::format("ringtol-bench-{}.h5", ::getpid())
                  : command.results;
    progress << "bench campaign: ringtol report on the campaign mode's results\n" << std::flush;
    result.report_time = TimeReport(campaign, result.first_mode_records, results);
    if (temporary) std::filesystem::remove(results);
    const CampaignModeRow& own = result.rows.front();
    out << fmt::format("report            {:.2f} s for {} samples: {:.1f} % of the campaign's compute time ({:.2f} s, "
                       "mode {})\n",
                       result.report_time, result.samples, 100.0 * result.report_time / own.wall_time, own.wall_time,
                       own.name);
  }
  if (csv.is_open()) WriteCampaignSpeedCsv(csv, result);
  if (svg.is_open()) WriteCampaignSpeedSvg(svg, result);
  return 0;
}

}  // namespace ringtol::jobs
