#include "jobs/cli/report_command.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

#include <fmt/format.h>

#include "engine/visible_text.h"
#include "jobs/inputs/input_error.h"
#include "jobs/report/allocation_report.h"
#include "jobs/store/allocation_store.h"
#include "jobs/report/report_html.h"
#include "jobs/report/report_text.h"
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
  if (std::filesystem::is_directory(path, error)) {
    throw InputError(fmt::format("{} {}: is a folder; allowed: a file name in it", option, path.string()));
  }
  if (access(folder.c_str(), W_OK) != 0) {
    throw InputError(fmt::format("{} {}: the folder '{}' is not writable ({})", option, path.string(), folder.string(),
                                 std::strerror(errno)));
  }
}

// Write beside, then rename: readers see the old page or the new one, never half of one.
void WriteAtomically(const std::filesystem::path& path, const std::string& text) {
  const std::filesystem::path temporary = path.string() + ".partial";
  {
    errno = 0;
    std::ofstream file(temporary, std::ios::binary | std::ios::trunc);
    file << text;
    file.close();
    if (!file) {
      const int reason = errno;
      std::error_code ignored;
      std::filesystem::remove(temporary, ignored);
      throw InputError(fmt::format("{}: cannot be written ({})", path.string(),
                                   reason != 0 ? std::strerror(reason) : "the write failed"));
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw InputError(fmt::format("{}: cannot be written ({})", path.string(), error.message()));
  }
}

analysis::SobolEstimator EstimatorNamed(const std::string& name) {
  if (const auto estimator = ValueNamed(analysis::kSobolEstimatorNames, name)) return *estimator;
  throw InputError(fmt::format("--estimator {}: unknown; allowed: {}", VisibleText(name),
                               NameList(analysis::kSobolEstimatorNames, "")));
}

// The page, and the JSON when asked for; says where they went.
template <typename Json>
int WriteReport(const ReportCommand& command, const std::string& html, Json json, std::ostream& out) {
  WriteAtomically(command.out, html);
  out << "Report: " << command.out.string() << "\n";
  if (command.json) {
    WriteAtomically(*command.json, json().dump(1) + "\n");
    out << "Summary (JSON): " << command.json->string() << "\n";
  }
  return 0;
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
  if (ReadResultsKind(command.results) == ResultsKind::kAllocation) {
    if (const ResultsCheck check = CheckAllocationResults(command.results); !check.intact()) {
      const auto damaged = std::find_if(check.datasets.begin(), check.datasets.end(),
                                        [](const DatasetCheck& d) { return !d.damaged.empty(); });
      throw InputError(fmt::format("{}: damaged ({}); `ringtol verify {}` lists what, and `ringtol allocate "
                                   "--resume` recomputes the samples of damaged chunks",
                                   command.results.string(), damaged->first_problem, command.results.string()));
    }
    AllocationReportOptions allocation;
    allocation.bootstrap_resamples = options.bootstrap_resamples;
    allocation.screening_samples = options.screening_samples;
    const AllocationReport report = ReadAllocationReport(command.results, allocation);
    return WriteReport(command, AllocationReportHtml(report), [&] { return AllocationReportJson(report); }, out);
  }
  if (const ResultsCheck check = CheckResults(command.results); !check.intact()) {
    throw InputError(DamageMessage(command.results, check));
  }
  const CampaignReport report = BuildReport(command.results, options);
  const int status = WriteReport(command, ReportHtml(report), [&] { return ReportJson(report); }, out);
  for (const PopulationView& view : report.populations) out << PopulationLine(view) << "\n";
  return status;
}

}  // namespace ringtol::jobs
