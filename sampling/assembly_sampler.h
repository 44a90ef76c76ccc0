// From tolerances to assemblies: a base scene plus the tolerance of each error source
// becomes, for every design point u in (0, 1)^d, one realistic random assembly.
//
// Every scalar random input is one coordinate of u, mapped by its own inverse CDF, so that
// designs (sampling/design.h) stratify each input and Sobol' groups are clean:
//   ring form        orders 2..cutoff: Rayleigh amplitude and uniform phase per order
//                    (sampling/spectrum.h), scale calibrated to the circularity on RONt
//   roller shape     order 1: eccentricity e of the running surface about the axis,
//                    Rayleigh with P(2e <= Kea) = p, uniform phase;
//                    orders 2..cutoff: spectrum calibrated to VDsp on the two-point variation;
//                    size: mean diameter deviation, normal on the ΔDmp interval
//   roller position  offset of the axis from its nominal place: Rayleigh magnitude with
//                    P(2 |offset| <= zone diameter) = p, uniform direction
//   spring           relative stiffness and preload deviations, normal on +-tolerance
//   measured parts   instead of the ring's or the rollers' class (PartPopulation): one
//                    coordinate picks a measured part, or two per order draw from a law
//                    fitted to the parts (PopulationDraw)
// Capability: p = erf(3 Cp / sqrt 2) is the fraction of parts inside their tolerance
// (Cp = 1: 99.73 %; a normal quantity's +-tolerance is then 3 sigma Cp). Mode kProcess
// keeps every part, as made; kInspected rejects parts outside the tolerance and draws
// them again, as after a 100 % inspection. Redraws come from the counter-based generator
// keyed by (seed, sample, input, attempt), not from the design: the design stratifies the
// first attempt only.
//
// Sampled errors add to those of the base scene (harmonics of equal order add, offsets
// add, the spring's stiffness and preload scale by 1 + deviation).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "engine/scene.h"
#include "sampling/catalogue.h"
#include "sampling/design.h"
#include "sampling/spectrum.h"
#include "engine/enum_names.h"

