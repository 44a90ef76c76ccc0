#include "sampling/assembly_sampler.h"

#include <algorithm>
#include <boost/math/special_functions/erf.hpp>
#include <cmath>
#include <map>
#include <mutex>
#include <numeric>
#include <numbers>
#include <stdexcept>
#include <string>

#include "sampling/random.h"
#include "engine/units.h"

namespace ringtol::sampling {
namespace {

constexpr double kMaxFormCp = 1.33;

// Inverse CDFs of the unit coordinates.
double Rayleigh(double sigma, double u) { return sigma * std::sqrt(-2.0 * std::log(u)); }
double UniformPhase(double v) { return units::kRadiansPerRevolution * v - std::numbers::pi; }
double StandardNormal(double u) { return std::numbers::sqrt2 * boost::math::erf_inv(2.0 * u - 1.0); }

// Rayleigh scale sigma with P(R <= limit) = p: 1 - exp(-limit^2 / (2 sigma^2)) = p.
double RayleighScaleFor(double limit, double p) { return limit / std::sqrt(-2.0 * std::log1p(-p)); }

void CheckTolerance(double value, const std::string& what, bool zero_allowed) {
  if (!std::isfinite(value) || value < 0.0 || (!zero_allowed && value == 0.0))
    throw std::invalid_argument(what + " = " + std::to_string(value) + ": allowed: " + (zero_allowed ? ">= 0" : "> 0") +
                                " and finite");
}

void CheckCapability(const Capability& c, const std::string& what, bool form) {
  const double max = form ? kMaxFormCp : 1e3;
  if (!(c.cp > 0.0 && c.cp <= max))
    throw std::invalid_argument(what + " capability Cp = " + std::to_string(c.cp) + ": allowed: > 0 and <= " +
                                (form ? "1.33 (the calibration of form spectra "
                                        "resolves coverages up to 99.993 %)"
                                      : std::string("1000")));
}

}  // namespace

double Capability::Coverage() const { return std::erf(3.0 * cp / std::numbers::sqrt2); }

namespace {

// Drawn errors add to the base scene's: harmonics of equal order add, as do mean deviations.
void AddToProfile(engine::PolarProfile& profile, const std::vector<engine::Harmonic>& added, double mean) {
  if (added.empty() && mean == 0.0) return;
  std::vector<engine::Harmonic> all = profile.harmonics();
  all.insert(all.end(), added.begin(), added.end());
  profile = engine::PolarProfile(profile.radius(), profile.mean_deviation() + mean, std::move(all));
}

}  // namespace

std::size_t TakePart(std::vector<std::size_t>& left, double u) {
  const auto at = std::min(left.size() - 1, static_cast<std::size_t>(u * static_cast<double>(left.size())));
  const std::size_t part = left[at];
  left.erase(left.begin() + static_cast<std::ptrdiff_t>(at));
  return part;
}

std::vector<std::size_t> BatchRollers(const AssemblyTolerances& tolerances, std::size_t rollers) {
  if (!tolerances.batch_rollers.empty()) return tolerances.batch_rollers;
  std::vector<std::size_t> all(rollers);
  std::iota(all.begin(), all.end(), std::size_t{0});
  return all;
}

engine::Scene WithRollerParts(const engine::Scene& base, const PartPopulation& batch,
                              std::span<const std::size_t> rollers, std::span<const std::size_t> parts) {
  if (parts.size() != rollers.size()) {
    throw std::invalid_argument("WithRollerParts: " + std::to_string(parts.size()) + " parts for " +
                                std::to_string(rollers.size()) + " rollers");
  }
  engine::Scene scene = base;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    if (parts[k] >= batch.parts.size() || rollers[k] >= base.rollers.size()) {
      throw std::invalid_argument("WithRollerParts: part " + std::to_string(parts[k]) + " of a batch of " +
                                  std::to_string(batch.parts.size()) + " on roller " + std::to_string(rollers[k]) +
                                  " of " + std::to_string(base.rollers.size()));
    }
    const MeasuredPart& part = batch.parts[parts[k]];
    AddToProfile(scene.rollers[rollers[k]].outline, part.harmonics, part.mean_deviation);
  }
  return scene;
}

