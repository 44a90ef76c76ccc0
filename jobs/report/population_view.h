// The report's view of a campaign's measured populations ([population.ring],
// [population.rollers]): what the parts are, one by one and per harmonic order, beside what
// the class they were made or bought to would have drawn instead.
//
// The class is the table's `class` (jobs/inputs/sampling_file.h, PopulationSettings), else
// the tightest class of the catalogue that every part meets at the parts' diameter, else,
// where none holds them all, the loosest there. A part is judged on the form measure the
// sampler calibrates that class's spectrum to: a ring's RONt against the class's
// circularity, a roller's two-point variation against its VDsp (sampling/spectrum.h). Size
// and a roller's eccentricity are shown, not judged.
//
// The class's column is drawn, not computed: an AssemblySampler over the campaign's base
// scene with that one tolerance draws options.class_parts parts with a fixed seed, and each
// order's drawn amplitudes (the sampler's recorded inputs) give its median and 95th
// percentile. So the comparison is with what a campaign of that class would draw, inspection
// redraws and all.
//
// Failure: never throws for a plan ReadSamplingFile accepted; a class that cannot be drawn
// (no class has a row at the diameter, or the sampler refuses it) leaves the class's numbers
// out and says why in class_problem.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "jobs/inputs/sampling_file.h"
#include "sampling/assembly_sampler.h"
#include "sampling/spectrum.h"

namespace ringtol::jobs {

struct PopulationViewOptions {
  // Parts drawn from the class (a roller population's draws count every roller of an
  // assembly): the 95th percentile's rank is then known to about 0.3 points.
  std::int64_t class_parts = 4096;
  std::uint64_t seed = 1;  // of the class's draws, fixed so that a report reads the same each time
};

struct MeasuredPartView {
  std::string name;  // its export's file name
  // [µm] Its size as the population draws it: a ring's mean radius, a roller's mean diameter
  // (ΔDmp), about nominal; none where reference = "own_mean" takes the form alone.
  std::optional<double> size_deviation_um;
  double roundness_um = 0.0;  // [µm] RONt of its fitted form
  double form_um = 0.0;       // [µm] the measure the class limits: RONt (ring), two-point variation (roller)
  bool within_class = false;  // form_um <= the class's limit
  std::vector<double> amplitudes_um;  // [µm] per entry of PopulationView::orders; 0 where its fit has none
};

struct OrderComparison {
  int order = 0;
  double measured_median_um = 0.0;  // of the parts' amplitudes at this order
  double measured_max_um = 0.0;
  // Of the class's drawn amplitudes; none where the class draws nothing at this order (a
  // ring's order 1, an order beyond its spectrum's cutoff) or nothing could be drawn.
  std::optional<double> class_median_um, class_q95_um;
};

struct PopulationView {
  bool ring = true;  // the ring's population, else the rollers'
  sampling::PopulationDraw draw = sampling::PopulationDraw::kResample;
  std::string class_name;     // empty when no class could be compared with
  bool class_chosen = false;  // picked by the report, not named by the file
  sampling::ToleranceMode mode = sampling::ToleranceMode::kProcess;
  sampling::FormMeasure measure = sampling::FormMeasure::kRoundness;
  double class_limit_um = 0.0;        // [µm] the class's tolerance on `measure` at the parts' diameter
  double diameter_mm = 0.0;           // where the class was looked up
  std::int64_t class_parts_drawn = 0;  // 0 when the class was not drawn
  std::optional<std::string> class_problem;  // why the class's numbers are missing
  std::vector<MeasuredPartView> parts;        // in the population's order
  std::vector<OrderComparison> orders;        // the population's: 2..orders, or 1..orders with its eccentricity
};

// The views of `plan`'s populations, the ring's first; empty without one.
std::vector<PopulationView> ViewPopulations(const SamplingPlan& plan, const PopulationViewOptions& options = {});

// How many of the view's parts lie within its class.
std::int64_t PartsWithinClass(const PopulationView& view);

// The view as ReportJson writes it ("populations" entries; docs/usage.md, "Reports").
nlohmann::json PopulationJson(const PopulationView& view);

}  // namespace ringtol::jobs
