// What a campaign's results file says, for a designer: the distribution of every output
// with confidence intervals, capability and yield against each spec limit and within all
// of them at once, how the estimates converged and how many samples a stated precision
// needs, which tolerances and harmonic orders drive the variance (Sobol' indices from a
// Saltelli design, or a cheaper screening for other designs), and the orbits of the worst
// and the median sample by D_trajectory (centre path, enclosing circle, static
// equilibrium, sensor signal), replayed from their stored design points. Where the file
// holds the life columns (docs/model.md §9), also how much of the life's D_trajectory and
// runout one revolution misses, what the error motion over the life is, and the ISO 230-7
// polar plot of the sample with the largest total error motion, replayed over several
// revolutions (jobs/report/error_motion_plot.h). Where the campaign draws measured parts,
// also what they are beside the class they were made to (jobs/report/population_view.h).
// `ringtol report` writes it as one self-contained HTML page (jobs/report/report_html.h) and
// as JSON (ReportJson).
//
// The numbers come from analysis/ (order statistics, distributions, sensitivities); this
// layer reads the HDF5 file, picks the samples each statistic may use, and names things.
//
// Samples used: the independent draws (all samples, except for a Saltelli design, where
// the A and B matrices are; its AB matrices feed the Sobol' indices). Failed samples are
// counted by reason and listed, and excluded from every statistic; the yield is also given
// counting them as outside the spec. Pending samples (an unfinished campaign) are counted
// and left out.
//
// Failure: InputError for a results file that does not open (CampaignReader) or whose
// stored campaign no longer reads in this ringtol (Campaign's stored constructor); a file
// with no ok sample still gives a report that says so.
//
// Memory: per-sample columns are read whole, one output at a time: about 70 bytes a
// sample at the peak (statuses, redraws, the output being described and D_trajectory, the
// used samples' indices, their values and the sorted copy the distribution makes). The
// screening adds a fixed share for at most screening_samples samples (analysis::ScreenInputs:
// about 170 MB at the default 16,384 and 157 inputs). Peak resident size measured with
// `/usr/bin/time -v`: 42 MB at 2,048 samples, 198 MB at 65,536; so about 270 MB at 10^6.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/distribution.h"
#include "analysis/order_statistics.h"
#include "analysis/sensitivity.h"
#include "sampling/assembly_sampler.h"
#include "jobs/report/campaign_summary.h"
#include "jobs/report/error_motion_plot.h"
#include "jobs/report/population_view.h"
#include "jobs/store/campaign_store.h"
#include "solvers/simulation.h"