// One toleranced part of the assembly and the coordinates it draws from.
struct AssemblySampler::Component {
  enum class Kind {
    kRingForm,
    kPart,        // a measured part, resampled (the ring's, or a roller's without replacement)
    kOrderModel,  // one order of a population model, of the ring or a roller
    kSizeModel,   // a population model's size
    kRollerEccentricity,
    kRollerForm,
    kRollerSize,
    kPosition,
    kStiffness,
    kPreload
  };
  explicit Component(Kind k, int r = -1) : kind(k), roller(r) {}
  Kind kind;
  int roller;
  int first = 0;  // first coordinate
  int count = 0;
  bool inspected = false;
  double tolerance = 0.0;           // [m] or [-], what inspection checks
  double sigma = 0.0;               // scale of the draw: Rayleigh or normal sigma, or spectrum scale c
  double mean = 0.0;                // normal draws: centre of the interval
  double lower = 0.0, upper = 0.0;  // size: accepted interval [m]
  SpectrumShape shape;              // form only
  std::vector<double> relative_scales;  // form only: RelativeScales(shape)
  int order = 0;                    // kOrderModel: its order
  double mean_b = 0.0;              // kOrderModel: mean of C sin phi (`mean`: of C cos phi)
  double size_scale = 1.0;          // kSizeModel: recorded value per metre of radius (2: a diameter)
};

// The construction's steps, one per kind of tolerance: each validates its tolerance and
// appends its components with their design coordinates (and, for form spectra, their
// calibration) to the sampler.
class AssemblySampler::Builder {
 public:
  explicit Builder(AssemblySampler& sampler) : sampler_(sampler) {}

  void AddRingForm(const RingFormTolerance& t) {
    CheckTolerance(t.circularity, "ring circularity", false);
    CheckCapability(t.capability, "ring form", true);
    CheckSpectrumShape(t.spectrum);
    if (t.spectrum.min_order < 2)
      throw std::invalid_argument("ring form spectrum starts at order " + std::to_string(t.spectrum.min_order) +
                                  "; allowed: >= 2 (order 1 is the bore's eccentricity, not form)");
    Component c(Component::Kind::kRingForm);
    c.inspected = t.capability.mode == ToleranceMode::kInspected;
    c.tolerance = t.circularity;
    c.shape = t.spectrum;
    Calibrate(c, "ring", FormMeasure::kRoundness, t.capability);
    AddInputs(std::move(c), ErrorSource::kRingShape, "ring", SpectrumInputs(t.spectrum), "ring");
  }

  // The ring's population (roller = -1, prefix "ring") or one roller's share of the rollers'
  // (its index, prefix "roller.<name>"): named as the class's draws of the same part are.
  void AddPopulation(const PartPopulation& population, int roller, const std::string& prefix) {
    const bool ring = roller < 0;
    const std::string component = ring ? prefix : prefix + ".shape";
    const ErrorSource source = ring ? ErrorSource::kRingShape : ErrorSource::kRollerShape;
    const std::size_t m = population.parts.size();
    if (m == 0) throw std::invalid_argument(std::string(ring ? "the ring" : "the rollers'") + " population has no parts");
    if (population.draw == PopulationDraw::kResample) {
      AddInputs(Component(Component::Kind::kPart, roller), source, component, {{"part_index", 0}},
                prefix + ".population");
      return;
    }
    if (m < 2) {
      throw std::invalid_argument(std::string(ring ? "a ring" : "a roller") +
                                  " population model needs at least 2 parts; it has 1");
    }
    // Per order, the parts' coefficients; an order a part lacks is 0 there.
    std::map<int, std::vector<std::pair<double, double>>> coefficients;
    for (std::size_t p = 0; p < m; ++p) {
      for (const engine::Harmonic& h : population.parts[p].harmonics) {
        auto& list = coefficients[h.order];
        list.resize(m, {0.0, 0.0});
        list[p].first += h.amplitude * std::cos(h.phase);
        list[p].second += h.amplitude * std::sin(h.phase);
      }
    }
    const double parts = static_cast<double>(m);
    for (auto& [order, list] : coefficients) {
      list.resize(m, {0.0, 0.0});
      Component c(Component::Kind::kOrderModel, roller);
      c.order = order;
      for (const auto& [a, b] : list) {
        c.mean += a / parts;
        c.mean_b += b / parts;
      }
      double squares = 0.0;
      for (const auto& [a, b] : list) squares += (a - c.mean) * (a - c.mean) + (b - c.mean_b) * (b - c.mean_b);
      // Two coordinates share the variance, each with m - 1 degrees of freedom.
      c.sigma = std::sqrt(squares / (2.0 * (parts - 1.0)));
      AddInputs(std::move(c), source, component, {{"amplitude_um", order}, {"phase_deg", order}}, prefix);
    }
    Component size(Component::Kind::kSizeModel, roller);
    // A roller's size is stated as its class states it, a mean diameter deviation.
    size.size_scale = ring ? 1.0 : 2.0;
    for (const MeasuredPart& part : population.parts) size.mean += part.mean_deviation / parts;
    double squares = 0.0;
    for (const MeasuredPart& part : population.parts) squares += (part.mean_deviation - size.mean) * (part.mean_deviation - size.mean);
    size.sigma = std::sqrt(squares / (parts - 1.0));
    if (size.mean != 0.0 || size.sigma > 0.0) {
      AddInputs(std::move(size), source, component,
                {{ring ? "mean_deviation_um" : "mean_diameter_deviation_um", 0}}, prefix + ".size");
    }
  }

