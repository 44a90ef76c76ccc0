// Allocation files: a campaign file (jobs/campaign/campaign_file.h) whose [tolerances.*] are
// the current design, plus an [allocation] table saying what may change, what it costs and
// what must hold. The format, key by key, is docs/inputs.md, "Allocation files";
// docs/allocation.md is the manual, examples/allocation/default.toml the reference example.
//
// A component's options inherit every other key of its [tolerances] table (mode,
// capability, spectrum); a component with no [tolerances] table takes the defaults.
// Classes are looked up as the campaign looks them up, at each part's diameter.
//
// Failure: InputError naming the file, key, value and allowed values, for everything
// ReadCampaignFile refuses ([spec] is refused: constraints take its place) and for an
// unknown class, an unknown mode, options not ordered loosest first (by their
// characteristic tolerance, then process before inspected), a cost or model parameter out
// of range, a cost that falls as options tighten, a constraint on an output that does not
// exist or with neither or both of quantile and yield, an empty option list, an option
// listed twice, springs on a scene without a spring roller, candidates that would draw
// different sampler inputs (common random numbers need the same: options of a component
// must agree on which of Kea, VDsp, the ΔDmp interval, the spring stiffness and preload
// tolerances are zero, the only class values that change the sampler's input list), and
// reference = "current" when the current design is not a candidate.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "analysis/allocation.h"
#include "engine/enum_names.h"
#include "jobs/campaign/campaign_file.h"
#include "sampling/assembly_sampler.h"
#include "solvers/solver.h"

namespace ringtol::jobs {

// What may change: the four toleranced parts of a campaign, named as their [tolerances] tables.
enum class AllocatedComponent { kRing, kRollers, kRollerPositions, kSprings };
inline constexpr NameTable<AllocatedComponent, 4> kAllocatedComponentNames = {
    {{AllocatedComponent::kRing, "ring"},
     {AllocatedComponent::kRollers, "rollers"},
     {AllocatedComponent::kRollerPositions, "roller_positions"},
     {AllocatedComponent::kSprings, "springs"}}};

struct AllocationOption {
  std::string class_name;
  sampling::ToleranceMode mode = sampling::ToleranceMode::kProcess;
  // The class's characteristic tolerance, in the unit cost models take: ring circularity
  // RONt [µm], roller radial runout Kea [µm], roller position zone diameter [µm], spring
  // stiffness tolerance [%]; at the diameters the campaign looks the class up at (the
  // first roller's, where rollers differ).
  double tolerance = 0.0;
  double cost = 0.0;  // relative
  // The option's tolerances, resolved at every part's diameter: only this component's
  // entries are set (ring, or one per scene roller for the others).
  sampling::AssemblyTolerances tolerances;
};

struct ComponentChoice {
  AllocatedComponent component = AllocatedComponent::kRing;
  std::vector<AllocationOption> options;  // loosest first
  std::optional<analysis::CostModel> cost_model;  // where the costs came from, if not a table
};

enum class CostReference { kCurrent, kLoosest };
inline constexpr NameTable<CostReference, 2> kCostReferenceNames = {
    {{CostReference::kCurrent, "current"}, {CostReference::kLoosest, "loosest"}}};

struct AllocationPlan {
  CampaignPlan campaign;  // the current design; its [solver] is the accurate rung
  std::vector<ComponentChoice> components;  // in the order ring, rollers, roller_positions, springs
  std::vector<analysis::Constraint> constraints;
  std::optional<solvers::Rung> screen = solvers::Rung::kLinear;  // none: every sample on the accurate rung
  analysis::SearchOptions search;  // kind resolved from "auto"
  std::int64_t max_exhaustive = 256;
  std::int64_t first_samples = 256;
  double confidence = 0.95;
  CostReference reference = CostReference::kCurrent;
  std::optional<std::int64_t> current;  // the candidate the [tolerances] tables describe, if any
  std::string text;  // the file as read

  analysis::AllocationSpace Space() const;  // costs from `components`
  // The tolerances of a candidate: the current design's with each allocated component's
  // class (and mode) replaced by the candidate's option.
  sampling::AssemblyTolerances Tolerances(std::int64_t candidate) const;
};

// `stored`: the file's text and base scene as an allocation results file keeps them
// (see ReadSamplingFile).
AllocationPlan ReadAllocationFile(const std::filesystem::path& file, const StoredSampling* stored = nullptr);

}  // namespace ringtol::jobs
