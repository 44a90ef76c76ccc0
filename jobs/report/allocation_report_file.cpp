// ReadAllocationReport apart from the rest of the report: it alone needs the allocation
// results file's reader (jobs/store/allocation_store.h).
#include <cstdint>
#include <string>
#include <vector>

#include "jobs/report/allocation_report.h"
#include "jobs/store/allocation_store.h"

namespace ringtol::jobs {

AllocationReport ReadAllocationReport(const std::filesystem::path& results, const AllocationReportOptions& options) {
  const AllocationReader reader(results);
  AllocationReportInput input;
  input.results = results;
  input.identity = reader.identity();
  input.outcome = reader.ReadOutcome();
  if (const std::optional<std::int64_t> recommended = input.outcome.recommendation) {
    const CandidateOutcome& candidate = input.outcome.candidates.at(static_cast<std::size_t>(*recommended));
    // The recommendation was settled feasible, which only the confirming rung's samples do.
    const EvaluationRole role = candidate.settled_by.value_or(EvaluationRole::kConfirm);
    const std::int64_t n = candidate.samples;
    for (const analysis::Constraint& constraint : input.identity.constraints) {
      if (input.recommendation_samples.contains(constraint.output)) continue;
      input.recommendation_samples[constraint.output] = reader.ReadOutput(role, constraint.output, *recommended, 0, n);
    }
    input.design_points = reader.ReadDesignPoints(0, n);
  }
  return MakeAllocationReport(input, options);
}

}  // namespace ringtol::jobs
