#include "jobs/campaign/sample_record.h"

namespace ringtol::jobs {
namespace {

// solvers::Status is numbered 0..kNonFinite; SampleStatus reuses those numbers.
constexpr int kLastSolverStatus = static_cast<int>(solvers::Status::kNonFinite);

}  // namespace

SampleStatus FromSolverStatus(solvers::Status status) {
  return static_cast<SampleStatus>(static_cast<std::int8_t>(status));
}

std::string_view SampleStatusName(SampleStatus status) {
  const int value = static_cast<int>(status);
  if (value >= 0 && value <= kLastSolverStatus) return solvers::StatusName(static_cast<solvers::Status>(value));
  switch (status) {
    case SampleStatus::kPending:
      return "pending";
    case SampleStatus::kException:
      return "exception";
    case SampleStatus::kNonFiniteOutput:
      return "non_finite_output";
    case SampleStatus::kSamplingFailed:
      return "sampling_failed";
    default:
      return "unknown";
  }
}

const std::vector<SampleStatus>& AllSampleStatuses() {
  static const std::vector<SampleStatus> statuses = [] {
    std::vector<SampleStatus> all{SampleStatus::kPending};
    for (int value = 0; value <= kLastSolverStatus; ++value) all.push_back(static_cast<SampleStatus>(value));
    all.insert(all.end(), {SampleStatus::kException, SampleStatus::kNonFiniteOutput, SampleStatus::kSamplingFailed});
    return all;
  }();
  return statuses;
}

}  // namespace ringtol::jobs