  void AddRollerShape(int index, const std::string& prefix, const RollerShapeTolerance& t) {
    const std::string component = prefix + ".shape";
    CheckTolerance(t.kea, component + " Kea", true);
    CheckTolerance(t.vdsp, component + " VDsp", true);
    if (!(t.mean_diameter_lower <= t.mean_diameter_upper) || !std::isfinite(t.mean_diameter_lower) ||
        !std::isfinite(t.mean_diameter_upper))
      throw std::invalid_argument(component +
                                  " mean diameter deviation interval must be "
                                  "finite with lower <= upper");
    CheckCapability(t.capability, component, t.vdsp > 0.0);
    const bool inspected = t.capability.mode == ToleranceMode::kInspected;
    const double p = t.capability.Coverage();
    if (t.kea > 0.0) {
      Component c(Component::Kind::kRollerEccentricity, index);
      c.inspected = inspected;
      c.tolerance = t.kea;
      c.sigma = RayleighScaleFor(t.kea / 2.0, p);
      AddInputs(std::move(c), ErrorSource::kRollerShape, component, {{"amplitude_um", 1}, {"phase_deg", 1}},
                prefix + ".order1");
    }
    if (t.vdsp > 0.0) {
      CheckSpectrumShape(t.form);
      if (t.form.min_order < 2)
        throw std::invalid_argument(component + " form spectrum starts at order " + std::to_string(t.form.min_order) +
                                    "; allowed: >= 2 (order 1 is the eccentricity Kea sets)");
      Component c(Component::Kind::kRollerForm, index);
      c.inspected = inspected;
      c.tolerance = t.vdsp;
      c.shape = t.form;
      Calibrate(c, component, FormMeasure::kTwoPointVariation, t.capability);
      AddInputs(std::move(c), ErrorSource::kRollerShape, component, SpectrumInputs(t.form), prefix);
    }
    if (t.mean_diameter_upper > t.mean_diameter_lower) {
      Component c(Component::Kind::kRollerSize, index);
      c.inspected = inspected;
      c.lower = t.mean_diameter_lower;
      c.upper = t.mean_diameter_upper;
      c.mean = 0.5 * (c.lower + c.upper);
      c.sigma = (c.upper - c.lower) / (6.0 * t.capability.cp);
      AddInputs(std::move(c), ErrorSource::kRollerShape, component, {{"mean_diameter_deviation_um", 0}},
                prefix + ".size");
    }
  }

