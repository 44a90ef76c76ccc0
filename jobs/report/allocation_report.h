// What a tolerance allocation found, for a designer: the recommended tolerance classes
// first (their cost against the current design and against the loosest, the margin each
// constraint keeps, the next two alternatives), the cheaper candidates still undecided and
// the samples that would decide them, or that no candidate is feasible and which
// constraints bind; the Pareto front of cost against yield with feasible, infeasible and
// undecided candidates told apart and the recommendation marked; a table of the front;
// for the recommendation, the distribution of every constrained output against its limit
// and which component's tolerance still dominates its variance; what the search simulated
// and what common random numbers saved; how the numbers were made. `ringtol report` writes
// it as one self-contained HTML page (AllocationReportHtml, the campaign page's style
// sheet and charts: jobs/report/html_parts.h, svg_chart.h) and as JSON
// (AllocationReportJson) with the same numbers.
//
// Two entry points: MakeAllocationReport from plain data (what the results file holds,
// read by the caller: the allocation's identity and outcome, the recommendation's samples
// and their design points), and ReadAllocationReport, which reads them from an allocation
// results file (jobs/store/allocation_store.h) and calls it.
//
// The verdicts, intervals and yields of candidates are the outcome's as the allocation
// judged them (analysis::JudgeConstraint at identity.confidence); the report only
// recomputes the recommendation's distributions (at the same confidence) and its
// sensitivities from its samples.
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "jobs/allocation/allocation_outcome.h"
#include "jobs/report/campaign_report.h"

namespace ringtol::jobs {

struct AllocationReportOptions {
  // Bootstrap resamples of the sensitivity screening's error bars: it uses a fifth of
  // them, as the campaign report's screening does; 0: no error bars.
  int bootstrap_resamples = 1000;
  // The screening reads at most this many of the recommendation's samples, the first in
  // design order (8 bytes x inputs each), >= 1.
  std::int64_t screening_samples = 16384;
};

// What the report is made of: the results file's contents, as plain data.
struct AllocationReportInput {
  std::filesystem::path results;  // where they were read from (shown; may be empty)
  AllocationIdentity identity;
  AllocationOutcome outcome;
  // The recommendation's samples 0 .. n - 1 (n = its CandidateOutcome::samples) from the
  // role that settled it (the confirming rung): per output a constraint names, by column
  // name, n values in the output's unit, NaN where the sample failed. Empty without a
  // recommendation.
  std::map<std::string, std::vector<double>> recommendation_samples;
  // The same samples' design points u, row-major [n, d] with d = identity.inputs.size()
  // (common to every candidate); empty: no sensitivities.
  std::vector<double> design_points;
};

// A candidate as the report names it.
struct CandidateReport {
  std::int64_t index = 0;
  // Per component (identity.components), its option's class with its mode (ClassWithMode,
  // jobs/report/allocation_summary.h): "6 (inspected)".
  std::vector<std::string> classes;
  // cost / the loosest candidate's (candidate 0); NaN when that costs nothing.
  double relative_to_loosest = std::numeric_limits<double>::quiet_NaN();
  CandidateOutcome outcome;
  // Per constraint (empty unless simulated): how far the far end of the interval stays
  // within the limit, negative beyond it, in AllocationReport::margin_units: for a quantile
  // constraint upper - interval.upper (an output in mm: in µm), for a yield constraint
  // interval.lower - level (in percentage points).
  std::vector<double> margins;
  // The most samples_to_decide over its undecided constraints: about how many samples
  // would decide it; -1 when one sits on its limit (none would); 0 when decided.
  std::int64_t samples_to_decide = 0;
};

// The recommendation's view of one constrained output.
struct RecommendedOutput {
  // Its distribution over the recommendation's ok samples, against the tightest upper
  // limit its constraints set; quantiles at 50, 90, 99, 99.9 % and every quantile
  // constraint's level.
  OutputReport distribution;
  // A screening of the recommendation's samples on their design points, grouped by error
  // source (ring shape, roller shape, roller position, spring: one allocated component
  // each): which component still dominates. None without design points, without spread,
  // or with too few ok samples (fewer than the inputs + 2).
  std::optional<OutputSensitivity> sensitivity;
  std::string sensitivity_problem;  // why there is none, when there is none
};

struct AllocationReport {
  std::filesystem::path results;
  AllocationIdentity identity;
  AllocationReportOptions options;
  std::vector<std::string> margin_units;  // per constraint: "µm", an output's unit, or "points"
  // Every candidate, by index.
  std::vector<CandidateReport> candidates;
  // Simulated candidates by ascending cost (ties: index).
  std::vector<std::int64_t> simulated;
  // As the outcome: the recommendation, its alternatives, the undecided cheaper
  // candidates, the Pareto front (ascending cost), the binding constraints.
  std::optional<std::int64_t> recommendation;
  std::vector<std::int64_t> alternatives, undecided_cheaper, front;
  std::vector<int> binding;
  // The tightest candidate (the last) when the search ran to its end and no candidate is
  // feasible: its intervals show how far the binding constraints miss.
  std::optional<std::int64_t> tightest;
  std::vector<RecommendedOutput> recommended_outputs;  // one per constrained output, in constraint order
  // What the search did.
  bool complete = false;
  std::int64_t implied = 0, costlier = 0, not_visited = 0;
  std::int64_t simulated_count = 0, settled_by_screen = 0, samples_screen = 0, samples_confirm = 0;
  double common_random_numbers_gain = std::numeric_limits<double>::quiet_NaN();
};

// The report of plain data. Throws std::invalid_argument for an outcome that does not
// match its identity (candidate count, options per candidate, constraints per candidate,
// indices out of range) or design points of a size other than n d.
AllocationReport MakeAllocationReport(const AllocationReportInput& input, const AllocationReportOptions& options = {});

// The report of an allocation results file: AllocationReader's identity, outcome, the
// recommendation's samples of the confirming role and their design points. InputError
// as AllocationReader for a file that does not open or is not an allocation's.
AllocationReport ReadAllocationReport(const std::filesystem::path& results,
                                      const AllocationReportOptions& options = {});

// Everything the page shows, with the campaign report's keys where the quantities are the
// same (OutputJson, SensitivityJson).
nlohmann::json AllocationReportJson(const AllocationReport& report);

// The page: self-contained (no scripts, no network, no files beside it), printable.
std::string AllocationReportHtml(const AllocationReport& report);

}  // namespace ringtol::jobs
