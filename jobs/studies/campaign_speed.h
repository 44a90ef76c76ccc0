// `ringtol bench campaign`: speed against accuracy of the solver's modes on a campaign's
// own samples (docs/performance.md).
//
// Every mode computes every sample of the campaign's design, with its sampler, on all
// cores of this process; only the [solver] settings differ. The reference
// is the quasistatic rung at full resolution: the exact step rule (every undulation of
// the path sampled 32 times, no sampling budget) and its default 1 pm Newton tolerance.
// A mode's error in an output is the largest |value - reference| over the samples that
// both computed (a maximum, not a mean), and its statuses are compared sample by sample.
// Throughput is samples per second of wall time, realisation and inspection included,
// the way a campaign spends it; the solve time is the median over samples of one
// sample's wall time.
#pragma once

#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "jobs/campaign/campaign_file.h"
#include "jobs/campaign/sample_record.h"
#include "solvers/simulation.h"

namespace ringtol::jobs {

struct CampaignMode {
  std::string name;                // e.g. "linear", "quasistatic"
  solvers::SolverSettings solver;  // the [solver] settings this mode runs with
};

// The file's own [solver] settings first (what `ringtol campaign` runs), then the other
// linear, quasistatic and auto rungs at the file's sampling budget, on the dense grid and
// then on refined angles (SimulationOptions::angles). The first mode takes the name of the
// rung and angles it runs ("auto" for the default campaign), or "campaign" for a rung not
// listed (dynamic); "quasistatic" (dense) is the unit of the speed ratios. With the life,
// the linear modes and the file's own again reading one revolution only; then the auto rung
// on spectral angles at accuracy fast ("auto, spectral, fast"), and with the life its
// one-revolution row.
std::vector<CampaignMode> DefaultCampaignModes(const solvers::SolverSettings& campaign);

// The reference settings of the comparison: `campaign` with the quasistatic rung, the
// exact step rule (no path_tolerance), no step count forced, every angle (dense), accuracy full.
solvers::SolverSettings FullResolutionReference(const solvers::SolverSettings& campaign);

struct CampaignSpeedOptions {
  int threads = 0;                   // >= 0: 0 is one per core
  std::vector<CampaignMode> modes;   // empty: DefaultCampaignModes
};

struct CampaignModeRow {
  std::string name;
  std::string solver;                // solvers::SolverDescription
  double samples_per_second = 0.0;   // [1/s] of wall time, all threads
  double wall_time = 0.0;            // [s] for all the samples
  double median_solve_time = 0.0;    // [s] one sample's wall time, median
  std::int64_t ok = 0;               // samples whose status is ok
  std::int64_t compared = 0;         // samples ok in this mode and in the reference
  // [um] max |value - reference| over the compared samples, per output; NaN if none compared.
  double max_error_d_trajectory = 0.0;
  double max_error_runout = 0.0;
  double max_error_swing = 0.0;
  double max_error_static_offset = 0.0;
  // [um] the same for life_d_trajectory_mm: the life's closed form on this mode's path
  // against the reference's; NaN for a mode that reads one revolution only.
  double max_error_life_d_trajectory = 0.0;
  std::int64_t status_mismatches = 0;  // samples whose status differs from the reference's
  std::string first_mismatch;          // "sample <i>: <status> against <reference status>"
  double speed_ratio = 0.0;            // samples_per_second over the "quasistatic" row's; 0 if none
};

struct CampaignSpeedResult {
  std::string campaign;                  // the campaign file
  std::int64_t samples = 0;
  int threads = 0;
  CampaignModeRow reference;             // its errors are 0 by construction
  std::vector<CampaignModeRow> rows;     // one per mode, in the order asked
  std::vector<SampleRecord> first_mode_records;  // the first mode's samples, in index order
  double report_time = 0.0;              // [s] `ringtol report` on the first mode's results (set by the caller); 0: not measured
};

// Runs every mode and the reference over the campaign's samples. Throws InputError for
// threads < 0, and the campaign's own refusals (MakeSampling). Progress lines go to
// *progress if non-null.
CampaignSpeedResult RunCampaignSpeed(const CampaignPlan& plan, const CampaignSpeedOptions& options,
                                     std::ostream* progress);

// The rows as an aligned table, with the reference's throughput beneath.
void PrintCampaignSpeed(std::ostream& out, const CampaignSpeedResult& result);

// One row per mode and the reference: mode,solver,samples_per_second,median_solve_ms,
// ok,compared,max_error_d_trajectory_um,max_error_runout_um,max_error_swing_um,
// max_error_static_offset_um,max_error_life_d_trajectory_um,status_mismatches,speed_ratio.
void WriteCampaignSpeedCsv(std::ostream& out, const CampaignSpeedResult& result);

// A self-contained log-log chart: samples per second against the largest per-sample error
// in D_trajectory (filled markers) and in runout (open squares) for each mode, a dashed
// line at 1 um. Errors below 1e-3 um are drawn at 1e-3 um.
void WriteCampaignSpeedSvg(std::ostream& out, const CampaignSpeedResult& result);

}  // namespace ringtol::jobs
