// `ringtol report RESULTS.h5 --out report.html [--json summary.json]`: a campaign's results
// file as one self-contained HTML page (jobs/report/report_html.h) and, on request, the same
// numbers as JSON (jobs/report/campaign_report.h); an allocation's results file likewise
// (jobs/report/allocation_report.h), told apart by the file's own format attribute.
//
// Failure: InputError, before any statistic is computed, for a results file that does not
// open or is damaged (any chunk that fails its checksum: CheckResults), a report path in a folder that does not exist, a report path that is the results
// file itself, or options outside their ranges. Reports are derived files: an existing
// one is replaced, atomically (written beside it, then renamed), so a failed run never
// leaves half a page.
#pragma once

#include <filesystem>
#include <optional>
#include <ostream>
#include <string>

#include "jobs/report/campaign_report.h"

namespace ringtol::jobs {

struct ReportCommand {
  std::filesystem::path results;
  std::filesystem::path out;                      // the HTML page
  std::optional<std::filesystem::path> json;      // the JSON summary
  std::string estimator = "saltelli2010-jansen";  // analysis::SobolEstimatorName
  ReportOptions options;
};

// Prints where the page (and the JSON) went.
int RunReport(const ReportCommand& command, std::ostream& out);

}  // namespace ringtol::jobs