namespace ringtol::jobs {

struct ReportOptions {
  double confidence = 0.95;  // of every interval
  analysis::SobolEstimator estimator = analysis::SobolEstimator::kSaltelliJansen;
  int bootstrap_resamples = 1000;  // Sobol' indices; the screening uses a fifth of it
  // Stated precisions for "samples needed": the 99 % quantile's interval half-width as a
  // fraction of its value, and the yield's half-width as a fraction (0.01 = 1 point).
  double quantile_precision = 0.01;
  double yield_precision = 0.005;
  // Screening (non-Saltelli designs) reads the drawn values of at most this many samples,
  // the first in design order: 8 bytes x inputs each.
  std::int64_t screening_samples = 16384;
  bool replay = true;  // replay the worst and the median sample to draw their orbits
  // Revolutions the sample with the largest total error motion is replayed over for its
  // polar plot (with `replay`, where the file has error_motion_total_mm), >= 1. Sixteen
  // show the band the rollers' drifting phases spread the motion into, at sixteen times a
  // replayed orbit's cost; the stored value may reach further (it is over the life).
  int error_motion_revolutions = 16;
  // The harmonic-order chart shows the fewest orders that together carry this share of
  // what all orders carry, plus any other carrying at least `order_chart_single`
  // (OrdersCarryingVariance); the rest are summed into one bar. Both in [0, 1].
  double order_chart_cumulative = 0.99;
  double order_chart_single = 0.005;
};

// Probability of the quantile whose convergence and precision the report follows.
inline constexpr double kReportQuantile = 0.99;

struct FailedSample {
  std::int64_t index = 0;
  std::string status;
  std::string message;
};

struct OutputReport {
  std::string name;  // kOutputNames
  std::optional<double> upper_spec_limit;
  std::int64_t count = 0;                                                     // ok samples used
  std::optional<analysis::DistributionSummary> distribution;                  // none without an ok sample
  std::optional<analysis::ProportionEstimate> within_spec_counting_failures;  // failed = outside
  std::vector<analysis::ConvergencePoint> convergence;
  std::optional<std::int64_t> samples_for_quantile;  // independent samples for quantile_precision
  std::optional<std::int64_t> samples_for_yield;     // ... for yield_precision
};

// One Sobol' or screening entry: a design group, an input, or a sum over them.
struct SensitivityEntry {
  std::string name;
  std::string source;                               // ring_shape, roller_shape, roller_position, spring; "" when mixed
  int order = 0;                                    // harmonic order, 0 when none or mixed
  analysis::SobolIndex first_order;                 // Sobol' S1, or the given-data first-order estimate
  std::optional<analysis::SobolIndex> total_order;  // Sobol' ST (Saltelli designs only)
  double src = 0.0, srrc = 0.0;                     // screening only (sums of squares for sums)
  // What entries are ranked by: ST (Sobol'), the first-order estimate (a screened input),
  // or the sum of SRC^2 (a screened group: the share of variance its inputs explain in the
  // linear fit; a sum of first-order estimates grows with the number of inputs summed).
  double ranking = 0.0;
};

// How an aggregated entry relates to the index of the whole category.
enum class Aggregation {
  kExact,   // the design froze exactly this category together
  kBounds,  // a sum over smaller groups: S1 sum <= the category's S1, ST sum >= its ST
};

struct SensitivityLevel {
  std::string level;  // "design", "source", "order"
  Aggregation aggregation = Aggregation::kExact;
  std::vector<SensitivityEntry> entries;  // largest first
};

struct OutputSensitivity {
  std::string output;
  std::string method;  // "sobol" (Saltelli design) or "screening"
  std::string estimator;
  std::int64_t rows = 0, rows_excluded = 0;  // Saltelli rows (or screening samples) used / with a failed sample
  std::int64_t rows_pending = 0;             // Saltelli rows not finished yet (left out)
  double variance = 0.0;
  std::optional<double> r2, rank_r2;               // screening: of the linear and rank regressions
  std::optional<std::int64_t> rows_for_precision;  // for the widest ST conf to reach 0.05
  std::optional<double> ab_correlation;  // Saltelli only: analysis::SobolIndices::ab_correlation
  std::vector<SensitivityLevel> levels;
};

// Points of a replayed curve that the report keeps and draws (svg::DecimateCurve: every
// extreme, and the path's points on its enclosing circle, kept).
inline constexpr std::size_t kDrawnPoints = 2000;

// One sample replayed from its stored design point (/inputs/u) with the campaign's solver
// settings, to draw its orbit. Positions are in the scene's frame [µm]; the curves are
// kept as drawn (at most kDrawnPoints points each, decimated from `steps` + 1).
struct ReplayedTrajectory {
  std::string label;  // "worst" (largest value of `by`) or "median" (nearest its median)
  // The output the sample is worst or median by: each output the spec constrains, else
  // d_trajectory_mm; and its stored value [in the output's unit].
  std::string by = "d_trajectory_mm";
  double stored_by = 0.0;
  std::int64_t index = 0;
  double stored_d_trajectory_mm = 0.0;
  double d_trajectory_mm = 0.0;  // as replayed now
  double tolerance_mm = 0.0;     // ReplayTolerance of the campaign's solver settings
  // The replay's status is ok and its D_trajectory within tolerance_mm of the stored one:
  // the orbit below is the stored sample's. Otherwise nothing below is drawn.
  bool reproduced = false;
  std::string status;   // the replay's status ("exception" when realising or solving threw)
  std::string message;  // why, when status is not ok
  int steps = 0;        // angles per revolution
  std::vector<double> x_um, y_um;                                       // ring centre over one revolution
  double circle_x_um = 0.0, circle_y_um = 0.0, circle_radius_um = 0.0;  // minimum enclosing circle
  double static_x_um = 0.0, static_y_um = 0.0;                          // static equilibrium before rotation
  // The sensor over the same revolution: ring angle psi [deg] and the reading's excess
  // over its minimum [µm], so the total indicator reading (TIR = max - min) is the
  // largest value; where the reading is greatest and least.
  std::vector<double> angle_deg, sensor_um;
  double tir_um = 0.0;
  double max_angle_deg = 0.0, min_angle_deg = 0.0;
};

struct CampaignReport {
  std::filesystem::path results;
  CampaignIdentity identity;
  std::string schema_note;  // SchemaNote: what an older file's columns are; empty for the current
  std::string design;
  int rollers = 0;  // Z, for "orders that are multiples of the roller count"
  std::int64_t samples = 0, used = 0, done = 0, ok = 0, pending = 0;
  std::int64_t redrawn = 0;  // used samples with inspection redraws
  // Campaign samples per independent draw: (groups + 2) / 2 for a Saltelli design, whose
  // rows hold two draws (A and B); 1 otherwise. Scales "samples needed" to campaign size.
  double samples_per_draw = 1.0;
  std::map<std::string, std::int64_t> failures;  // status name -> count, among used
  std::vector<FailedSample> failed;              // the first few, with their messages
  // Used, done samples each rung settled (CampaignSummary::settled_by); empty for files of
  // schema < 3.
  std::vector<std::int64_t> settled_by;
  std::optional<ContactOpenings> openings;       // how often rollers left the bore; none before schema 6
  std::int64_t life_missing = 0;                 // used ok samples without life values (CountNotFinite)
  std::vector<OutputReport> outputs;             // kOutputNames order
  std::string primary_output;                    // the first spec'd output, else d_trajectory_mm
  // The fraction within every spec limit at once, of the used ok samples, and of the used
  // done samples with the failed ones counted as outside; none without a spec. Each
  // limit's own is its output's (OutputReport).
  std::optional<analysis::ProportionEstimate> within_every_limit, within_every_limit_counting_failures;
  // The verdict on the measured part, when the campaign file has a [disposition].
  std::optional<Disposition> disposition;
  std::vector<OutputSensitivity> sensitivities;  // one per output
  // Per output ranked by (ReplayedTrajectory::by), in kOutputNames order: the worst, then
  // the median (if another sample).
  std::vector<ReplayedTrajectory> trajectories;
  std::optional<std::string> replay_problem;      // why trajectories are missing
  // Over the stage's life, where the file holds the life columns (none otherwise):
  std::vector<LifeGap> life_gaps;  // kLifeColumns order
  std::optional<LifeErrorMotion> life_error_motion;  // the error motion columns' q50 and q99
  // The sample with the largest error_motion_total_mm among the used ok ones, replayed
  // over options.error_motion_revolutions; or why it is not (error_motion_problem). Both
  // empty for a file without the column.
  std::optional<ErrorMotionPlot> error_motion;
  std::optional<std::string> error_motion_problem;
  // The measured populations the campaign drew from, beside their classes; empty without one.
  std::vector<PopulationView> populations;
  ReportOptions options;
};

CampaignReport BuildReport(const std::filesystem::path& results, const ReportOptions& options = {});

// How far a replayed D_trajectory may lie from the stored one [m] and still be the same
// run: four times the solver's position tolerance. Each converged run's centres lie within
// that tolerance of the exact ones, so two runs' within twice it, and the enclosing
// circle's diameter moves by at most twice its farthest point. The position tolerance is
// the quasistatic rung's as MakeSolver sets it (1 % of path_tolerance, else 1 pm), the
// same 1 pm for the linear rung (a closed form: round-off only), and the dynamic rung's
// absolute position tolerance (1e-11 m at relative_tolerance 1e-8, proportional to it:
// solvers/dynamic.h). A replay on the build that ran the campaign reproduces the bits.
double ReplayTolerance(const solvers::SolverSettings& settings);

// The harmonic orders the order chart shows, given what each carries (`ranking`: ST, or
// a sum of SRC^2; a negative estimate counts as 0): the fewest, largest first, whose sum
// reaches `cumulative` of the sum over all, plus every other that carries at least
// `single` of that sum. Indices into `ranking`, ascending; all of them when nothing is
// carried (a zero sum).
std::vector<std::size_t> OrdersCarryingVariance(std::span<const double> ranking, double cumulative, double single);

// The sum of index estimates over parts: values added, half-widths in quadrature (as if
// their bootstrap errors were independent; they are not quite, so it is a guide, not an
// interval). A sum of total indices is capped at 1, which no total index exceeds.
analysis::SobolIndex SumOfIndices(std::span<const analysis::SobolIndex> parts, bool total);

// Everything the HTML shows, keyed in the SALib / OpenTURNS vocabulary (S1, S1_conf, ST,
// ST_conf); docs/usage.md ("Reports") documents the keys.
nlohmann::json ReportJson(const CampaignReport& report);

// The pieces of the report the allocation report (jobs/report/allocation_report.h) also
// builds and writes, for one output whose samples the caller picked.

// The distribution of one output from its ok values (any order, the caller's choice of
// independent draws; none: count 0 and no distribution), against an upper spec limit if
// any: quantiles at `probabilities` (each in (0, 1)) with intervals at options.confidence,
// the convergence of the kReportQuantile quantile over the values' order, samples needed
// for the stated precisions (the quantile's only when kReportQuantile is among
// `probabilities`), and the yield also counting `failed` samples as outside the spec.
OutputReport DescribeOutput(std::string name, std::optional<double> upper_spec_limit, std::span<const double> ok_values,
                            std::int64_t failed, std::span<const double> probabilities, const ReportOptions& options);

// The screening of one output (method "screening"): y_used[i] is the output of sample i
// and x_used its d inputs (row-major [n, d]); levels "input", then "source" and "order"
// where the inputs fall into more than one category. Throws as analysis::ScreenInputs.
OutputSensitivity ScreenOutput(const std::string& output, std::span<const double> y_used,
                               std::span<const double> x_used, int d,
                               const std::vector<sampling::SampledInput>& inputs, const ReportOptions& options);
// ScreenOutput of several outputs of the same samples (ys_used[o] is output outputs[o]), in
// one analysis::ScreenInputs call that shares the work the inputs alone decide.
std::vector<OutputSensitivity> ScreenOutputs(std::span<const std::string> outputs,
                                             std::span<const std::span<const double>> ys_used,
                                             std::span<const double> x_used, int d,
                                             const std::vector<sampling::SampledInput>& inputs,
                                             const ReportOptions& options);

// JSON as ReportJson writes it: a non-finite number as null, an interval as [lower,
// upper], estimates with their intervals, one output's distribution ("outputs" entries,
// campaign samples scaled by samples_per_draw) and one output's sensitivities
// ("sensitivity" entries).
nlohmann::json JsonNumber(double value);
nlohmann::json Json(const analysis::Interval& interval);
nlohmann::json Json(const analysis::QuantileEstimate& quantile);
nlohmann::json Json(const analysis::ProportionEstimate& proportion);
nlohmann::json OutputJson(const OutputReport& out, double samples_per_draw);
nlohmann::json SensitivityJson(const OutputSensitivity& sensitivity);

}  // namespace ringtol::jobs