namespace ringtol::sampling {

enum class ToleranceMode { kProcess, kInspected };
inline constexpr NameTable<ToleranceMode, 2> kToleranceModeNames = {
    {{ToleranceMode::kProcess, "process"}, {ToleranceMode::kInspected, "inspected"}}};

struct Capability {
  ToleranceMode mode = ToleranceMode::kProcess;
  double cp = 1.0;          // [-] > 0; spectra (form errors) accept up to 1.33 (CalibrationOptions)
  double Coverage() const;  // p = erf(3 cp / sqrt 2)
};

struct RingFormTolerance {
  std::string class_name;    // provenance only; empty when given as a number
  double circularity = 0.0;  // [m] RONt tolerance t > 0
  SpectrumShape spectrum;    // default orders 2..50 (ISO 12181's classic 50 UPR), n^-1
  Capability capability;
};

struct RollerShapeTolerance {
  std::string class_name;
  double kea = 0.0;                  // [m] >= 0; 0: no eccentricity drawn
  double vdsp = 0.0;                 // [m] >= 0; 0: no form drawn
  double mean_diameter_lower = 0.0;  // [m] ΔDmp interval; equal bounds: no size drawn
  double mean_diameter_upper = 0.0;
  // Default orders 2..8: a roller's order n passes n R / r_b (~60 n) times per revolution,
  // so each order costs solver steps; raise it where rollers are known to be lobed.
  SpectrumShape form{2, 8, 1.0, {}};
  Capability capability;
};

struct PositionTolerance {
  std::string class_name;
  double zone_diameter = 0.0;  // [m] > 0
  Capability capability;
};

struct SpringTolerance {
  std::string class_name;
  double stiffness = 0.0;  // [-] relative +-tolerance >= 0
  double preload = 0.0;    // [-] relative +-tolerance >= 0 and < 1
  Capability capability;
};

// A measured part as its fitted profile gives it: its deviation from the nominal profile.
struct MeasuredPart {
  std::string name;             // what the records call it: its export's file name
  double mean_deviation = 0.0;  // [m] its size about the nominal radius (0: its form alone)
  std::vector<engine::Harmonic> harmonics;
};

// How parts are drawn from a measured population (docs/usage.md, "Populations of measured
// parts"). kResample: each assembly takes one of the measured parts, every part equally
// likely; rollers take theirs without replacement, as from a batch on the bench (the i-th
// roller of the scene among the B - i parts left). kModel: per harmonic order the Fourier
// coefficients (C cos phi, C sin phi) of the parts are a two-dimensional normal law, their
// mean (a systematic lobe at a fixed phase) and one isotropic variance fitted to the parts,
// so that the amplitude is Rice distributed about that mean with uniform phase where it is
// zero; the size likewise normal. It draws parts the supplier has not made yet.
enum class PopulationDraw { kResample, kModel };
inline constexpr NameTable<PopulationDraw, 2> kPopulationDrawNames = {
    {{PopulationDraw::kResample, "resample"}, {PopulationDraw::kModel, "model"}}};

struct PartPopulation {
  std::vector<MeasuredPart> parts;  // >= 1 to resample (rollers: >= the scene's), >= 2 to model
  PopulationDraw draw = PopulationDraw::kResample;
};

// What is toleranced; an absent entry is an error source held at its nominal value.
struct AssemblyTolerances {
  std::optional<RingFormTolerance> ring;
  // Rings drawn from measured parts instead of a class: exclusive with `ring`.
  std::optional<PartPopulation> ring_population;
  // Rollers' running surfaces from a measured batch: exclusive with `roller_shapes` on the
  // rollers it fills.
  std::optional<PartPopulation> roller_population;
  // The scene rollers the batch fills, ascending (resampled in this order); empty: every
  // roller. The others keep their own outline, or their class's draw.
  std::vector<std::size_t> batch_rollers;
  std::vector<std::optional<RollerShapeTolerance>> roller_shapes;  // empty or one per scene roller
  std::vector<std::optional<PositionTolerance>> roller_positions;  // empty or one per scene roller
  std::vector<std::optional<SpringTolerance>> springs;             // empty or one per scene roller; springs only
};

enum class ErrorSource { kRingShape, kRollerShape, kRollerPosition, kSpring };
inline constexpr NameTable<ErrorSource, 4> kErrorSourceNames = {{{ErrorSource::kRingShape, "ring_shape"},
                                                                 {ErrorSource::kRollerShape, "roller_shape"},
                                                                 {ErrorSource::kRollerPosition, "roller_position"},
                                                                 {ErrorSource::kSpring, "spring"}}};
constexpr std::string_view ErrorSourceName(ErrorSource source) { return NameOf(kErrorSourceNames, source); }

// One coordinate of the design: what it draws, for records and for grouping.
struct SampledInput {
  std::string name;  // e.g. "ring.order3.amplitude_um", "roller.spring.position.offset_um"
  ErrorSource source;
  int roller = -1;        // scene roller index, -1 for the ring
  int order = 0;          // harmonic order (1 = eccentricity), 0 for sizes, positions, springs
  std::string quantity;   // the physical input it belongs to, e.g. "ring.order3", "roller.spring.position"
  std::string component;  // e.g. "ring", "roller.spring.shape", "roller.spring.position", "roller.spring.spring"
};

// How Saltelli groups are formed from the inputs.
enum class InputGrouping {
  kCoordinate,  // every coordinate alone (an amplitude apart from its phase)
  kQuantity,    // every physical input: a harmonic (amplitude + phase), a size, a position, ...
  kComponent,   // the ring's form; each roller's shape; each roller's position; each spring
  kSource,      // ring shape, roller shape, roller position, spring
  kOrder,       // each harmonic order across ring and rollers; sizes, positions, springs apart
};
inline constexpr NameTable<InputGrouping, 5> kInputGroupingNames = {{{InputGrouping::kCoordinate, "coordinate"},
                                                                     {InputGrouping::kQuantity, "quantity"},
                                                                     {InputGrouping::kComponent, "component"},
                                                                     {InputGrouping::kSource, "source"},
                                                                     {InputGrouping::kOrder, "order"}}};
constexpr std::string_view InputGroupingName(InputGrouping grouping) { return NameOf(kInputGroupingNames, grouping); }

struct InputGroups {
  std::vector<std::string> names;
  std::vector<std::vector<int>> coordinates;  // per group, the design coordinates it holds
};

// One realised assembly.
struct SampledAssembly {
  std::int64_t index = 0;
  engine::Scene scene;
  std::vector<double> u;       // the coordinates used, after any redraws
  std::vector<double> values;  // per input, the drawn value in the unit its name states
  int redraws = 0;             // inspected parts rejected and drawn again
};

// What a component's calibration came to, for provenance and reports.
struct ComponentScale {
  std::string component;
  FormMeasure measure;
  double tolerance = 0.0;  // [m]
  double coverage = 0.0;   // [-]
  SpectrumCalibration calibration;
};

// Calibrations kept for reuse by every sampler given the same cache: a calibration costs
// about a quarter of a second and depends only on (shape, measure, tolerance, coverage,
// options), so samplers that share classes (one per candidate of a tolerance allocation)
// calibrate each class once. Thread-safe; a calibration that throws is not kept.
class CalibrationCache {
 public:
  CalibrationCache();
  ~CalibrationCache();
  SpectrumCalibration Calibrate(const SpectrumShape& shape, FormMeasure measure, double tolerance, double coverage,
                                const CalibrationOptions& options);
  std::size_t size() const;

