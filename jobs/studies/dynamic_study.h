// `ringtol bench dynamics`: where the quasi-static answer stops being the answer. For one
// scene (its ring errors replaced by one harmonic per order studied, docs/model.md §6.1) it
// measures, with the dynamic rung's full model at its default tolerance:
//   - the start: D_trajectory quasi-statically; over the first and a later steady
//     revolution from the default start (at rest at the quasistatic equilibrium); and,
//     from the article's start (centred, settling under the preload), over the first
//     revolution after the scene's settle, the first after a long settle and the steady
//     one. The differences split the article's excess over the quasi-static value into
//     "the ring had not settled" and "the step in speed";
//   - speed: the steady-revolution D_trajectory against the quasi-static one at several
//     steady speeds, and per order the speed above which they differ by more than 1 um.
// Every run that fails keeps its status in the table ("-" and a footnote), never a number.
#pragma once

#include <numbers>
#include <ostream>
#include <string>
#include <vector>

#include "engine/scene.h"
#include "engine/units.h"

namespace ringtol::jobs {

struct DynamicStudyOptions {
  std::vector<int> orders = {2, 3, 4, 5, 6, 7, 8, 9, 10, 12, 15, 17, 20};
  double amplitude = 0.14e-3;         // [m] of each order's ring harmonic
  double phase = 45.0 * units::kRadiansPerDegree;      // [rad] the article's phase
  double long_settle = 5.0;           // [s] ten creep time constants (c_max / k ~ 0.5 s)
  std::vector<double> rates = {1.0 * units::kRadiansPerDegree,  3.0 * units::kRadiansPerDegree,  10.0 * units::kRadiansPerDegree,
                               30.0 * units::kRadiansPerDegree, 90.0 * units::kRadiansPerDegree, 270.0 * units::kRadiansPerDegree};  // [rad/s]
  double agreement = 1e-6;            // [m] "within 1 um"
};

// D_trajectory per run [m], NaN when the run failed.
struct TransientRow {
  int order = 0;
  double quasistatic = 0.0;
  // From the default start (solvers::DynamicStart::kQuasistaticEquilibrium), the scene's law.
  double first = 0.0;               // first revolution
  double steady = 0.0;              // a later revolution (the solver's steady_revolution)
  // From the article's start (solvers::DynamicStart::kArticleSettle).
  double first_article_settle = 0.0;   // first revolution after the scene's settle
  double first_long_settle = 0.0;      // first revolution after options.long_settle
  double steady_article_settle = 0.0;  // the later revolution after the scene's settle
};

struct SpeedRow {
  int order = 0;
  std::vector<double> gap;   // [m] |D_steady - D_quasistatic| per rate, NaN when a run failed
  double threshold = 0.0;    // [rad/s] lowest rate with gap > agreement, log-interpolated; +inf if none
};

struct DynamicStudy {
  double rate = 0.0;    // [rad/s] the scene's own steady rate (transient table)
  double settle = 0.0;  // [s] the scene's own settle
  std::vector<TransientRow> transient;
  std::vector<double> rates;  // [rad/s]
  std::vector<SpeedRow> speed;
  std::vector<std::string> failures;  // "order n, <run>: <status>: <message>"
};

// The scene's motion law must be the article's kind: at rest, then one steady rate (any
// settle >= 0); throws InputError otherwise, or for an empty list of orders or rates.
DynamicStudy RunDynamicStudy(const engine::Scene& scene, const DynamicStudyOptions& options, std::ostream* progress);

void PrintDynamicStudy(std::ostream& out, const DynamicStudy& study);

// The start table as a chart (jobs/report/svg_chart.h): D_trajectory [mm] against ring
// order, quasistatic, the first and steady revolutions from the default start, the first
// after the article's settle, with the article's reported range 0.29-0.63 mm as a band.
void WriteDynamicStudySvg(std::ostream& out, const DynamicStudy& study);

}  // namespace ringtol::jobs
