// Tolerance allocation: choose one option (a tolerance class) per component so that an
// assembly meets every constraint at the lowest cost. Pure computation: the candidates,
// their costs, the judgement of a constraint from simulated samples with confidence
// intervals, the search that decides which candidates to simulate, and the Pareto front.
// What a candidate's samples are, and how they are simulated, is the caller's
// (jobs/allocation/).
//
// A candidate is one option per component. Each component's options are listed loosest
// first, and the search relies on two monotone facts (docs/allocation.md):
//   cost:        a tighter option never costs less (AllocationSpace checks it);
//   feasibility: tightening an option never widens the distribution of an output, so a
//                candidate looser than an infeasible one in every component is
//                infeasible, and one tighter than a feasible one is feasible.
// Feasibility is only ever decided from a confidence interval (JudgeConstraint): a
// candidate whose interval straddles a limit is undecided, and the search never prunes
// with an undecided candidate, so sampling noise between neighbouring classes cannot
// make it skip the answer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "analysis/order_statistics.h"
#include "engine/enum_names.h"

namespace ringtol::analysis {

// The candidates: the product of every component's options.
class AllocationSpace {
 public:
  // costs[c][o]: the cost of option o of component c, options loosest first. Throws
  // std::invalid_argument for no component, a component without options, a negative or
  // non-finite cost, or a cost that falls as options tighten (naming component and option).
  explicit AllocationSpace(std::vector<std::vector<double>> costs);

  int components() const { return static_cast<int>(costs_.size()); }
  int options(int component) const { return static_cast<int>(costs_[static_cast<std::size_t>(component)].size()); }
  std::int64_t size() const { return size_; }  // number of candidates

  // Mixed radix, the last component fastest: candidate 0 is the loosest in every component,
  // size() - 1 the tightest. std::out_of_range for a candidate or option outside the space.
  std::vector<int> Options(std::int64_t candidate) const;
  std::int64_t Candidate(std::span<const int> options) const;
  // The sum of the components' option costs.
  double Cost(std::int64_t candidate) const;
  // Whether `a` is at least as tight as `b` in every component.
  bool AtLeastAsTight(std::int64_t a, std::int64_t b) const;

