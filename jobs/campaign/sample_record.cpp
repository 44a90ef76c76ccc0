#include "jobs/campaign/sample_record.h"

#include <boost/crc.hpp>

namespace ringtol::jobs {

std::uint32_t DrawChecksum(const SampleRecord& record) {
  boost::crc_32_type crc;
  crc.process_bytes(record.u.data(), record.u.size() * sizeof(double));
  for (const double value : record.values) {
    const auto stored = static_cast<float>(value);
    crc.process_bytes(&stored, sizeof(stored));
  }
  crc.process_bytes(&record.redraws, sizeof(record.redraws));
  return crc.checksum();
}

SampleStatus FromSolverStatus(solvers::Status status) {
  return static_cast<SampleStatus>(static_cast<std::int8_t>(status));
}

std::string_view SampleStatusName(SampleStatus status) {
  const int value = static_cast<int>(status);
  if (value >= 0 && value <= kLastSolverStatus) return solvers::StatusName(static_cast<solvers::Status>(value));
  return NameOf(kCampaignStatusNames, status);
}

const std::vector<SampleStatus>& AllSampleStatuses() {
  static const std::vector<SampleStatus> statuses = [] {
    std::vector<SampleStatus> all{SampleStatus::kPending};
    for (int value = 0; value <= kLastSolverStatus; ++value) all.push_back(static_cast<SampleStatus>(value));
    for (const auto& [status, name] : kCampaignStatusNames) {
      if (status != SampleStatus::kPending) all.push_back(status);
    }
    return all;
  }();
  return statuses;
}

}  // namespace ringtol::jobs