  void AddRollerPosition(int index, const std::string& prefix, const PositionTolerance& t) {
    const std::string component = prefix + ".position";
    CheckTolerance(t.zone_diameter, component + " zone diameter", false);
    CheckCapability(t.capability, component, false);
    Component c(Component::Kind::kPosition, index);
    c.inspected = t.capability.mode == ToleranceMode::kInspected;
    c.tolerance = t.zone_diameter / 2.0;
    c.sigma = RayleighScaleFor(c.tolerance, t.capability.Coverage());
    AddInputs(std::move(c), ErrorSource::kRollerPosition, component, {{"offset_um", 0}, {"direction_deg", 0}},
              component);
  }

  void AddSpring(int index, const engine::Roller& roller, const std::string& prefix, const SpringTolerance& t) {
    const std::string component = prefix + ".spring";
    if (roller.mount != engine::RollerMount::kSpring)
      throw std::invalid_argument(component + ": roller '" + roller.name +
                                  "' is fixed; spring tolerances apply to spring rollers only");
    CheckTolerance(t.stiffness, component + " stiffness tolerance", true);
    CheckTolerance(t.preload, component + " preload tolerance", true);
    if (t.preload >= 1.0) throw std::invalid_argument(component + " preload tolerance must be below 100 %");
    CheckCapability(t.capability, component, false);
    const bool inspected = t.capability.mode == ToleranceMode::kInspected;
    for (const auto& [kind, tolerance, name] :
         {std::tuple{Component::Kind::kStiffness, t.stiffness, "stiffness_deviation_percent"},
          std::tuple{Component::Kind::kPreload, t.preload, "preload_deviation_percent"}}) {
      if (tolerance == 0.0) continue;
      Component c(kind, index);
      c.inspected = inspected;
      c.tolerance = tolerance;
      c.sigma = tolerance / (3.0 * t.capability.cp);
      AddInputs(std::move(c), ErrorSource::kSpring, component, {{name, 0}}, component);
    }
  }

 private:
  using NamesAndOrders = std::vector<std::pair<std::string, int>>;

  static NamesAndOrders SpectrumInputs(const SpectrumShape& shape) {
    NamesAndOrders list;
    for (int n = shape.min_order; n <= shape.max_order; ++n) {
      list.emplace_back("amplitude_um", n);
      list.emplace_back("phase_deg", n);
    }
    return list;
  }

  void AddInputs(Component c, ErrorSource source, const std::string& component, const NamesAndOrders& names_and_orders,
                 const std::string& quantity_prefix) {
    std::vector<SampledInput>& inputs = sampler_.inputs_;
    c.first = static_cast<int>(inputs.size());
    c.count = static_cast<int>(names_and_orders.size());
    for (const auto& [name, order] : names_and_orders) {
      std::string quantity = quantity_prefix;
      if (order > 0 && c.kind != Component::Kind::kRollerEccentricity) quantity += ".order" + std::to_string(order);
      inputs.push_back({quantity + "." + name, source, c.roller, order, quantity, component});
    }
    sampler_.components_.push_back(std::move(c));
  }

  void Calibrate(Component& c, const std::string& component, FormMeasure measure, const Capability& cap) {
    std::vector<ComponentScale>& scales = sampler_.scales_;
    const double p = cap.Coverage();
    ComponentScale scale{component, measure, c.tolerance, p, {}};
    for (std::size_t k = 0; k < scales.size(); ++k) {
      const ComponentScale& done = scales[k];
      if (done.measure == measure && done.tolerance == c.tolerance && done.coverage == p &&
          calibrated_shapes_[k] == c.shape)
        scale.calibration = done.calibration;
    }
    for (const ComponentScale& known : sampler_.options_.known_scales) {
      if (scale.calibration.draws == 0 && known.component == component && known.measure == measure &&
          known.tolerance == c.tolerance && known.coverage == p)
        scale.calibration = known.calibration;
    }
    if (scale.calibration.draws == 0) {
      const AssemblySamplerOptions& options = sampler_.options_;
      scale.calibration = options.calibrations
                              ? options.calibrations->Calibrate(c.shape, measure, c.tolerance, p, options.calibration)
                              : CalibrateSpectrum(c.shape, measure, c.tolerance, p, options.calibration);
    }
    c.sigma = scale.calibration.scale;
    c.relative_scales = RelativeScales(c.shape);
    scales.push_back(std::move(scale));
    calibrated_shapes_.push_back(c.shape);
  }

