#include "jobs/cli/report_command.h"

#include <fstream>
#include <system_error>

#include <fmt/format.h>

#include "jobs/inputs/input_error.h"
#include "jobs/report/report_html.h"
#include "jobs/store/campaign_store.h"

namespace ringtol::jobs {
namespace {

void CheckWritable(const std::filesystem::path& path, const std::filesystem::path& results, const char* option) {
  const std::filesystem::path folder = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  std::error_code error;
  if (!std::filesystem::is_directory(folder, error)) {
    throw InputError(fmt::format("{} {}: the folder '{}' does not exist; allowed: a file in an existing folder", option,
                                 path.string(), folder.string()));
  }
  if (std::filesystem::equivalent(path, results, error)) {
    throw InputError(fmt::format("{} {}: is the results file itself; allowed: another path", option, path.string()));
  }
}

// Write beside, then rename: readers see the old page or the new one, never half of one.
void WriteAtomically(const std::filesystem::path& path, const std::string& text) {
  const std::filesystem::path temporary = path.string() + ".partial";
  {
    std::ofstream file(temporary, std::ios::binary | std::ios::trunc);
    file << text;
    file.close();
    if (!file) {
      std::filesystem::remove(temporary);
      throw InputError(fmt::format("{}: cannot be written", path.string()));
    }
  }
  std::filesystem::rename(temporary, path);
}

analysis::SobolEstimator EstimatorNamed(const std::string& name) {
  if (const auto estimator = ValueNamed(analysis::kSobolEstimatorNames, name)) return *estimator;
  throw InputError(fmt::format("--estimator {}: unknown; allowed: {}", name, NameList(analysis::kSobolEstimatorNames, "")));
}

}  // namespace

int RunReport(const ReportCommand& command, std::ostream& out) {
  ReportOptions options = command.options;
  options.estimator = EstimatorNamed(command.estimator);
  CheckWritable(command.out, command.results, "--out");
  if (command.json) CheckWritable(*command.json, command.results, "--json");
  // Every chunk is read once up front, not only those the report reads: a page built on a
  // damaged file must not exist, and the replays would otherwise catch a damaged design
  // point as a replay problem.
  if (const ResultsCheck check = CheckResults(command.results); !check.intact()) {
    throw InputError(DamageMessage(command.results, check));
  }
  const CampaignReport report = BuildReport(command.results, options);
  WriteAtomically(command.out, ReportHtml(report));
  out << "Report: " << command.out.string() << "\n";
  if (command.json) {
    WriteAtomically(*command.json, ReportJson(report).dump(1) + "\n");
    out << "Summary (JSON): " << command.json->string() << "\n";
  }
  return 0;
}

}  // namespace ringtol::jobs
