#include "jobs/report/population_view.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "analysis/order_statistics.h"
#include "engine/units.h"
#include "sampling/design.h"

namespace ringtol::jobs {
namespace {

constexpr double um = units::kMicrometresPerMetre;
constexpr double kClassQuantile = 0.95;

sampling::ErrorSource PartSource(bool ring) {
  return ring ? sampling::ErrorSource::kRingShape : sampling::ErrorSource::kRollerShape;
}

struct ClassLimit {
  std::string name;
  double limit = 0.0;  // [m] on the population's form measure
};

// The class's limit on the population's form measure at the parts' diameter, looked up as
// [tolerances.ring] or [tolerances.rollers] would look it up; none where the class has no
// row there.
std::optional<double> LimitOf(const SamplingPlan& plan, bool ring, const std::string& name) {
  sampling::AssemblyTolerances tolerances;
  try {
    tolerances = ToleranceOfClass(plan, PartSource(ring), name, sampling::ToleranceMode::kProcess);
  } catch (const std::invalid_argument&) {
    return std::nullopt;
  }
  if (ring) return tolerances.ring->circularity;
  for (const std::optional<sampling::RollerShapeTolerance>& roller : tolerances.roller_shapes) {
    if (roller) return roller->vdsp;
  }
  return std::nullopt;
}

// Every class with a form limit at the parts' diameter, tightest first (catalogue order
// among equals).
std::vector<ClassLimit> ClassesAtDiameter(const SamplingPlan& plan, bool ring) {
  std::vector<std::string> names;
  if (ring) {
    for (const auto& c : plan.catalogue.ring_classes) names.push_back(c.name);
  } else {
    for (const auto& c : plan.catalogue.roller_classes) names.push_back(c.name);
  }
  std::vector<ClassLimit> classes;
  for (const std::string& name : names) {
    if (const std::optional<double> limit = LimitOf(plan, ring, name); limit && *limit > 0.0) {
      classes.push_back({name, *limit});
    }
  }
  std::stable_sort(classes.begin(), classes.end(),
                   [](const ClassLimit& a, const ClassLimit& b) { return a.limit < b.limit; });
  return classes;
}

// What a class draws: per order, the amplitudes [µm] of the parts drawn.
struct ClassDraws {
  std::map<int, std::vector<double>> amplitudes_um;
  std::int64_t parts = 0;
};

// At least options.class_parts parts drawn with `tolerances`, every roller of an assembly a
// part; their amplitudes are the sampler's recorded amplitude inputs.
ClassDraws DrawClass(const SamplingPlan& plan, const sampling::AssemblyTolerances& tolerances,
                     const PopulationViewOptions& options) {
  sampling::AssemblySamplerOptions sampler_options;
  sampler_options.seed = options.seed;
  const sampling::AssemblySampler sampler(plan.scene, tolerances, sampler_options);
  ClassDraws draws;
  if (sampler.dimension() == 0) return draws;  // a class that draws no form and no eccentricity
  sampling::DesignOptions design_options;
  design_options.kind = sampling::DesignKind::kMonteCarlo;
  design_options.seed = options.seed;
  sampling::Design design(sampler.dimension(), design_options);
  const std::vector<sampling::SampledInput>& inputs = sampler.inputs();
  constexpr std::string_view kAmplitude = ".amplitude_um";
  std::vector<std::size_t> amplitudes;
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    if (inputs[k].order > 0 && inputs[k].name.ends_with(kAmplitude)) amplitudes.push_back(k);
  }
  std::int64_t per_assembly = tolerances.ring ? 1 : 0;
  for (const auto& roller : tolerances.roller_shapes) per_assembly += roller ? 1 : 0;
  for (std::int64_t index = 0; draws.parts < options.class_parts && per_assembly > 0; ++index) {
    const sampling::SampledAssembly assembly = sampler.Sample(design, index);
    for (const std::size_t k : amplitudes) draws.amplitudes_um[inputs[k].order].push_back(assembly.values[k]);
    draws.parts += per_assembly;
  }
  return draws;
}

MeasuredPartView ViewPart(const sampling::MeasuredPart& part, const PopulationSettings& settings, bool ring,
                          const std::vector<int>& orders) {
  MeasuredPartView view;
  view.name = part.name;
  // A roller's size is stated as its class states it, a mean diameter deviation.
  if (settings.sized) view.size_deviation_um = (ring ? 1.0 : 2.0) * part.mean_deviation * um;
  view.roundness_um = sampling::MeasureForm(sampling::FormMeasure::kRoundness, part.harmonics) * um;
  view.form_um = ring ? view.roundness_um
                      : sampling::MeasureForm(sampling::FormMeasure::kTwoPointVariation, part.harmonics) * um;
  for (const int order : orders) {
    double amplitude = 0.0;
    for (const engine::Harmonic& h : part.harmonics) {
      if (h.order == order) amplitude += h.amplitude;
    }
    view.amplitudes_um.push_back(amplitude * um);
  }
  return view;
}

PopulationView ViewPopulation(const SamplingPlan& plan, bool ring, const sampling::PartPopulation& population,
                              const PopulationSettings& settings, const PopulationViewOptions& options) {
  PopulationView view;
  view.ring = ring;
  view.draw = population.draw;
  view.mode = settings.mode;
  view.measure = ring ? sampling::FormMeasure::kRoundness : sampling::FormMeasure::kTwoPointVariation;
  // A batch's parts share the size of the rollers it fills, which the reader checked.
  const double radius = ring ? plan.scene.ring.inner.radius()
                             : plan.scene.rollers[sampling::BatchRollers(plan.tolerances, plan.scene.rollers.size()).front()]
                                   .outline.radius();
  view.diameter_mm = 2.0 * radius * units::kMillimetresPerMetre;
  std::vector<int> orders;
  for (int n = settings.keep_eccentricity ? 1 : 2; n <= settings.orders; ++n) orders.push_back(n);
  double largest_um = 0.0;
  for (const sampling::MeasuredPart& part : population.parts) {
    view.parts.push_back(ViewPart(part, settings, ring, orders));
    largest_um = std::max(largest_um, view.parts.back().form_um);
  }

  if (settings.class_name) {
    view.class_name = *settings.class_name;
    view.class_limit_um = LimitOf(plan, ring, view.class_name).value_or(0.0) * um;
  } else if (const std::vector<ClassLimit> classes = ClassesAtDiameter(plan, ring); !classes.empty()) {
    const auto holding = std::find_if(classes.begin(), classes.end(),
                                      [&](const ClassLimit& c) { return c.limit * um >= largest_um; });
    const ClassLimit& chosen = holding != classes.end() ? *holding : classes.back();
    view.class_name = chosen.name;
    view.class_limit_um = chosen.limit * um;
    view.class_chosen = true;
  } else {
    view.class_problem = "no class of the catalogue has a row at this diameter";
  }
  for (MeasuredPartView& part : view.parts) {
    part.within_class = !view.class_name.empty() && part.form_um <= view.class_limit_um;
  }

  ClassDraws drawn;
  if (!view.class_name.empty()) {
    try {
      drawn = DrawClass(plan, ToleranceOfClass(plan, PartSource(ring), view.class_name, settings.mode), options);
    } catch (const std::exception& e) {
      view.class_problem = std::string("the class cannot be drawn: ") + e.what();
    }
  }
  view.class_parts_drawn = drawn.parts;
  for (std::size_t k = 0; k < orders.size(); ++k) {
    OrderComparison& order = view.orders.emplace_back();
    order.order = orders[k];
    std::vector<double> measured;
    for (const MeasuredPartView& part : view.parts) measured.push_back(part.amplitudes_um[k]);
    order.measured_max_um = *std::max_element(measured.begin(), measured.end());
    order.measured_median_um = analysis::Median(std::move(measured));
    const auto found = drawn.amplitudes_um.find(orders[k]);
    if (found == drawn.amplitudes_um.end() || found->second.empty()) continue;
    std::vector<double>& values = found->second;
    std::sort(values.begin(), values.end());
    order.class_median_um = analysis::Median(values);
    order.class_q95_um = analysis::EstimateQuantile(values, kClassQuantile).value;
  }
  return view;
}

nlohmann::json Optional(const std::optional<double>& value) {
  return value && std::isfinite(*value) ? nlohmann::json(*value) : nlohmann::json(nullptr);
}

nlohmann::json Optional(const std::optional<std::string>& text) {
  return text ? nlohmann::json(*text) : nlohmann::json(nullptr);
}

}  // namespace

