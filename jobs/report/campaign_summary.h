// What a campaign's results say, read back from its results file: how many samples, which
// failed and why, the distribution of every output (quantiles with distribution-free
// confidence intervals) and the fraction within the spec limits.
//
// Statistics use the samples that are independent draws: all of them, except for a
// Saltelli design, where only the A and B matrices are (the AB matrices re-use their
// coordinates). The intervals assume independent samples; a randomised Sobol' net is
// better balanced than that, so for it they err on the wide side.
//
// Within spec: a sample whose status is ok and every output with a limit is <= it. A
// failed sample counts as outside (the assembly could not be simulated, e.g. it rattles):
// `in_spec` is over every done sample; `in_spec_ok` only over the ok ones.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/order_statistics.h"
#include "jobs/store/campaign_store.h"

namespace ringtol::jobs {

struct OutputSummary {
  std::string name;
  std::int64_t count = 0;  // ok samples
  double mean = 0.0, standard_deviation = 0.0, min = 0.0, max = 0.0;
  std::vector<analysis::QuantileEstimate> quantiles;  // 50, 90, 99, 99.9 %
  std::optional<double> upper_spec_limit;
};

struct CampaignSummary {
  std::int64_t samples = 0;  // of the campaign
  std::int64_t used = 0;     // independent draws among them (see above)
  std::int64_t done = 0;     // used samples on disk
  std::int64_t ok = 0;
  std::map<std::string, std::int64_t> failures;  // status name -> count, among used
  std::vector<OutputSummary> outputs;
  std::optional<analysis::ProportionEstimate> in_spec;     // over done samples; none without a spec
  std::optional<analysis::ProportionEstimate> in_spec_ok;  // over ok samples
  double confidence = 0.95;
  // Samples each rung settled (solvers::Rung numbers 0..2: linear, quasistatic, dynamic),
  // among the used, done samples a rung ran on; empty for files of schema < 3.
  std::vector<std::int64_t> settled_by;
  // What an older results file's columns are, in its schema's terms; empty for the current.
  std::string schema_note;
};

inline constexpr double kSummaryProbabilities[] = {0.5, 0.9, 0.99, 0.999};

// What an older results file's columns are, in its schema's terms; empty for the current.
std::string SchemaNote(const CampaignReader& results);

// Samples each rung settled (CampaignSummary::settled_by) among the samples `used` whose
// status is done, from /outputs/rung; empty for files of schema < 3.
std::vector<std::int64_t> CountRungs(const CampaignReader& results, const std::vector<SampleStatus>& status,
                                     const std::vector<bool>& used);
// "linear 93.2 %, quasistatic 6.8 %, dynamic 0.0 %" of the samples a rung ran on; empty
// when no rung ran.
std::string RungShares(const std::vector<std::int64_t>& settled_by);
std::int64_t RungsRan(const std::vector<std::int64_t>& settled_by);
// {"linear": {"samples": n, "share": s}, ...}; null when no rung ran.
nlohmann::json RungsJson(const std::vector<std::int64_t>& settled_by);

// `independent(index)` says whether a sample is an independent draw (empty: all are).
CampaignSummary Summarise(const CampaignReader& results, const std::function<bool(std::int64_t)>& independent,
                          double confidence = 0.95);

// Text for the terminal, and the same as JSON. What a run of the pool cost is the
// campaign command's to add (jobs/cli/campaign_command.cpp): a summary is also made of
// files no run of this process wrote.
void PrintSummary(std::ostream& out, const CampaignSummary& summary);
nlohmann::json SummaryJson(const CampaignSummary& summary);

}  // namespace ringtol::jobs