  AssemblySampler& sampler_;
  // Per scale, the shape it was calibrated for. Rollers of one class share a calibration:
  // it depends only on what is compared here.
  std::vector<SpectrumShape> calibrated_shapes_;
};

struct CalibrationCache::Entries {
  struct Entry {
    SpectrumShape shape;
    FormMeasure measure;
    double tolerance;
    double coverage;
    CalibrationOptions options;
    SpectrumCalibration calibration;
  };
  mutable std::mutex mutex;
  std::vector<Entry> entries;
};

CalibrationCache::CalibrationCache() : entries_(std::make_unique<Entries>()) {}
CalibrationCache::~CalibrationCache() = default;

SpectrumCalibration CalibrationCache::Calibrate(const SpectrumShape& shape, FormMeasure measure, double tolerance,
                                                double coverage, const CalibrationOptions& options) {
  auto same = [&](const Entries::Entry& e) {
    return e.shape == shape && e.measure == measure && e.tolerance == tolerance && e.coverage == coverage &&
           e.options.min_draws == options.min_draws && e.options.max_draws == options.max_draws &&
           e.options.seed == options.seed;
  };
  {
    std::lock_guard lock(entries_->mutex);
    for (const Entries::Entry& e : entries_->entries)
      if (same(e)) return e.calibration;
  }
  // Calibrated outside the lock: two threads may both calibrate one class, to the same
  // bits (the calibration is deterministic), rather than one waiting a quarter second.
  const SpectrumCalibration calibration = CalibrateSpectrum(shape, measure, tolerance, coverage, options);
  std::lock_guard lock(entries_->mutex);
  if (std::none_of(entries_->entries.begin(), entries_->entries.end(), same))
    entries_->entries.push_back({shape, measure, tolerance, coverage, options, calibration});
  return calibration;
}

std::size_t CalibrationCache::size() const {
  std::lock_guard lock(entries_->mutex);
  return entries_->entries.size();
}

AssemblySampler::AssemblySampler(engine::Scene base, AssemblyTolerances tolerances, AssemblySamplerOptions options)
    : base_(std::move(base)), tolerances_(std::move(tolerances)), options_(std::move(options)) {
  const std::size_t rollers = base_.rollers.size();
  auto check_size = [&](std::size_t size, const char* what) {
    if (size != 0 && size != rollers)
      throw std::invalid_argument(std::string(what) + " lists " + std::to_string(size) + " rollers; the scene has " +
                                  std::to_string(rollers));
  };
  check_size(tolerances_.roller_shapes.size(), "roller shape tolerances");
  check_size(tolerances_.roller_positions.size(), "roller position tolerances");
  check_size(tolerances_.springs.size(), "spring tolerances");

  Builder builder(*this);
  if (tolerances_.ring && tolerances_.ring_population) {
    throw std::invalid_argument("the ring has a form tolerance and a population: draw it from one");
  }
  std::vector<bool> batch_fills(rollers, false);
  if (tolerances_.roller_population) {
    const std::vector<std::size_t> filled = BatchRollers(tolerances_, rollers);
    for (std::size_t k = 0; k < filled.size(); ++k) {
      if (filled[k] >= rollers || (k > 0 && filled[k] <= filled[k - 1])) {
        throw std::invalid_argument("the rollers' batch fills roller " + std::to_string(filled[k]) +
                                    ": not one of the scene's " + std::to_string(rollers) + " in ascending order");
      }
      if (filled[k] < tolerances_.roller_shapes.size() && tolerances_.roller_shapes[filled[k]]) {
        throw std::invalid_argument("roller " + base_.rollers[filled[k]].name +
                                    " has a shape tolerance and a population: draw it from one");
      }
      batch_fills[filled[k]] = true;
    }
    const PartPopulation& batch = *tolerances_.roller_population;
    if (batch.draw == PopulationDraw::kResample && !batch.parts.empty() && batch.parts.size() < filled.size()) {
      throw std::invalid_argument("the rollers' batch has " + std::to_string(batch.parts.size()) + " parts for " +
                                  std::to_string(filled.size()) + " rollers; resampling takes each part once");
    }
  }
  if (tolerances_.ring) builder.AddRingForm(*tolerances_.ring);
  if (tolerances_.ring_population) builder.AddPopulation(*tolerances_.ring_population, -1, "ring");
  for (std::size_t i = 0; i < rollers; ++i) {
    const engine::Roller& roller = base_.rollers[i];
    const std::string prefix = "roller." + roller.name;
    const int index = static_cast<int>(i);
    if (i < tolerances_.roller_shapes.size() && tolerances_.roller_shapes[i])
      builder.AddRollerShape(index, prefix, *tolerances_.roller_shapes[i]);
    if (batch_fills[i]) builder.AddPopulation(*tolerances_.roller_population, index, prefix);
    if (i < tolerances_.roller_positions.size() && tolerances_.roller_positions[i])
      builder.AddRollerPosition(index, prefix, *tolerances_.roller_positions[i]);
    if (i < tolerances_.springs.size() && tolerances_.springs[i])
      builder.AddSpring(index, roller, prefix, *tolerances_.springs[i]);
  }
}

