// `ringtol bench ladder`: speed against accuracy of every rung and setting of the solver
// ladder on the article's order and amplitude studies (docs/model.md §6.1-2).
//
// The reference for every case is the dynamic rung's full model (friction, spring roller
// with mass) integrated at a relative tolerance of 1e-10: D_trajectory over the first
// revolution after the article's 0.5 s settle, the article's own quantity. A method's
// error is the largest |D - D_reference| over the cases it ran, so the time-free rungs
// carry their model error (no start transient, no creep lag) as well as their numerical
// one; for them the numerical error alone, against a quasistatic solve with the same
// contact law at 20 times the steps, is reported beside it. Time is wall time per simulated revolution:
// the median over repeats of one case, then the median over cases. A method that fails
// on a case records the count and the first reason; that case is left out of its error.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "engine/scene.h"
#include "solvers/solver.h"

namespace ringtol::jobs {

struct LadderOptions {
  std::string cases = "all";         // "orders", "amplitudes" or "all"
  int repeats = 3;                   // >= 1 timing repetitions per method and case (explicit methods: 1)
  bool explicit_full_model = false;  // add RK4 on the full model at 65 ns, order-2 case only (~3 min)
  int max_cases = 0;                 // > 0 keeps the first cases only (tests); 0 keeps all
  bool skip_slow = false;            // (tests) leave out the explicit runs that take seconds
};

struct LadderRow {
  std::string method;
  solvers::Rung rung = solvers::Rung::kQuasistatic;
  int cases_run = 0;
  int cases_failed = 0;
  std::string first_failure;         // "<case>: <status>: <message>"
  double time = 0.0;                 // [s] median wall time per revolution
  double error = 0.0;                // [m] max |D - D_reference| over the cases that ran
  double numerical_error = -1.0;     // [m] time-free rungs: against quasistatic at 20x steps; < 0 for dynamic rows
};

struct LadderResult {
  std::vector<LadderRow> rows;
  int cases = 0;
  double reference_time = 0.0;       // [s] median wall time of the reference runs
  int fastest_within = -1;           // index of the fastest row with error <= 1 um, or -1
};

// The studies on `scene`'s error-free assembly (its ring replaced by one harmonic per
// case, 45 deg). Throws InputError for an unknown `cases`, repeats < 1, or a reference
// run that fails. Progress lines go to *progress when it is non-null.
LadderResult RunLadder(const engine::Scene& scene, const LadderOptions& options, std::ostream* progress);

// One row per method: method,rung,cases_run,cases_failed,time_ms,error_um,
// numerical_error_um,first_failure.
void WriteLadderCsv(std::ostream& out, const LadderResult& result);

// A self-contained log-log scatter chart: error in D_trajectory [um] against wall time per
// revolution [ms], one marker per method coloured by rung, a dashed line at 1 um, and the
// fastest method within 1 um ringed, drawn like the report's charts (jobs/report/svg_chart.h).
// Errors below 1e-3 um are drawn at 1e-3 um.
void WriteLadderSvg(std::ostream& out, const LadderResult& result);

// The rows as an aligned table, for the terminal.
void PrintLadder(std::ostream& out, const LadderResult& result);

}  // namespace ringtol::jobs