 private:
  std::vector<std::vector<double>> costs_;
  std::int64_t size_ = 0;
};

// Cost-tolerance models: the relative cost of holding a tolerance t (t > 0, in the unit
// the caller documents for the component: µm for lengths, % for relative tolerances).
// Forms from the cost-tolerance literature (docs/tolerances.md §9, C1).
enum class CostForm {
  kReciprocalPower,  // a + b / t^k
  kExponential,      // a + b exp(-k t)
};
inline constexpr NameTable<CostForm, 2> kCostFormNames = {
    {{CostForm::kReciprocalPower, "reciprocal_power"}, {CostForm::kExponential, "exponential"}}};

struct CostModel {
  CostForm form = CostForm::kReciprocalPower;
  double a = 0.0;  // >= 0: the cost of any tolerance (setup, handling)
  double b = 1.0;  // > 0
  double k = 1.0;  // > 0
  // Throws std::invalid_argument for a tolerance not finite and > 0 or parameters out of
  // their ranges.
  double Cost(double tolerance) const;
};

// What a constraint bounds: a quantile of an output, or the fraction of assemblies
// within a limit (the yield).
enum class ConstraintKind { kQuantile, kYield };
inline constexpr NameTable<ConstraintKind, 2> kConstraintKindNames = {
    {{ConstraintKind::kQuantile, "quantile"}, {ConstraintKind::kYield, "yield"}}};

struct Constraint {
  std::string output;  // a per-sample output, by its column name (unit in the name)
  ConstraintKind kind = ConstraintKind::kQuantile;
  // kQuantile: the probability p in (0, 1) of the quantile that must be <= upper;
  // kYield: the least fraction in (0, 1) of assemblies whose output must be <= upper.
  double level = 0.99;
  double upper = 0.0;  // the limit, in the output's unit
};

// What is known of a candidate's feasibility.
enum class Verdict : std::int8_t {
  kUnknown = 0,     // not simulated (or not enough of it)
  kFeasible = 1,    // the interval lies within the limit at the stated confidence
  kInfeasible = 2,  // the interval lies beyond it
  kUndecided = 3,   // the interval straddles it at every sample count simulated
};
inline constexpr NameTable<Verdict, 4> kVerdictNames = {{{Verdict::kUnknown, "unknown"},
                                                         {Verdict::kFeasible, "feasible"},
                                                         {Verdict::kInfeasible, "infeasible"},
                                                         {Verdict::kUndecided, "undecided"}}};

struct ConstraintJudgement {
  Verdict verdict = Verdict::kUnknown;  // kFeasible, kInfeasible or kUndecided
  double estimate = 0.0;  // kQuantile: the sample quantile; kYield: the fraction within the limit
  Interval interval;      // confidence interval of the same quantity
  std::int64_t samples = 0;
  // Undecided: about how many samples would decide it, from the interval's half-width
  // shrinking as 1/sqrt(n) around the estimate (n (half-width / |estimate - limit|)^2,
  // the half-width being the distance from the estimate to the interval's end facing the
  // limit). Where too few samples bound that end at all (a quantile's rank beyond n), the
  // least n that bounds it. -1 when the estimate sits on the limit, where no sample count
  // decides it, or is infinite (failures beyond the quantile). 0 when decided.
  std::int64_t samples_to_decide = 0;
};

// Judges one constraint from n >= 1 samples of one candidate. Sample i's true value is
// known to lie in [lower[i], upper[i]] (equal for an accurate rung; a cheap rung's value
// -+ its error bound); `value[i]` is the best estimate, used for `estimate`. A failed
// sample is NaN in all three and counts as beyond the limit (an assembly that cannot be
// simulated is not one that meets its spec). The quantile's interval is the lower end of
// the distribution-free interval of the lower values and the upper end of that of the
// upper values (EstimateQuantile); the yield's runs from the Clopper-Pearson lower bound
// of the samples surely within (upper <= limit) to the upper bound of those possibly
// within (lower <= limit). Feasible when the whole interval is within the limit
// (quantile: interval.upper <= limit; yield: interval.lower >= level), infeasible when the
// whole of it is beyond, else undecided. Throws std::invalid_argument for spans of
// unequal length or empty, a level or confidence outside (0, 1), or a non-finite limit.
ConstraintJudgement JudgeConstraint(const Constraint& constraint, std::span<const double> value,
                                    std::span<const double> lower, std::span<const double> upper,
                                    double confidence);

// The samples of a yield: those surely within the limit (even at the far end of their error
// bound), those within by their value, those possibly within (at the near end), of n.
struct YieldCounts {
  std::int64_t surely = 0;
  std::int64_t possibly = 0;
  std::int64_t within = 0;
  std::int64_t n = 0;
};
// JudgeConstraint's yield from its counts, against the least fraction `level` in (0, 1):
// feasible when the Clopper-Pearson interval [lower bound of `surely`, upper bound of
// `possibly`] lies at or above `level`, infeasible when below, else undecided with
// samples_to_decide. Throws std::invalid_argument for counts not 0 <= surely <= within <=
// possibly <= n with n >= 1, or a level or confidence outside (0, 1).
ConstraintJudgement JudgeYield(const YieldCounts& counts, double level, double confidence);

// A candidate's verdict from its constraints' verdicts: infeasible when any is
// infeasible, feasible when all are feasible (so when there are none), else undecided
// (kUnknown when any is).
Verdict CombineVerdicts(std::span<const Verdict> verdicts);

// How the search visits the space.
enum class SearchKind {
  kExhaustive,      // every candidate, in index order
  kBranchAndBound,  // see AllocationSearch
};
inline constexpr NameTable<SearchKind, 2> kSearchKindNames = {
    {{SearchKind::kExhaustive, "exhaustive"}, {SearchKind::kBranchAndBound, "branch_and_bound"}}};

struct SearchOptions {
  SearchKind kind = SearchKind::kBranchAndBound;
  // Candidates asked for at a time (>= 1): a fixed number, not one per rank, so that which
  // candidates are simulated never depends on how many ranks simulate them.
  int batch = 8;
};

// How the search came to know a candidate's verdict.
enum class Settlement : std::int8_t {
  kNotVisited = 0,  // neither simulated nor implied
  kSimulated = 1,   // simulated; its verdict is its own
  kImplied = 2,     // not simulated: looser than an infeasible candidate (infeasible) or
                    // tighter than a feasible one (feasible)
  kCostlier = 3,    // not simulated nor implied: costs at least as much as the
                    // recommendation (ties lose to its lower index), so it cannot change it
};
inline constexpr NameTable<Settlement, 4> kSettlementNames = {{{Settlement::kNotVisited, "not_visited"},
                                                               {Settlement::kSimulated, "simulated"},
                                                               {Settlement::kImplied, "implied"},
                                                               {Settlement::kCostlier, "costlier"}}};

// Decides which candidates to simulate; the caller simulates them and reports each
// candidate's verdict. Deterministic: what Next() returns depends only on the verdicts
// reported so far (not on their order within a batch), so a run interrupted and resumed
// from its stored verdicts asks for the same candidates.
//
// kExhaustive asks for every candidate. kBranchAndBound (after Lee & Woo's branch and
// bound over discrete tolerances, docs/tolerances.md §9) walks a tree that fixes one
// component per level, loosest option first. A node (the first j components fixed) is
// bounded by two candidates: its loosest completion L (the rest at their loosest: the
// node's cheapest candidate) and its tightest completion T (the rest at their tightest).
// Nodes are taken cheapest L first (ties: lower L index, then the shallower node); a node is
//   - cut when the best feasible candidate found beats L: cheaper, or as cheap with a
//     lower index (every candidate of the node costs at least cost(L), and L has the
//     node's lowest index),
//   - cut when T is infeasible: every candidate of the node is looser than T,
//   - closed when L is feasible: L is the node's cheapest candidate (the best is then L or
//     one that beats it),
//   - else expanded into its children (T or L undecided included; an undecided leaf is
//     dropped).
// A verdict is known when the candidate was simulated, or implied by a decided simulated
// one (looser than an infeasible one: infeasible; tighter than a feasible one: feasible;
// infeasible wins where noise makes both hold). kUndecided implies nothing. A node whose
// T and L are known is settled without asking; otherwise it asks for its T first and for
// its L only once T is known not to be infeasible, so a node beyond the limit costs one
// simulation (and a space without a feasible candidate ends on the tightest). Each step
// settles what it can and asks for the unknown T or L of the open nodes, cheapest first,
// until `batch` candidates are asked. The best is the cheapest simulated feasible
// candidate (ties: lower index), whichever node asked for it. The result is the cheapest
// feasible candidate, equal to exhaustive evaluation's whenever the two monotone facts
// hold for the verdicts. Cost per step: O(log) per node settled plus, per verdict looked
// up, the size of the frontier of decided candidates; verdict() and settlement() build a
// per-candidate table (O(size x components)) after each step in which they are first
// called.
class AllocationSearch {
 public:
  AllocationSearch(const AllocationSpace& space, SearchOptions options);
  ~AllocationSearch();