AssemblySampler::~AssemblySampler() = default;
AssemblySampler::AssemblySampler(const AssemblySampler&) = default;
AssemblySampler::AssemblySampler(AssemblySampler&&) noexcept = default;

InputGroups AssemblySampler::Groups(InputGrouping grouping) const {
  InputGroups groups;
  std::map<std::string, std::size_t> index;
  for (std::size_t k = 0; k < inputs_.size(); ++k) {
    const SampledInput& in = inputs_[k];
    std::string key;
    switch (grouping) {
      case InputGrouping::kCoordinate:
        key = in.name;
        break;
      case InputGrouping::kQuantity:
        key = in.quantity;
        break;
      case InputGrouping::kComponent:
        key = in.component;
        break;
      case InputGrouping::kSource:
        key = ErrorSourceName(in.source);
        break;
      case InputGrouping::kOrder:
        if (in.order > 0)
          key = "order" + std::to_string(in.order);
        else if (in.source == ErrorSource::kRollerShape)
          key = "roller_size";
        else
          key = ErrorSourceName(in.source);
        break;
    }
    auto [it, inserted] = index.try_emplace(key, groups.names.size());
    if (inserted) {
      groups.names.push_back(key);
      groups.coordinates.emplace_back();
    }
    groups.coordinates[it->second].push_back(static_cast<int>(k));
  }
  return groups;
}

