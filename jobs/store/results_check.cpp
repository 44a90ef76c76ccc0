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

std::vector<SampleRange> Without(const std::vector<SampleRange>& rows, const std::vector<SampleRange>& removed) {
  std::vector<SampleRange> kept;
  auto next = removed.begin();
  for (SampleRange range : rows) {
    while (next != removed.end() && next->end <= range.begin) ++next;
    for (auto it = next; it != removed.end() && it->begin < range.end; ++it) {
      if (it->begin > range.begin) kept.push_back({range.begin, it->begin});
      range.begin = std::max(range.begin, it->end);
    }
    if (range.begin < range.end) kept.push_back(range);
  }
  return kept;
}

namespace {

std::vector<SampleRange> Intersect(const std::vector<SampleRange>& a, const std::vector<SampleRange>& b) {
  return Without(a, Without(a, b));
}

std::int64_t Count(const std::vector<SampleRange>& ranges) {
  std::int64_t count = 0;
  for (const SampleRange& range : ranges) count += range.end - range.begin;
  return count;
}

}  // namespace

ResultsCheck SumOfShards(ResultsCheck index, const std::vector<ShardCheck>& shards) {
  const std::int64_t rows = index.allocation() ? index.candidates * index.samples : index.samples;
  // An allocation's damaged ranges each stay within one candidate: sorted, never joined.
  const auto merge = [&](std::vector<SampleRange> ranges) {
    if (!index.allocation()) return MergeRanges(std::move(ranges));
    std::sort(ranges.begin(), ranges.end(), [](const SampleRange& a, const SampleRange& b) { return a.begin < b.begin; });
    return ranges;
  };
  std::vector<SampleRange> claimed;  // some shard answers for them
  std::vector<SampleRange> done;     // and its status chunk reads
  std::vector<SampleRange> whole;    // and no dataset of that shard is damaged there
  for (const auto& [name, one] : shards) {
    const std::vector<SampleRange> answers = Without({{0, rows}}, one.pending);
    std::vector<SampleRange> damaged_here;
    std::vector<SampleRange> status_damaged;
    for (const DatasetCheck& dataset : one.datasets) {
      auto found = std::find_if(index.datasets.begin(), index.datasets.end(),
                                [&](const DatasetCheck& d) { return d.path == dataset.path; });
      if (found != index.datasets.end() && !found->per_sample) continue;  // the index keeps it itself
      const std::vector<SampleRange> damaged = Intersect(merge(dataset.damaged), answers);
      if (dataset.path == "/outputs/status") status_damaged = damaged;
      damaged_here.insert(damaged_here.end(), damaged.begin(), damaged.end());
      if (found == index.datasets.end()) {
        DatasetCheck copy = dataset;
        copy.damaged.clear();
        copy.first_problem.clear();
        index.datasets.push_back(std::move(copy));
        found = index.datasets.end() - 1;
      }
      found->checksummed = found->checksummed && dataset.checksummed;
      if (!damaged.empty() && found->first_problem.empty()) found->first_problem = name + ": " + dataset.first_problem;
      found->damaged.insert(found->damaged.end(), damaged.begin(), damaged.end());
      found->damaged = merge(std::move(found->damaged));
    }
    claimed.insert(claimed.end(), answers.begin(), answers.end());
    const std::vector<SampleRange> readable = Without(answers, status_damaged);
    done.insert(done.end(), readable.begin(), readable.end());
    const std::vector<SampleRange> intact = Without(answers, MergeRanges(std::move(damaged_here)));
    whole.insert(whole.end(), intact.begin(), intact.end());
    index.done_screen += one.done_screen;
    index.done_confirm += one.done_confirm;
  }
  if (index.allocation()) {
    index.done = index.done_screen + index.done_confirm;
    return index;
  }
  index.done = Count(MergeRanges(std::move(done)));
  index.pending = Without({{0, rows}}, MergeRanges(std::move(claimed)));
  index.recompute = Without({{0, rows}}, MergeRanges(std::move(whole)));
  return index;
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
