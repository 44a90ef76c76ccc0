// What an allocation found, candidate by candidate: the allocation's own vocabulary, which
// its results file (jobs/store/allocation_store.h) persists and the report and the
// command read back. Plain data; no I/O.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "analysis/allocation.h"
#include "analysis/order_statistics.h"
#include "engine/enum_names.h"
#include "engine/error_motion.h"
#include "sampling/assembly_sampler.h"

namespace ringtol::jobs {

// The two ways a candidate's sample is simulated: by the cheap rung that screens, and by
// the accurate rung (the file's [solver]) that confirms.
enum class EvaluationRole : std::int8_t { kScreen = 0, kConfirm = 1 };
inline constexpr NameTable<EvaluationRole, 2> kEvaluationRoleNames = {
    {{EvaluationRole::kScreen, "screen"}, {EvaluationRole::kConfirm, "confirm"}}};

// What makes two runs the same allocation; resume refuses a file whose identity differs
// in any field but allocation_path.
struct AllocationIdentity {
  std::string ringtol_version;
  std::string catalogue_version;
  std::string allocation_path;  // provenance only
  std::string allocation_file;  // the allocation file's text
  std::string base_scene;       // the base scene as a scene file
  // How the error motion was filtered: the base scene's, so compared through it; the
  // results file states it beside each error-motion column it keeps.
  engine::ErrorMotionFilter error_motion_filter;
  std::string design;           // sampling::DesignName
  std::string solver;           // the confirming rung, solvers::SolverDescription
  std::string screen;           // the screening rung's name, or "none"
  std::string search;           // analysis::kSearchKindNames
  std::uint64_t seed = 0;
  std::int64_t samples = 0;     // the most samples any candidate gets (N)
  std::int64_t first_samples = 0;
  double confidence = 0.95;
  std::vector<sampling::SampledInput> inputs;  // the design's coordinates, common to every candidate
  // Per component (names of kAllocatedComponentNames), its options: class, mode name,
  // characteristic tolerance and cost.
  struct Option {
    std::string class_name;
    std::string mode;
    double tolerance = 0.0;
    double cost = 0.0;
  };
  std::vector<std::string> components;
  std::vector<std::vector<Option>> options;
  std::vector<analysis::Constraint> constraints;
  std::optional<std::int64_t> reference;  // the candidate relative cost is against
};

// A candidate as the search left it.
struct CandidateOutcome {
  std::vector<int> options;  // per component, loosest = 0
  double cost = 0.0;
  double relative_cost = 0.0;  // cost / the reference candidate's cost
  analysis::Verdict verdict = analysis::Verdict::kUnknown;
  analysis::Settlement settlement = analysis::Settlement::kNotVisited;
  // Simulated: the role whose samples gave the verdict, and how many samples it took.
  std::optional<EvaluationRole> settled_by;
  std::int64_t samples = 0;
  std::vector<analysis::ConstraintJudgement> constraints;  // per constraint; empty unless simulated
  // The fraction of assemblies within every constraint's limit at once (quantile
  // constraints count their `upper` as a limit too), from the settling role's samples;
  // trials = 0 unless simulated.
  analysis::ProportionEstimate yield;
  std::int64_t implied_by = -1;  // kImplied: the simulated candidate it follows from
};

struct AllocationOutcome {
  std::vector<CandidateOutcome> candidates;  // every candidate, by index
  bool complete = false;  // the search ran to its end (else: interrupted, or still running)
  std::optional<std::int64_t> recommendation;  // the cheapest feasible candidate
  std::vector<std::int64_t> alternatives;      // the next cheapest feasible, at most two
  // Simulated candidates cheaper than the recommendation whose verdict stayed undecided at
  // the most samples the file allows: the recommendation holds only if they are infeasible.
  std::vector<std::int64_t> undecided_cheaper;
  std::vector<std::int64_t> front;  // Pareto front of cost against yield, simulated candidates
  // No candidate feasible: the constraints the tightest candidate fails (indices).
  std::vector<int> binding;
  // Common random numbers, measured: analysis::CommonRandomNumbersGain for the first
  // constrained output between the recommendation and its cheapest simulated neighbour
  // (one option looser); NaN when there is none.
  double common_random_numbers_gain = 0.0;
  std::int64_t simulated = 0;         // candidates simulated
  std::int64_t settled_by_screen = 0;  // of which the screening rung settled
  std::int64_t samples_screen = 0;     // samples simulated by each role
  std::int64_t samples_confirm = 0;
};

}  // namespace ringtol::jobs
