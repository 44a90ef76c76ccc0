#include "jobs/store/results_check.h"

#include <fmt/format.h>

#include <algorithm>

namespace ringtol::jobs {

bool ResultsCheck::intact() const {
  return std::all_of(datasets.begin(), datasets.end(), [](const DatasetCheck& d) { return d.damaged.empty(); });
}

bool ResultsCheck::checksummed() const {
  return std::all_of(datasets.begin(), datasets.end(), [](const DatasetCheck& d) { return d.checksummed; });
}

std::vector<SampleRange> MergeRanges(std::vector<SampleRange> ranges) {
  std::sort(ranges.begin(), ranges.end(), [](const SampleRange& a, const SampleRange& b) { return a.begin < b.begin; });
  std::vector<SampleRange> merged;
  for (const SampleRange& range : ranges) {
    if (range.begin >= range.end) continue;
    if (!merged.empty() && range.begin <= merged.back().end) {
      merged.back().end = std::max(merged.back().end, range.end);
    } else {
      merged.push_back(range);
    }
  }
  return merged;
}

std::string FormatRanges(const std::vector<SampleRange>& ranges) {
  std::vector<std::string> parts;
  for (const SampleRange& range : ranges) {
    parts.push_back(range.end - range.begin == 1 ? fmt::format("{}", range.begin)
                                                 : fmt::format("{} to {}", range.begin, range.end - 1));
  }
  return fmt::format("{}", fmt::join(parts, ", "));
}

std::string DamagedDatasets(const ResultsCheck& check) {
  std::vector<std::string> damaged;
  for (const DatasetCheck& dataset : check.datasets) {
    if (dataset.damaged.empty()) continue;
    std::vector<std::string> rows;
    if (check.allocation() && dataset.per_sample) {
      for (const SampleRange& range : dataset.damaged) {
        rows.push_back(fmt::format("candidate {}, samples {}", check.CandidateOf(range),
                                   FormatRanges({check.SamplesOf(range)})));
      }
    } else {
      rows.push_back("samples " + FormatRanges(dataset.damaged));
    }
    damaged.push_back(fmt::format("dataset {} is damaged at {} ({})", dataset.path, fmt::join(rows, "; "),
                                  dataset.first_problem));
  }
  return fmt::format("{}", fmt::join(damaged, "; "));
}

}  // namespace ringtol::jobs