SampledAssembly AssemblySampler::Realise(std::int64_t index, std::span<const double> u) const {
  if (static_cast<int>(u.size()) != dimension())
    throw std::invalid_argument("design point has " + std::to_string(u.size()) + " coordinates; the sampler draws " +
                                std::to_string(dimension()));
  SampledAssembly out;
  out.index = index;
  out.u.assign(u.begin(), u.end());
  out.values.assign(u.size(), 0.0);
  out.scene = base_;
  engine::Scene& scene = out.scene;

  std::vector<engine::Harmonic> ring_harmonics;
  double ring_mean = 0.0;
  // The rollers' batch parts not yet taken by an earlier roller of this assembly.
  std::vector<std::size_t> batch_left;
  if (tolerances_.roller_population) {
    batch_left.resize(tolerances_.roller_population->parts.size());
    std::iota(batch_left.begin(), batch_left.end(), std::size_t{0});
  }
  std::vector<std::vector<engine::Harmonic>> roller_harmonics(scene.rollers.size());
  std::vector<double> roller_mean(scene.rollers.size(), 0.0);

  for (const Component& c : components_) {
    std::span<double> w(out.u.data() + c.first, static_cast<std::size_t>(c.count));
    std::span<double> values(out.values.data() + c.first, static_cast<std::size_t>(c.count));
    std::vector<engine::Harmonic> harmonics;
    double drawn = 0.0;  // the scalar drawn, for non-spectrum components
    for (int attempt = 0;; ++attempt) {
      if (attempt > 0) {
        if (attempt >= options_.max_attempts)
          throw std::runtime_error("sample " + std::to_string(index) + ": " +
                                   inputs_[static_cast<std::size_t>(c.first)].component + " failed inspection " +
                                   std::to_string(attempt) + " times");
        ++out.redraws;
        for (int k = 0; k < c.count; ++k)
          w[static_cast<std::size_t>(k)] =
              RandomUnit(options_.seed, RandomStream::kRedraw, static_cast<std::uint64_t>(index),
                         static_cast<std::uint64_t>(c.first + k), static_cast<std::uint64_t>(attempt));
      }
      bool inside = true;
      switch (c.kind) {
        case Component::Kind::kRingForm:
        case Component::Kind::kRollerForm: {
          const std::size_t orders = static_cast<std::size_t>(c.shape.order_count());
          std::vector<double> a(orders), v(orders);
          for (std::size_t k = 0; k < orders; ++k) {
            a[k] = w[2 * k];
            v[k] = w[2 * k + 1];
          }
          harmonics = DrawHarmonics(c.shape, c.relative_scales, c.sigma, a, v);
          const FormMeasure measure =
              c.kind == Component::Kind::kRingForm ? FormMeasure::kRoundness : FormMeasure::kTwoPointVariation;
          if (c.inspected)
            inside = options_.exact_form_inspection ? MeasureForm(measure, harmonics) <= c.tolerance
                                                    : FormWithin(measure, harmonics, c.tolerance);
          break;
        }
        case Component::Kind::kRollerEccentricity:
          harmonics = {{1, Rayleigh(c.sigma, w[0]), UniformPhase(w[1])}};
          inside = 2.0 * harmonics[0].amplitude <= c.tolerance;
          break;
        case Component::Kind::kPart:
        case Component::Kind::kSizeModel:
          break;
        case Component::Kind::kOrderModel: {
          const double a = c.mean + c.sigma * StandardNormal(w[0]);
          const double b = c.mean_b + c.sigma * StandardNormal(w[1]);
          harmonics = {{c.order, std::hypot(a, b), std::atan2(b, a)}};
          break;
        }
        case Component::Kind::kPosition:
          drawn = Rayleigh(c.sigma, w[0]);
          inside = drawn <= c.tolerance;
          break;
        case Component::Kind::kRollerSize:
          drawn = c.mean + c.sigma * StandardNormal(w[0]);
          inside = drawn >= c.lower && drawn <= c.upper;
          break;
        case Component::Kind::kStiffness:
        case Component::Kind::kPreload:
          drawn = c.sigma * StandardNormal(w[0]);
          inside = std::abs(drawn) <= c.tolerance;
          break;
      }
      if (!c.inspected || inside) break;
    }

    const auto r = static_cast<std::size_t>(std::max(c.roller, 0));
    switch (c.kind) {
      case Component::Kind::kRingForm:
      case Component::Kind::kRollerForm:
      case Component::Kind::kRollerEccentricity: {
        for (std::size_t k = 0; k < harmonics.size(); ++k) {
          values[2 * k] = harmonics[k].amplitude * units::kMicrometresPerMetre;
          values[2 * k + 1] = harmonics[k].phase * units::kDegreesPerRadian;
        }
        auto& target = c.kind == Component::Kind::kRingForm ? ring_harmonics : roller_harmonics[r];
        target.insert(target.end(), harmonics.begin(), harmonics.end());
        break;
      }
      case Component::Kind::kRollerSize:
        values[0] = drawn * units::kMicrometresPerMetre;
        roller_mean[r] += drawn / 2.0;  // the profile's mean radius deviation
        break;
      case Component::Kind::kPart: {
        const bool ring = c.roller < 0;
        const std::vector<MeasuredPart>& parts = (ring ? tolerances_.ring_population : tolerances_.roller_population)->parts;
        std::size_t part = 0;
        if (ring) {
          part = std::min(parts.size() - 1, static_cast<std::size_t>(w[0] * static_cast<double>(parts.size())));
        } else {
          part = TakePart(batch_left, w[0]);
        }
        values[0] = static_cast<double>(part);
        auto& target = ring ? ring_harmonics : roller_harmonics[r];
        target.insert(target.end(), parts[part].harmonics.begin(), parts[part].harmonics.end());
        (ring ? ring_mean : roller_mean[r]) += parts[part].mean_deviation;
        break;
      }
      case Component::Kind::kOrderModel:
        values[0] = harmonics[0].amplitude * units::kMicrometresPerMetre;
        values[1] = harmonics[0].phase * units::kDegreesPerRadian;
        (c.roller < 0 ? ring_harmonics : roller_harmonics[r]).push_back(harmonics[0]);
        break;
      case Component::Kind::kSizeModel: {
        const double drawn_size = c.mean + c.sigma * StandardNormal(w[0]);
        values[0] = c.size_scale * drawn_size * units::kMicrometresPerMetre;
        (c.roller < 0 ? ring_mean : roller_mean[r]) += drawn_size;
        break;
      }
      case Component::Kind::kPosition: {
        const double direction = UniformPhase(w[1]);
        values[0] = drawn * units::kMicrometresPerMetre;
        values[1] = direction * units::kDegreesPerRadian;
        scene.rollers[r].radial_offset += drawn * std::cos(direction);
        scene.rollers[r].tangential_offset += drawn * std::sin(direction);
        break;
      }
      case Component::Kind::kStiffness:
        values[0] = 100.0 * drawn;
        scene.rollers[r].spring.stiffness *= 1.0 + drawn;
        break;
      case Component::Kind::kPreload:
        values[0] = 100.0 * drawn;
        scene.rollers[r].spring.preload *= 1.0 + drawn;
        break;
    }
  }

  AddToProfile(scene.ring.inner, ring_harmonics, ring_mean);
  for (std::size_t i = 0; i < scene.rollers.size(); ++i) AddToProfile(scene.rollers[i].outline, roller_harmonics[i], roller_mean[i]);
  return out;
}