  // The next candidates to simulate (at most options.batch, none already asked for), in
  // ascending index order; empty when the search is over. Every candidate returned by the
  // previous call must have been reported (Report) first (else std::logic_error).
  std::vector<std::int64_t> Next();
  // The verdict of a simulated candidate: kFeasible, kInfeasible or kUndecided (else
  // std::invalid_argument). Throws std::logic_error for a candidate not in the last batch
  // or already reported.
  void Report(std::int64_t candidate, Verdict verdict);

  bool done() const;
  // The cheapest candidate known to be feasible (ties: lowest index), if any.
  std::optional<std::int64_t> best() const;
  // Per candidate, what is known and how: a simulated candidate's own verdict, else the
  // implied one, else kUnknown. Throws std::out_of_range outside the space.
  Verdict verdict(std::int64_t candidate) const;
  Settlement settlement(std::int64_t candidate) const;
  std::int64_t simulated() const;  // candidates reported so far

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// Indices of the candidates on the Pareto front of cost (lower is better) against
// `merit` (higher is better: a yield), among those given: a point is on the front when no
// other has cost <= and merit >= with one of them strict. Sorted by ascending cost.
// NaN merits are left out.
std::vector<std::int64_t> ParetoFront(std::span<const std::int64_t> candidates, std::span<const double> cost,
                                      std::span<const double> merit);

// Variance reduction of common random numbers for the difference of two candidates'
// means over the same n paired samples (NaN pairs left out): (Var a + Var b) / Var(a - b),
// the factor by which independent streams would need more samples for the same precision
// of the difference. Infinity when a - b is constant; NaN for fewer than two pairs.
double CommonRandomNumbersGain(std::span<const double> a, std::span<const double> b);

}  // namespace ringtol::analysis