 private:
  struct Entries;
  std::unique_ptr<Entries> entries_;
};

struct AssemblySamplerOptions {
  std::uint64_t seed = 1;  // the campaign seed (redraws)
  // Attempts per inspected component before the sample is refused. With p >= 0.24 (Cp >=
  // 0.1), 200 attempts all failing has probability below 1e-23.
  int max_attempts = 200;
  CalibrationOptions calibration;
  // How an inspected part's form is judged against its tolerance. false: bounds first
  // (FormWithin: the amplitudes, then a coarse grid), the exact measure only where they
  // straddle the tolerance. true: MeasureForm on every part. The
  // accepted parts, and so every assembly and redraw count, are the same either way; true
  // is the reference the fast path is tested against.
  bool exact_form_inspection = false;
  // Shared calibrations (may be null: every sampler calibrates its own).
  std::shared_ptr<CalibrationCache> calibrations;
  // Calibrations made before, as scales() gave them (read back from a results file): a
  // form spectrum whose component, measure, tolerance and coverage all equal one of these
  // takes its calibration instead of calibrating, so that a replay draws with the very
  // scales the run drew with, at no cost; any other calibrates. The shape and the
  // calibration options are not compared: a results file's samples were drawn with its
  // stored scales whatever this build would calibrate.
  std::vector<ComponentScale> known_scales;
};

// Resampling without replacement: the part a coordinate u in [0, 1) picks among the parts
// `left` (in their order), removed from them. A batch's k-th roller takes its part so from
// the B - k left.
std::size_t TakePart(std::vector<std::size_t>& left, double u);

// The scene rollers a roller batch fills: `tolerances.batch_rollers`, or all `rollers` of
// the scene when it is empty.
std::vector<std::size_t> BatchRollers(const AssemblyTolerances& tolerances, std::size_t rollers);

// `base` with roller rollers[k]'s running surface joined by part parts[k] of `batch` (its
// size and form added to the outline's, as a resampled draw adds them): the assembly built
// with those rollers. Throws std::invalid_argument unless there is one part per listed
// roller, each in the batch and each roller in the scene.
engine::Scene WithRollerParts(const engine::Scene& base, const PartPopulation& batch,
                              std::span<const std::size_t> rollers, std::span<const std::size_t> parts);

// The fastest term any assembly drawn from (base, tolerances) can have: the base scene's
// own harmonics, the ring's spectrum up to its cutoff, each roller's form up to its cutoff
// (its eccentricity where only Kea is toleranced) at the base scene's spin ratios. Drawn
// sizes move a ratio by parts per million, which this leaves out.
engine::FastestHarmonic FastestDrawnHarmonic(const engine::Scene& base, const AssemblyTolerances& tolerances);

class AssemblySampler {
 public:
  // Validates the tolerances against the scene and calibrates every spectrum. Throws
  // std::invalid_argument naming the roller and quantity for vectors of the wrong size, a
  // spring tolerance on a fixed roller, non-positive or non-finite tolerances, a
  // capability outside (0, 1.33] for form errors, a population beside its part's tolerance,
  // one without parts, with fewer than two to model or, to resample rollers, fewer parts
  // than rollers, and what CalibrateSpectrum refuses.
  AssemblySampler(engine::Scene base, AssemblyTolerances tolerances, AssemblySamplerOptions options = {});
  ~AssemblySampler();
  AssemblySampler(const AssemblySampler&);
  AssemblySampler(AssemblySampler&&) noexcept;

  int dimension() const { return static_cast<int>(inputs_.size()); }
  const std::vector<SampledInput>& inputs() const { return inputs_; }
  const std::vector<ComponentScale>& scales() const { return scales_; }
  const engine::Scene& base() const { return base_; }
  const AssemblyTolerances& tolerances() const { return tolerances_; }

  InputGroups Groups(InputGrouping grouping) const;

  // The assembly of sample `index` at design point u (size dimension()). A pure function
  // of (base, tolerances, options, index, u). Throws std::runtime_error if an inspected
  // component fails max_attempts times (not reachable at p >= 0.24, see above).
  SampledAssembly Realise(std::int64_t index, std::span<const double> u) const;

  // Design point and assembly of sample `index` in one step.
  SampledAssembly Sample(Design& design, std::int64_t index) const;

 private:
  struct Component;
  class Builder;
  engine::Scene base_;
  AssemblyTolerances tolerances_;
  AssemblySamplerOptions options_;
  std::vector<SampledInput> inputs_;
  std::vector<ComponentScale> scales_;
  std::vector<Component> components_;
};

}  // namespace ringtol::sampling
