#include "jobs/cli/verify_command.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "jobs/store/allocation_store.h"
#include "jobs/store/campaign_store.h"

namespace ringtol::jobs {
namespace {

std::int64_t Count(const std::vector<SampleRange>& ranges) {
  std::int64_t count = 0;
  for (const SampleRange& range : ranges) count += range.end - range.begin;
  return count;
}

nlohmann::json RangesJson(const std::vector<SampleRange>& ranges) {
  nlohmann::json array = nlohmann::json::array();
  for (const SampleRange& range : ranges) array.push_back({range.begin, range.end - 1});
  return array;
}

std::string Verdict(const ResultsCheck& check) {
  if (!check.intact()) return "damaged";
  return check.checksummed() ? "intact" : "unchecked";
}

int ExitStatus(const ResultsCheck& check) {
  if (!check.intact()) return kVerifyDamaged;
  return check.checksummed() ? kVerifyIntact : kVerifyUnchecked;
}

void PrintJson(const VerifyCommand& command, const ResultsCheck& check, std::ostream& out) {
  nlohmann::json datasets = nlohmann::json::array();
  for (const DatasetCheck& dataset : check.datasets) {
    nlohmann::json entry = {{"path", dataset.path},
                            {"checksum", dataset.checksummed},
                            {"state", !dataset.damaged.empty() ? "damaged" : dataset.checksummed ? "intact" : "unchecked"},
                            {"damaged_samples", RangesJson(dataset.damaged)}};
    if (!dataset.damaged.empty()) entry["problem"] = dataset.first_problem;
    datasets.push_back(std::move(entry));
  }
  const nlohmann::json result = {{"file", command.results.string()},
                                 {"verdict", Verdict(check)},
                                 {"samples", check.samples},
                                 {"done", check.done},
                                 {"pending", Count(check.pending)},
                                 {"pending_samples", RangesJson(check.pending)},
                                 {"resume_recomputes", Count(check.recompute)},
                                 {"resume_recomputes_samples", RangesJson(check.recompute)},
                                 {"datasets", datasets}};
  out << result.dump(1) << "\n";
}

void PrintTable(const VerifyCommand& command, const ResultsCheck& check, std::ostream& out) {
  std::size_t width = 0;
  for (const DatasetCheck& dataset : check.datasets) width = std::max(width, dataset.path.size());
  out << fmt::format("{}: {} samples, {} datasets\n", command.results.string(), check.samples, check.datasets.size());
  for (const DatasetCheck& dataset : check.datasets) {
    std::string state = "intact";
    if (!dataset.damaged.empty()) {
      state = fmt::format("DAMAGED at samples {} ({})", FormatRanges(dataset.damaged), dataset.first_problem);
    } else if (!dataset.checksummed) {
      state = "no checksum: reads, but damage cannot be detected";
    }
    out << fmt::format("  {:<{}}  {}\n", dataset.path, width, state);
  }
  // Rows whose status chunk is damaged are neither done nor pending: their status is lost.
  const std::int64_t unknown = check.samples - check.done - Count(check.pending);
  out << fmt::format("Samples: {} on disk, {} done, {} pending{}\n", check.samples, check.done, Count(check.pending),
                     unknown > 0 ? fmt::format(", {} of unknown status", unknown) : std::string());
  if (check.recompute.empty()) {
    out << "A --resume computes nothing\n";
  } else {
    out << fmt::format("A --resume computes {} samples: {}\n", Count(check.recompute), FormatRanges(check.recompute));
  }
  if (!check.intact()) {
    out << "Verdict: damaged. ringtol report refuses the file; --resume rewrites the damaged chunks and computes "
           "their samples again\n";
  } else if (!check.checksummed()) {
    out << "Verdict: every chunk reads, but datasets without a checksum (written by an earlier ringtol) cannot show "
           "damage\n";
  } else {
    out << "Verdict: intact (every chunk matches its checksum)\n";
  }
}

// An allocation file: its damaged chunks by dataset and candidate, and what is done.
int VerifyAllocation(const VerifyCommand& command, std::ostream& out) {
  const ResultsCheck check = CheckAllocationResults(command.results);
  const std::string verdict = Verdict(check);
  // A damaged range as (candidate, samples) where the dataset has a row per candidate.
  struct Damage {
    const DatasetCheck* dataset;
    std::int64_t candidate;  // -1: not a [C, N] dataset
    SampleRange samples;
  };
  std::vector<Damage> damaged;
  std::vector<std::string> unchecked;
  for (const DatasetCheck& dataset : check.datasets) {
    if (!dataset.checksummed) unchecked.push_back(dataset.path);
    for (const SampleRange& rows : dataset.damaged) {
      damaged.push_back(dataset.per_sample ? Damage{&dataset, check.CandidateOf(rows), check.SamplesOf(rows)}
                                           : Damage{&dataset, -1, rows});
    }
  }
  if (command.json) {
    nlohmann::json list = nlohmann::json::array();
    for (const Damage& d : damaged) {
      list.push_back({{"path", d.dataset->path},
                      {"candidate", d.candidate},
                      {"samples", {d.samples.begin, d.samples.end - 1}},
                      {"problem", d.dataset->first_problem}});
    }
    const nlohmann::json result = {{"file", command.results.string()}, {"kind", "allocation"},
                                   {"verdict", verdict},              {"candidates", check.candidates},
                                   {"samples", check.samples},        {"done_screen", check.done_screen},
                                   {"done_confirm", check.done_confirm}, {"unchecked_datasets", unchecked},
                                   {"damaged", list}};
    out << result.dump(1) << "\n";
  } else {
    out << fmt::format("{}: allocation of {} candidates x {} samples, {} datasets\n", command.results.string(),
                       check.candidates, check.samples, check.datasets.size());
    for (const Damage& d : damaged) {
      out << fmt::format("  {}  DAMAGED{} ({})\n", d.dataset->path,
                         d.candidate >= 0 ? fmt::format(" at candidate {}, samples {}", d.candidate,
                                                        FormatRanges({d.samples}))
                                          : std::string(),
                         d.dataset->first_problem);
    }
    for (const std::string& path : unchecked) out << "  " << path << "  no checksum\n";
    out << fmt::format("Samples done: {} screened, {} confirmed\n", check.done_screen, check.done_confirm);
    out << "Verdict: " << verdict
        << (check.intact() ? "" : "; --resume computes the samples of damaged chunks again and rewrites /outcome")
        << "\n";
  }
  return ExitStatus(check);
}

}  // namespace

int RunVerify(const VerifyCommand& command, std::ostream& out) {
  if (ReadResultsKind(command.results) == ResultsKind::kAllocation) return VerifyAllocation(command, out);
  const ResultsCheck check = CheckResults(command.results);
  if (command.json) {
    PrintJson(command, check, out);
  } else {
    PrintTable(command, check, out);
  }
  return ExitStatus(check);
}

}  // namespace ringtol::jobs