std::vector<PopulationView> ViewPopulations(const SamplingPlan& plan, const PopulationViewOptions& options) {
  std::vector<PopulationView> views;
  if (plan.tolerances.ring_population && plan.ring_population) {
    views.push_back(ViewPopulation(plan, true, *plan.tolerances.ring_population, *plan.ring_population, options));
  }
  if (plan.tolerances.roller_population && plan.roller_population && !plan.scene.rollers.empty()) {
    views.push_back(ViewPopulation(plan, false, *plan.tolerances.roller_population, *plan.roller_population, options));
  }
  return views;
}

std::int64_t PartsWithinClass(const PopulationView& view) {
  return std::count_if(view.parts.begin(), view.parts.end(), [](const MeasuredPartView& p) { return p.within_class; });
}

nlohmann::json PopulationJson(const PopulationView& view) {
  nlohmann::json parts = nlohmann::json::array();
  for (const MeasuredPartView& p : view.parts) {
    parts.push_back({{"name", p.name},
                     {"size_deviation_um", Optional(p.size_deviation_um)},
                     {"roundness_um", p.roundness_um},
                     {"form_um", p.form_um},
                     {"within_class", p.within_class},
                     {"amplitudes_um", p.amplitudes_um}});
  }
  nlohmann::json orders = nlohmann::json::array();
  for (const OrderComparison& o : view.orders) {
    orders.push_back({{"order", o.order},
                      {"measured_median_um", o.measured_median_um},
                      {"measured_max_um", o.measured_max_um},
                      {"class_median_um", Optional(o.class_median_um)},
                      {"class_q95_um", Optional(o.class_q95_um)}});
  }
  const std::optional<std::string> name =
      view.class_name.empty() ? std::nullopt : std::optional<std::string>(view.class_name);
  nlohmann::json comparison = {{"name", Optional(name)},
                               {"chosen", view.class_chosen},
                               {"mode", NameOf(sampling::kToleranceModeNames, view.mode)},
                               {"measure", sampling::FormMeasureName(view.measure)},
                               {"limit_um", view.class_limit_um},
                               {"diameter_mm", view.diameter_mm},
                               {"parts_within", PartsWithinClass(view)},
                               {"parts_drawn", view.class_parts_drawn},
                               {"problem", Optional(view.class_problem)}};
  return {{"part", view.ring ? "ring" : "rollers"},
          {"draw", NameOf(sampling::kPopulationDrawNames, view.draw)},
          {"size_deviation_of", view.ring ? "radius" : "mean diameter"},
          {"class", std::move(comparison)},
          {"parts", std::move(parts)},
          {"orders", std::move(orders)}};
}

}  // namespace ringtol::jobs