SampledAssembly AssemblySampler::Sample(Design& design, std::int64_t index) const {
  if (design.dimension() != dimension())
    throw std::invalid_argument("the design has " + std::to_string(design.dimension()) +
                                " dimensions; the sampler draws " + std::to_string(dimension()));
  std::vector<double> u(static_cast<std::size_t>(dimension()));
  design.Point(index, u);
  return Realise(index, u);
}

engine::FastestHarmonic FastestDrawnHarmonic(const engine::Scene& base, const AssemblyTolerances& tolerances) {
  engine::FastestHarmonic fastest = engine::FindFastestHarmonic(base);
  if (tolerances.ring && tolerances.ring->spectrum.max_order > fastest.rate) {
    fastest = {static_cast<double>(tolerances.ring->spectrum.max_order), -1, tolerances.ring->spectrum.max_order};
  }
  if (tolerances.ring_population) {
    for (const MeasuredPart& part : tolerances.ring_population->parts) {
      for (const engine::Harmonic& h : part.harmonics) {
        if (h.order > fastest.rate) fastest = {static_cast<double>(h.order), -1, h.order};
      }
    }
  }
  if (tolerances.roller_population) {
    const std::vector<std::size_t> filled = BatchRollers(tolerances, base.rollers.size());
    for (const MeasuredPart& part : tolerances.roller_population->parts) {
      for (const engine::Harmonic& h : part.harmonics) {
        for (const std::size_t i : filled) {
          const double rate = h.order * engine::SpinRatio(base, static_cast<int>(i));
          if (rate > fastest.rate) fastest = {rate, static_cast<int>(i), h.order};
        }
      }
    }
  }
  for (std::size_t i = 0; i < tolerances.roller_shapes.size() && i < base.rollers.size(); ++i) {
    const std::optional<RollerShapeTolerance>& shape = tolerances.roller_shapes[i];
    if (!shape) continue;
    const int order = shape->vdsp > 0.0 ? shape->form.max_order : shape->kea > 0.0 ? 1 : 0;
    const double rate = order * engine::SpinRatio(base, static_cast<int>(i));
    if (rate > fastest.rate) fastest = {rate, static_cast<int>(i), order};
  }
  return fastest;
}

}  // namespace ringtol::sampling
