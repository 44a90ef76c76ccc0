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
// `in_spec` is over every done sample; `in_spec_ok` only over the ok ones. Each limit's
// own yield is given too (`in_spec_by_limit`, over every done sample), so that a spec of
// several limits shows which one costs the yield.
//
// Over the stage's life (docs/model.md §9): where a file holds an output's life column
// beside its one-revolution one, how much of the life's value one revolution misses
// (LifeGap), stated next to the headline; and what the axis's error motion over the life
// is (LifeErrorMotion). Older files have no life columns and say nothing.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/allocation.h"
#include "analysis/order_statistics.h"
#include "jobs/campaign/campaign_file.h"
#include "jobs/campaign/sample_record.h"
#include "jobs/store/campaign_store.h"

namespace ringtol::jobs {

struct OutputSummary {
  std::string name;
  std::int64_t count = 0;  // ok samples
  double mean = 0.0, standard_deviation = 0.0, min = 0.0, max = 0.0;
  std::vector<analysis::QuantileEstimate> quantiles;  // 50, 90, 99, 99.9 %
  std::optional<double> upper_spec_limit;
};

// An output read over one revolution and over the stage's life, compared on the same ok
// samples [mm].
struct LifeGap {
  std::string label;  // "D_trajectory", "runout"
  std::int64_t count = 0;  // ok samples with both values finite
  double one_q50 = 0.0, one_q99 = 0.0;    // quantiles of the one-revolution values
  double life_q50 = 0.0, life_q99 = 0.0;  // ... of the life values
  // The median over the samples of life / one - 1: how far a typical sample's own life
  // value lies above its one-revolution value (NaN when no sample has one > 0).
  double median_excess = 0.0;
};

// The outputs that have a life column: one-revolution column, life column, label.
struct LifeColumns {
  const char* one_revolution;
  const char* life;
  const char* label;
};
// Which life output is which revolution output's over the life is not a property of one
// row of the outputs table, so it is listed here; the table holds each to its span.
inline constexpr LifeColumns kLifeColumns[] = {{"d_trajectory_mm", "life_d_trajectory_mm", "D_trajectory"},
                                               {"runout_mm", "life_runout_mm", "runout"}};
static_assert([] {
  for (const LifeColumns& c : kLifeColumns) {
    const std::size_t one = OutputIndex(c.one_revolution), life = OutputIndex(c.life);
    if (one == kOutputCount || life == kOutputCount || kOutputs[one].span != OutputSpan::kRevolution ||
        kOutputs[life].span != OutputSpan::kLife)
      return false;
  }
  return true;
}(), "each pair is a revolution output of the outputs table and a life output");

// Whether `name` is one of kLifeColumns' columns.
bool IsLifeColumn(std::string_view name);
// The gap of every kLifeColumns pair whose two columns `ok_values` holds (by output name:
// the same ok samples in the same order in each).
std::vector<LifeGap> LifeGaps(const std::map<std::string, std::vector<double>, std::less<>>& ok_values);
// The gap from paired values (one[i] and life[i] of the same ok sample; a pair with a
// non-finite value is skipped); none without a finite pair.
std::optional<LifeGap> CompareLife(std::string label, std::span<const double> one, std::span<const double> life);
// "Over the stage's life, D_trajectory q99 is 0.2735 mm against 0.2555 mm over one
// revolution (+7.0 %) and q50 ...; the median sample's life value lies 3.4 % above its own
// one-revolution value." Plain text.
std::string LifeGapSentence(const LifeGap& gap);
// {"count", "one_revolution_mm": {"q50", "q99"}, "life_mm": {...}, "median_excess"}.
nlohmann::json LifeGapJson(const LifeGap& gap);

// The axis's radial error motion over the stage's life, ISO 230-7's three values read from
// their columns over the same ok samples. There is no one-revolution value to set beside
// them, as LifeGap does for D_trajectory and runout: what one revolution shows is not an
// error motion at all, since its asynchronous part needs several revolutions, the
// synchronous one their average, and what a single revolution's indicator reads (runout)
// holds the bore's own form as well as the axis's motion.
struct LifeErrorMotion {
  std::int64_t count = 0;  // ok samples with a finite total
  // [mm] q50 and q99 of each value, in kErrorMotionValues order (jobs/report/report_text.h);
  // NaN for a column the file lacks.
  std::array<double, 3> q50{}, q99{};
};

// How many of the ok samples' `values` of a life column are not finite: the samples without
// life values, because a roller left the bore and the life reads the linear rung's phasors,
// which assume every contact closed (solvers::SimulationResult::life_missing).
std::int64_t CountNotFinite(std::span<const double> values);
// "12 of 512 ok samples have no life values: a roller left the bore, ...; the life's
// numbers are over the other 500." Plain text.
std::string LifeMissingSentence(std::int64_t missing, std::int64_t ok);

// What the summary and the report say of a campaign that left the life out
// (CampaignIdentity::life false), in place of its numbers: "The life outputs
// (life_d_trajectory_mm, ...) were not computed: ...", every life output of the outputs
// table named.
std::string LifeNotComputed();

// Whether `name` is an error motion column (ErrorMotionOf, jobs/report/report_text.h).
bool IsErrorMotionColumn(std::string_view name);
// The error motion over the life of the columns `ok_values` holds (by output name, the
// same ok samples in each); none without a finite total.
std::optional<LifeErrorMotion> LifeErrorMotionOf(
    const std::map<std::string, std::vector<double>, std::less<>>& ok_values);
// "Over the stage's life, the axis's radial error motion (ISO 230-7, ...) is at q99 168.6 µm
// total, ... (q50 ...). No one-revolution value compares: ...". Plain text; `filter` is the
// campaign's (CampaignIdentity::error_motion_filter).
std::string LifeErrorMotionSentence(const LifeErrorMotion& motion, const engine::ErrorMotionFilter& filter);
// {"count", "reading", "filter_cutoff_upr", "revolutions", "total_mm": {"q50", "q99"},
// "synchronous_mm": ..., "asynchronous_mm": ...}.
nlohmann::json LifeErrorMotionJson(const LifeErrorMotion& motion, const engine::ErrorMotionFilter& filter);
// The "life" object of the summary's and the report's JSON: {"computed": false} for a
// campaign that left the life out; else {"computed": true, "samples_without_life":
// `missing` (CountNotFinite), <label>: LifeGapJson, ..., "error_motion":
// LifeErrorMotionJson}; null when there is nothing to say (a file of a schema before the
// life outputs, or without ok samples).
nlohmann::json LifeJson(bool computed, const std::vector<LifeGap>& gaps, const std::optional<LifeErrorMotion>& motion,
                        const engine::ErrorMotionFilter& filter, std::int64_t missing);

// How often rollers left the bore (docs/model.md §7, "Contacts that open"): over the used
// ok samples, from /outputs/off_bore_percent. On more fixed rollers than the ring needs,
// openings are the support's normal state, not a failure; they rock the ring between
// subsets of rollers, which is itself a source of runout.
struct RollerOpenings {
  std::string roller;               // CampaignIdentity::rollers
  std::int64_t samples = 0;         // ok samples on which it left the bore at some angle
  double median_percent = 0.0;      // [%] of the turn, the median over those samples; NaN when none
  double max_percent = 0.0;         // [%] of the turn, the largest
};
struct ContactOpenings {
  std::int64_t ok = 0;  // used ok samples
  // Of them, those with a roller off the bore at some angle, with its confidence interval.
  analysis::ProportionEstimate any;
  std::vector<RollerOpenings> rollers;  // every roller, in the scene's order
};
// None for a file that does not record openings (schema < 6) or has no used ok sample.
// `status` and `used` cover the file's first samples, as CountRungs's.
std::optional<ContactOpenings> CountOpenings(const CampaignReader& results, const std::vector<SampleStatus>& status,
                                             const std::vector<bool>& used, double confidence);
// "every roller touched the bore throughout, in all 512 ok samples", or "37 of 512 ok
// samples (7.2 % [5.1, 9.9 %]) had a roller off the bore for part of the turn: fixed_a in
// 30 (median 12.1 %, at most 33.9 % of the turn), ...". Plain text.
std::string OpeningsSentence(const ContactOpenings& openings);
// {"samples_ok", "samples_with_opening", "share": {"value", "lower", "upper"}, "rollers":
// {<name>: {"samples", "median_percent_of_turn", "max_percent_of_turn"}, ...}}.
nlohmann::json OpeningsJson(const ContactOpenings& openings);

// One spec limit's own yield.
struct LimitYield {
  std::string output;  // kOutputNames
  double limit = 0.0;  // upper, in the output's unit
  analysis::ProportionEstimate within;
};

// The verdict on a measured part (CampaignPlan::disposition, docs/usage.md "Disposition of a
// measured part"): the share of the done samples within every spec limit, failures outside
// as in CampaignSummary::in_spec, judged against the required yield at the rule's confidence
// (analysis::JudgeYield).
struct Disposition {
  DispositionRule rule;
  analysis::ConstraintJudgement judgement;  // kFeasible: pass; kInfeasible: fail; kUndecided
};
// From the done samples within every limit and the done samples (CampaignSummary::in_spec's
// successes and trials); none without a done sample.
std::optional<Disposition> Dispose(const DispositionRule& rule, std::int64_t within, std::int64_t done);
// "pass", "fail", "undecided".
std::string_view DispositionVerdictName(const Disposition& disposition);
// What `ringtol campaign` exits with, so that an inspection script can gate on it: 0 pass,
// 3 fail, 4 undecided (1 and 2 are errors).
int DispositionExitCode(const Disposition& disposition);
inline constexpr int kDispositionFailExitCode = 3;
inline constexpr int kDispositionUndecidedExitCode = 4;
// "pass: 99.71 % [99.32, 99.91 %] of 2048 assemblies are within every spec limit, at least
// the 99 % required at 95 % confidence", with, when undecided, about how many samples would
// decide it. Plain text.
std::string DispositionSentence(const Disposition& disposition);
// {"verdict", "required_yield", "confidence", "yield": {"value", "lower", "upper",
// "successes", "trials"}, "samples_to_decide"}.
nlohmann::json DispositionJson(const Disposition& disposition);

struct CampaignSummary {
  std::int64_t samples = 0;  // of the campaign
  std::int64_t used = 0;     // independent draws among them (see above)
  std::int64_t done = 0;     // used samples on disk
  std::int64_t ok = 0;
  std::map<std::string, std::int64_t> failures;  // status name -> count, among used
  std::vector<OutputSummary> outputs;
  std::optional<analysis::ProportionEstimate> in_spec;     // over done samples; none without a spec
  std::optional<analysis::ProportionEstimate> in_spec_ok;  // over ok samples
  std::vector<LimitYield> in_spec_by_limit;                // over done samples, kOutputNames order
  double confidence = 0.95;
  // Samples each rung settled (solvers::Rung numbers 0..2: linear, quasistatic, dynamic),
  // among the used, done samples a rung ran on; empty for files of schema < 3.
  std::vector<std::int64_t> settled_by;
  std::vector<std::int64_t> failed_by;  // of settled_by, those whose status is not ok
  // Whether `auto` chose the rungs: it sends a sample to the dynamic rung for one reason,
  // which the summary states (docs/model.md §7, "The auto rung").
  bool auto_rung = false;
  // What an older results file's columns are, in its schema's terms; empty for the current.
  std::string schema_note;
  bool life = true;  // CampaignIdentity::life: whether the samples computed the life outputs
  std::int64_t life_missing = 0;  // used ok samples without life values (CountNotFinite)
  std::vector<LifeGap> life_gaps;  // kLifeColumns order, those the file holds both columns of
  std::optional<LifeErrorMotion> life_error_motion;  // none for a file without the columns
  engine::ErrorMotionFilter error_motion_filter;     // the campaign's, which the error_motion_* outputs passed
  std::optional<ContactOpenings> openings;           // none for files of schema < 6
  // The verdict on the measured part, when the campaign file has a [disposition] (set by
  // whoever holds the campaign: Dispose on in_spec).
  std::optional<Disposition> disposition;
};

inline constexpr double kSummaryProbabilities[] = {0.5, 0.9, 0.99, 0.999};
// The confidence of the summary's intervals unless a [disposition] states its own.
inline constexpr double kSummaryConfidence = 0.95;

// What an older results file's columns are, in its schema's terms; empty for the current.
std::string SchemaNote(const CampaignReader& results);

// Samples each rung settled (CampaignSummary::settled_by) among the samples `used` whose
// status is done, from /outputs/rung; empty for files of schema < 3. `status` and `used`
// cover the first samples of the file, those its rungs are read for. `failed_by`, when
// given, receives the same counts of those whose status is not ok.
std::vector<std::int64_t> CountRungs(const CampaignReader& results, const std::vector<SampleStatus>& status,
                                     const std::vector<bool>& used, std::vector<std::int64_t>* failed_by = nullptr);
// "linear 93.2 %, quasistatic 6.8 %, dynamic 0.0 %" of the samples a rung ran on; empty
// when no rung ran.
std::string RungShares(const std::vector<std::int64_t>& settled_by);
std::int64_t RungsRan(const std::vector<std::int64_t>& settled_by);
// {"linear": {"samples": n, "share": s}, ...}; null when no rung ran.
nlohmann::json RungsJson(const std::vector<std::int64_t>& settled_by);

// `independent(index)` says whether a sample is an independent draw (empty: all are).
CampaignSummary Summarise(const CampaignReader& results, const std::function<bool(std::int64_t)>& independent,
                          double confidence = kSummaryConfidence);

// Text for the terminal, and the same as JSON. What a run of the pool cost is the
// campaign command's to add (jobs/cli/campaign_command.cpp): a summary is also made of
// files no run of this process wrote.
void PrintSummary(std::ostream& out, const CampaignSummary& summary);
nlohmann::json SummaryJson(const CampaignSummary& summary);

}  // namespace ringtol::jobs
