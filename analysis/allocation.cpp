#include "analysis/allocation.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <set>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>

#include "engine/check.h"

namespace ringtol::analysis {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

std::string OptionName(std::size_t component, std::size_t option) {
  return "component " + std::to_string(component) + ", option " + std::to_string(option);
}

}  // namespace

// ---------------------------------------------------------------------------------------
// The candidates.

AllocationSpace::AllocationSpace(std::vector<std::vector<double>> costs) : costs_(std::move(costs)) {
  if (costs_.empty()) throw std::invalid_argument("AllocationSpace: no component");
  size_ = 1;
  for (std::size_t c = 0; c < costs_.size(); ++c) {
    const std::vector<double>& options = costs_[c];
    if (options.empty()) throw std::invalid_argument("AllocationSpace: component " + std::to_string(c) + " has no option");
    for (std::size_t o = 0; o < options.size(); ++o) {
      if (!std::isfinite(options[o]) || options[o] < 0.0) {
        throw std::invalid_argument("AllocationSpace: " + OptionName(c, o) + " costs " + std::to_string(options[o]) +
                                    ": allowed finite and >= 0");
      }
      if (o > 0 && options[o] < options[o - 1]) {
        throw std::invalid_argument("AllocationSpace: " + OptionName(c, o) + " costs " + std::to_string(options[o]) +
                                    ", less than the looser option " + std::to_string(o - 1) + "'s " +
                                    std::to_string(options[o - 1]) + ": a tighter option never costs less");
      }
    }
    const auto count = static_cast<std::int64_t>(options.size());
    if (size_ > std::numeric_limits<std::int64_t>::max() / count) {
      throw std::invalid_argument("AllocationSpace: more than 2^63 candidates");
    }
    size_ *= count;
  }
}

std::vector<int> AllocationSpace::Options(std::int64_t candidate) const {
  if (candidate < 0 || candidate >= size_) {
    throw std::out_of_range("AllocationSpace: candidate " + std::to_string(candidate) + " of " + std::to_string(size_));
  }
  std::vector<int> options(costs_.size());
  for (std::size_t c = costs_.size(); c-- > 0;) {
    const auto count = static_cast<std::int64_t>(costs_[c].size());
    options[c] = static_cast<int>(candidate % count);
    candidate /= count;
  }
  return options;
}

std::int64_t AllocationSpace::Candidate(std::span<const int> options) const {
  if (options.size() != costs_.size()) {
    throw std::invalid_argument("AllocationSpace: " + std::to_string(options.size()) + " options for " +
                                std::to_string(costs_.size()) + " components");
  }
  std::int64_t candidate = 0;
  for (std::size_t c = 0; c < costs_.size(); ++c) {
    if (options[c] < 0 || static_cast<std::size_t>(options[c]) >= costs_[c].size()) {
      throw std::out_of_range("AllocationSpace: " + OptionName(c, static_cast<std::size_t>(options[c])) + " of " +
                              std::to_string(costs_[c].size()));
    }
    candidate = candidate * static_cast<std::int64_t>(costs_[c].size()) + options[c];
  }
  return candidate;
}

double AllocationSpace::Cost(std::int64_t candidate) const {
  const std::vector<int> options = Options(candidate);
  double cost = 0.0;
  for (std::size_t c = 0; c < costs_.size(); ++c) cost += costs_[c][static_cast<std::size_t>(options[c])];
  return cost;
}

bool AllocationSpace::AtLeastAsTight(std::int64_t a, std::int64_t b) const {
  const std::vector<int> tight = Options(a);
  const std::vector<int> loose = Options(b);
  return std::equal(tight.begin(), tight.end(), loose.begin(), std::greater_equal<>());
}

// ---------------------------------------------------------------------------------------
// Cost models.

double CostModel::Cost(double tolerance) const {
  if (!(std::isfinite(tolerance) && tolerance > 0.0)) {
    throw std::invalid_argument("CostModel: tolerance = " + std::to_string(tolerance) + ": allowed finite and > 0");
  }
  if (!(std::isfinite(a) && a >= 0.0) || !(std::isfinite(b) && b > 0.0) || !(std::isfinite(k) && k > 0.0)) {
    throw std::invalid_argument("CostModel " + std::string(NameOf(kCostFormNames, form)) + ": a = " + std::to_string(a) +
                                ", b = " + std::to_string(b) + ", k = " + std::to_string(k) +
                                ": allowed a >= 0, b > 0, k > 0, all finite");
  }
  switch (form) {
    case CostForm::kReciprocalPower:
      return a + b / std::pow(tolerance, k);
    case CostForm::kExponential:
      return a + b * std::exp(-k * tolerance);
  }
  throw std::invalid_argument("CostModel: unknown form");
}

// ---------------------------------------------------------------------------------------
// Judgement.

namespace {

// A failed sample (NaN) is beyond any upper limit: it sorts to the top as +inf.
std::vector<double> SortedWithFailuresOnTop(std::span<const double> values) {
  std::vector<double> sorted(values.begin(), values.end());
  for (double& v : sorted) {
    if (std::isnan(v)) v = kInfinity;
  }
  std::sort(sorted.begin(), sorted.end());
  return sorted;
}

// Hyndman & Fan type 7 as EstimateQuantile computes it, where an end may be infinite.
double QuantileWithInfiniteEnds(const std::vector<double>& sorted, double probability) {
  const double h = (static_cast<double>(sorted.size()) - 1.0) * probability;
  const auto below = static_cast<std::size_t>(std::floor(h));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  const double fraction = h - static_cast<double>(below);
  if (fraction == 0.0 || sorted[below] == sorted[above]) return sorted[below];
  if (std::isinf(sorted[below]) || std::isinf(sorted[above])) return sorted[std::isinf(sorted[above]) ? above : below];
  return sorted[below] + fraction * (sorted[above] - sorted[below]);
}

// The value of 1-based rank `rank` of `sorted`; -inf below rank 1, +inf above rank n.
double AtRank(const std::vector<double>& sorted, std::int64_t rank) {
  if (rank < 1) return -kInfinity;
  if (rank > static_cast<std::int64_t>(sorted.size())) return kInfinity;
  return sorted[static_cast<std::size_t>(rank - 1)];
}

// The least sample count at which the order-statistic interval of the p-quantile is
// bounded on one side: P(no sample beyond the quantile on that side) = q^n <= tail, with
// q = p for the upper side and 1 - p for the lower.
std::int64_t SamplesToBoundSide(double q, double confidence) {
  const double tail = 0.5 * (1.0 - confidence);
  return static_cast<std::int64_t>(std::ceil(std::log(tail) / std::log(q)));
}

// n (half-width / margin)^2, with `near_end` the interval's end facing the limit.
std::int64_t SamplesToDecide(std::int64_t n, double estimate, double near_end, double limit) {
  const double margin = std::abs(estimate - limit);
  const double half_width = std::abs(near_end - estimate);
  if (!(margin > 0.0) || !std::isfinite(margin) || !std::isfinite(half_width)) return -1;
  const double needed = std::ceil(static_cast<double>(n) * (half_width / margin) * (half_width / margin));
  constexpr double kMost = 1e18;  // beyond any campaign; keeps the conversion defined
  return static_cast<std::int64_t>(std::min(needed, kMost));
}

}  // namespace

ConstraintJudgement JudgeConstraint(const Constraint& constraint, std::span<const double> value,
                                    std::span<const double> lower, std::span<const double> upper,
                                    double confidence) {
  if (value.empty() || lower.size() != value.size() || upper.size() != value.size()) {
    throw std::invalid_argument("JudgeConstraint: " + std::to_string(value.size()) + " values, " +
                                std::to_string(lower.size()) + " lower and " + std::to_string(upper.size()) +
                                " upper bounds; allowed n >= 1 of each");
  }
  if (!(constraint.level > 0.0 && constraint.level < 1.0)) {
    throw std::invalid_argument("JudgeConstraint: " + constraint.output + " level = " + std::to_string(constraint.level) +
                                ": allowed (0, 1)");
  }
  if (!std::isfinite(constraint.upper)) {
    throw std::invalid_argument("JudgeConstraint: " + constraint.output + " upper = " + std::to_string(constraint.upper) +
                                ": allowed finite");
  }
  if (!(confidence > 0.0 && confidence < 1.0)) {
    throw std::invalid_argument("JudgeConstraint: confidence = " + std::to_string(confidence) + ": allowed (0, 1)");
  }
  const auto n = static_cast<std::int64_t>(value.size());
  const double limit = constraint.upper;
  ConstraintJudgement judgement;
  judgement.samples = n;

  if (constraint.kind == ConstraintKind::kQuantile) {
    // The interval's ranks depend on n, p and the confidence only: take them from the ranks
    // themselves, then read the values (failures at +inf) at those ranks.
    std::vector<double> ranks(static_cast<std::size_t>(n));
    std::iota(ranks.begin(), ranks.end(), 1.0);
    const QuantileEstimate by_rank = EstimateQuantile(ranks, constraint.level, confidence);
    judgement.estimate = QuantileWithInfiniteEnds(SortedWithFailuresOnTop(value), constraint.level);
    judgement.interval.lower = AtRank(SortedWithFailuresOnTop(lower), by_rank.lower_rank);
    judgement.interval.upper = AtRank(SortedWithFailuresOnTop(upper), by_rank.upper_rank);
    if (judgement.interval.upper <= limit) {
      judgement.verdict = Verdict::kFeasible;
    } else if (judgement.interval.lower > limit) {
      judgement.verdict = Verdict::kInfeasible;
    } else {
      judgement.verdict = Verdict::kUndecided;
      const bool below = judgement.estimate < limit;
      const double near_end = below ? judgement.interval.upper : judgement.interval.lower;
      if (std::isinf(near_end) && std::isfinite(judgement.estimate) && judgement.estimate != limit) {
        // Too few samples to bound that side at all: at least as many as bound it.
        const double q = below ? constraint.level : 1.0 - constraint.level;
        judgement.samples_to_decide = std::max(n + 1, SamplesToBoundSide(q, confidence));
      } else {
        judgement.samples_to_decide = SamplesToDecide(n, judgement.estimate, near_end, limit);
      }
    }
    return judgement;
  }

  // Yield. NaN compares false, so a failed sample is neither surely nor possibly within.
  std::int64_t surely = 0;
  std::int64_t possibly = 0;
  std::int64_t within = 0;
  for (std::size_t i = 0; i < value.size(); ++i) {
    surely += upper[i] <= limit ? 1 : 0;
    possibly += lower[i] <= limit ? 1 : 0;
    within += value[i] <= limit ? 1 : 0;
  }
  return JudgeYield({surely, possibly, within, n}, constraint.level, confidence);
}

ConstraintJudgement JudgeYield(const YieldCounts& counts, double level, double confidence) {
  const auto [surely, possibly, within, n] = counts;
  if (!(n >= 1 && surely >= 0 && surely <= within && within <= possibly && possibly <= n)) {
    throw std::invalid_argument("JudgeYield: counts surely " + std::to_string(surely) + ", within " +
                                std::to_string(within) + ", possibly " + std::to_string(possibly) + " of n " +
                                std::to_string(n) + ": allowed 0 <= surely <= within <= possibly <= n, n >= 1");
  }
  if (!(level > 0.0 && level < 1.0) || !(confidence > 0.0 && confidence < 1.0)) {
    throw std::invalid_argument("JudgeYield: level = " + std::to_string(level) + ", confidence = " +
                                std::to_string(confidence) + ": allowed (0, 1) each");
  }
  ConstraintJudgement judgement;
  judgement.samples = n;
  judgement.estimate = static_cast<double>(within) / static_cast<double>(n);
  judgement.interval.lower = EstimateProportion(surely, n, confidence).interval.lower;
  judgement.interval.upper = EstimateProportion(possibly, n, confidence).interval.upper;
  if (judgement.interval.lower >= level) {
    judgement.verdict = Verdict::kFeasible;
  } else if (judgement.interval.upper < level) {
    judgement.verdict = Verdict::kInfeasible;
  } else {
    judgement.verdict = Verdict::kUndecided;
    const double near_end = judgement.estimate >= level ? judgement.interval.lower : judgement.interval.upper;
    judgement.samples_to_decide = SamplesToDecide(n, judgement.estimate, near_end, level);
  }
  return judgement;
}

Verdict CombineVerdicts(std::span<const Verdict> verdicts) {
  bool unknown = false;
  bool undecided = false;
  for (const Verdict v : verdicts) {
    if (v == Verdict::kInfeasible) return Verdict::kInfeasible;
    unknown = unknown || v == Verdict::kUnknown;
    undecided = undecided || v == Verdict::kUndecided;
  }
  if (unknown) return Verdict::kUnknown;
  return undecided ? Verdict::kUndecided : Verdict::kFeasible;
}

// ---------------------------------------------------------------------------------------
// The search.

namespace {

// A node of the branch-and-bound tree: its first `depth` components fixed, the rest at
// their loosest in `loosest` (its cheapest and lowest-indexed candidate, L).
struct Node {
  double cost = 0.0;  // cost(L)
  std::int64_t loosest = 0;
  int depth = 0;
};

// Cheapest L first, then lower L index, then the shallower node (a node's first child
// shares its L and comes right after it).
struct NodeOrder {
  bool operator()(const Node& a, const Node& b) const {
    if (a.cost != b.cost) return a.cost < b.cost;
    if (a.loosest != b.loosest) return a.loosest < b.loosest;
    return a.depth < b.depth;
  }
};

// Candidates whose verdict implies that of every candidate on one side of them, kept as
// the antichain of the extreme ones (the tightest infeasible, the loosest feasible).
class Frontier {
 public:
  // `covers(a, b)`: a's verdict implies b's. Adds `c` unless an element covers it, and
  // drops the elements it covers.
  template <typename Relation>
  void Add(std::vector<int> options, Relation covers) {
    for (const std::vector<int>& e : elements_) {
      if (covers(e, options)) return;
    }
    std::erase_if(elements_, [&](const std::vector<int>& e) { return covers(options, e); });
    elements_.push_back(std::move(options));
  }
  template <typename Relation>
  bool Covers(const std::vector<int>& options, Relation covers) const {
    return std::any_of(elements_.begin(), elements_.end(), [&](const std::vector<int>& e) { return covers(e, options); });
  }

 private:
  std::vector<std::vector<int>> elements_;
};

bool Tighter(const std::vector<int>& a, const std::vector<int>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), std::greater_equal<>());
}
bool Looser(const std::vector<int>& a, const std::vector<int>& b) { return Tighter(b, a); }

}  // namespace

struct AllocationSearch::State {
  AllocationSpace space;
  SearchOptions options;
  std::vector<std::int64_t> stride;  // stride[c]: the index step of one option of component c
  std::vector<std::int64_t> tail;    // tail[j]: L -> T for a node of depth j

  std::unordered_map<std::int64_t, Verdict> simulated;
  std::vector<std::pair<std::int64_t, Verdict>> pending;  // reported since the last step
  std::vector<std::int64_t> outstanding;                  // asked for, not yet reported
  std::vector<std::int64_t> prepared;                     // what the next Next() returns
  Frontier tightest_infeasible;                           // everything looser is infeasible
  Frontier loosest_feasible;                              // everything tighter is feasible
  std::optional<std::int64_t> best;
  double best_cost = 0.0;

  std::int64_t next_exhaustive = 0;
  std::set<Node, NodeOrder> open;

  // Per candidate implications, recomputed on demand after a report.
  mutable bool implications_current = false;
  mutable std::vector<std::int8_t> implied;  // Verdict of the implication, kUnknown if none

  State(const AllocationSpace& s, SearchOptions o) : space(s), options(o) {
    const int k = space.components();
    stride.assign(static_cast<std::size_t>(k), 1);
    tail.assign(static_cast<std::size_t>(k) + 1, 0);
    for (int c = k - 1; c >= 0; --c) {
      const auto i = static_cast<std::size_t>(c);
      if (c + 1 < k) stride[i] = stride[i + 1] * space.options(c + 1);
      tail[i] = tail[i + 1] + static_cast<std::int64_t>(space.options(c) - 1) * stride[i];
    }
    if (options.kind == SearchKind::kBranchAndBound) open.insert(Node{space.Cost(0), 0, 0});
  }

  // Whether `a` is cheaper than `b`, ties to the lower index.
  bool Cheaper(std::int64_t a, double cost_a, std::int64_t b, double cost_b) const {
    return cost_a < cost_b || (cost_a == cost_b && a < b);
  }

  // What is known of a candidate now: its own verdict, else an implication (infeasible
  // first: when noise makes the two disagree, never call a candidate feasible on it).
  Verdict Known(std::int64_t candidate) const {
    if (const auto it = simulated.find(candidate); it != simulated.end()) return it->second;
    const std::vector<int> o = space.Options(candidate);
    if (tightest_infeasible.Covers(o, Tighter)) return Verdict::kInfeasible;
    if (loosest_feasible.Covers(o, Looser)) return Verdict::kFeasible;
    return Verdict::kUnknown;
  }

  // The reports of a step, in index order: what follows never depends on their order.
  void ApplyReports() {
    std::sort(pending.begin(), pending.end());
    for (const auto& [candidate, verdict] : pending) {
      simulated.emplace(candidate, verdict);
      if (verdict == Verdict::kInfeasible) tightest_infeasible.Add(space.Options(candidate), Tighter);
      if (verdict == Verdict::kFeasible) {
        loosest_feasible.Add(space.Options(candidate), Looser);
        const double cost = space.Cost(candidate);
        if (!best || Cheaper(candidate, cost, *best, best_cost)) {
          best = candidate;
          best_cost = cost;
        }
      }
    }
    pending.clear();
  }

  void Ask(std::int64_t candidate) {
    if (std::find(prepared.begin(), prepared.end(), candidate) == prepared.end()) prepared.push_back(candidate);
  }

  // Settles every node that needs no simulation, cheapest first, and asks for the
  // candidates of the others until the batch is full.
  void StepBranchAndBound() {
    const auto batch = static_cast<std::size_t>(options.batch);
    auto it = open.begin();
    while (it != open.end() && prepared.size() < batch) {
      const Node node = *it;
      if (best && Cheaper(*best, best_cost, node.loosest, node.cost)) {
        open.erase(it, open.end());  // the rest cost at least as much: none can win
        break;
      }
      const std::int64_t tightest = node.loosest + tail[static_cast<std::size_t>(node.depth)];
      const Verdict t = Known(tightest);
      if (t == Verdict::kUnknown) {  // first: when it fails, the node is cut on one simulation
        Ask(tightest);
        ++it;
        continue;
      }
      if (t == Verdict::kInfeasible) {
        it = open.erase(it);
        continue;
      }
      const Verdict l = Known(node.loosest);
      if (l == Verdict::kUnknown) {
        Ask(node.loosest);
        ++it;
        continue;
      }
      it = open.erase(it);
      if (l == Verdict::kFeasible || node.depth == space.components()) continue;  // closed, or an undecided leaf
      const auto component = static_cast<std::size_t>(node.depth);
      for (int o = 0; o < space.options(node.depth); ++o) {
        const std::int64_t child = node.loosest + o * stride[component];
        open.insert(Node{space.Cost(child), child, node.depth + 1});
      }
      it = open.upper_bound(node);  // the children sort after the node, maybe before `it`
    }
    std::sort(prepared.begin(), prepared.end());
  }

  void Step() {
    ApplyReports();
    implications_current = false;
    prepared.clear();
    if (options.kind == SearchKind::kExhaustive) {
      const std::int64_t end = std::min(space.size(), next_exhaustive + options.batch);
      for (; next_exhaustive < end; ++next_exhaustive) prepared.push_back(next_exhaustive);
    } else {
      StepBranchAndBound();
    }
  }

  // Implications for every candidate from the decided simulated ones: one sweep from the
  // tightest down (infeasible spreads to looser neighbours) and one from the loosest up.
  void ComputeImplications() const {
    if (implications_current) return;
    const auto size = static_cast<std::size_t>(space.size());
    std::vector<char> infeasible(size, 0);
    std::vector<char> feasible(size, 0);
    for (const auto& [candidate, verdict] : simulated) {
      infeasible[static_cast<std::size_t>(candidate)] = verdict == Verdict::kInfeasible ? 1 : 0;
      feasible[static_cast<std::size_t>(candidate)] = verdict == Verdict::kFeasible ? 1 : 0;
    }
    const int k = space.components();
    for (std::size_t x = size; x-- > 0;) {
      if (infeasible[x]) continue;
      const std::vector<int> o = space.Options(static_cast<std::int64_t>(x));
      for (int c = 0; c < k && !infeasible[x]; ++c) {
        const auto step = static_cast<std::size_t>(stride[static_cast<std::size_t>(c)]);
        infeasible[x] = o[static_cast<std::size_t>(c)] + 1 < space.options(c) && infeasible[x + step];
      }
    }
    for (std::size_t x = 0; x < size; ++x) {
      if (feasible[x]) continue;
      const std::vector<int> o = space.Options(static_cast<std::int64_t>(x));
      for (int c = 0; c < k && !feasible[x]; ++c) {
        const auto step = static_cast<std::size_t>(stride[static_cast<std::size_t>(c)]);
        feasible[x] = o[static_cast<std::size_t>(c)] > 0 && feasible[x - step];
      }
    }
    implied.assign(size, static_cast<std::int8_t>(Verdict::kUnknown));
    for (std::size_t x = 0; x < size; ++x) {
      if (infeasible[x]) {
        implied[x] = static_cast<std::int8_t>(Verdict::kInfeasible);
      } else if (feasible[x]) {
        implied[x] = static_cast<std::int8_t>(Verdict::kFeasible);
      }
    }
    implications_current = true;
  }

  void CheckCandidate(std::int64_t candidate) const {
    if (candidate < 0 || candidate >= space.size()) {
      throw std::out_of_range("AllocationSearch: candidate " + std::to_string(candidate) + " of " +
                              std::to_string(space.size()));
    }
  }
};

AllocationSearch::AllocationSearch(const AllocationSpace& space, SearchOptions options)
    : state_(std::make_unique<State>(space, options)) {
  if (options.batch < 1) {
    throw std::invalid_argument("AllocationSearch: batch = " + std::to_string(options.batch) + ": allowed >= 1");
  }
  state_->Step();
}

AllocationSearch::~AllocationSearch() = default;

std::vector<std::int64_t> AllocationSearch::Next() {
  // Every candidate of the last batch is reported first.
  RINGTOL_CHECK(state_->outstanding.empty(), state_->outstanding.size());
  state_->outstanding = state_->prepared;
  state_->prepared.clear();
  return state_->outstanding;
}

void AllocationSearch::Report(std::int64_t candidate, Verdict verdict) {
  State& s = *state_;
  if (verdict != Verdict::kFeasible && verdict != Verdict::kInfeasible && verdict != Verdict::kUndecided) {
    throw std::invalid_argument("AllocationSearch::Report: candidate " + std::to_string(candidate) + " reported " +
                                std::string(NameOf(kVerdictNames, verdict)) +
                                ": allowed feasible, infeasible, undecided");
  }
  const auto it = std::find(s.outstanding.begin(), s.outstanding.end(), candidate);
  // Asked for in the last batch, and not reported yet.
  RINGTOL_CHECK(it != s.outstanding.end(), candidate, s.outstanding.size());
  s.outstanding.erase(it);
  s.pending.emplace_back(candidate, verdict);
  if (s.outstanding.empty()) s.Step();
}

bool AllocationSearch::done() const { return state_->outstanding.empty() && state_->prepared.empty(); }

std::optional<std::int64_t> AllocationSearch::best() const { return state_->best; }

Verdict AllocationSearch::verdict(std::int64_t candidate) const {
  const State& s = *state_;
  s.CheckCandidate(candidate);
  if (const auto it = s.simulated.find(candidate); it != s.simulated.end()) return it->second;
  s.ComputeImplications();
  return static_cast<Verdict>(s.implied[static_cast<std::size_t>(candidate)]);
}

Settlement AllocationSearch::settlement(std::int64_t candidate) const {
  const State& s = *state_;
  s.CheckCandidate(candidate);
  if (s.simulated.contains(candidate)) return Settlement::kSimulated;
  s.ComputeImplications();
  if (s.implied[static_cast<std::size_t>(candidate)] != static_cast<std::int8_t>(Verdict::kUnknown)) {
    return Settlement::kImplied;
  }
  if (s.best && s.space.Cost(candidate) >= s.best_cost) return Settlement::kCostlier;
  return Settlement::kNotVisited;
}

std::int64_t AllocationSearch::simulated() const { return static_cast<std::int64_t>(state_->simulated.size()); }

// ---------------------------------------------------------------------------------------
// Pareto front and the gain of common random numbers.

std::vector<std::int64_t> ParetoFront(std::span<const std::int64_t> candidates, std::span<const double> cost,
                                      std::span<const double> merit) {
  if (cost.size() != candidates.size() || merit.size() != candidates.size()) {
    throw std::invalid_argument("ParetoFront: " + std::to_string(candidates.size()) + " candidates, " +
                                std::to_string(cost.size()) + " costs, " + std::to_string(merit.size()) + " merits");
  }
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (!std::isnan(merit[i]) && !std::isnan(cost[i])) order.push_back(i);
  }
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (cost[a] != cost[b]) return cost[a] < cost[b];
    if (merit[a] != merit[b]) return merit[a] > merit[b];
    return candidates[a] < candidates[b];
  });
  // Sorted so, a point is on the front when its merit beats every cheaper point's and
  // equals the best of its own cost (equal points dominate neither way).
  std::vector<std::int64_t> front;
  double best_cheaper = -kInfinity;
  for (std::size_t g = 0; g < order.size();) {
    std::size_t end = g;
    while (end < order.size() && cost[order[end]] == cost[order[g]]) ++end;
    const double top = merit[order[g]];
    if (top > best_cheaper) {
      for (std::size_t i = g; i < end && merit[order[i]] == top; ++i) front.push_back(candidates[order[i]]);
      best_cheaper = top;
    }
    g = end;
  }
  return front;
}

double CommonRandomNumbersGain(std::span<const double> a, std::span<const double> b) {
  if (a.size() != b.size()) {
    throw std::invalid_argument("CommonRandomNumbersGain: " + std::to_string(a.size()) + " and " +
                                std::to_string(b.size()) + " samples");
  }
  std::vector<std::pair<double, double>> pairs;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (!std::isnan(a[i]) && !std::isnan(b[i])) pairs.emplace_back(a[i], b[i]);
  }
  if (pairs.size() < 2) return std::numeric_limits<double>::quiet_NaN();
  const double first_difference = pairs.front().first - pairs.front().second;
  if (std::all_of(pairs.begin(), pairs.end(),
                  [&](const auto& p) { return p.first - p.second == first_difference; })) {
    return kInfinity;
  }
  const double count = static_cast<double>(pairs.size());
  double mean_a = 0.0;
  double mean_b = 0.0;
  for (const auto& [x, y] : pairs) {
    mean_a += x;
    mean_b += y;
  }
  mean_a /= count;
  mean_b /= count;
  double sum_aa = 0.0;  // two-pass sums of squares: the differences may be tiny beside a and b
  double sum_bb = 0.0;
  double sum_dd = 0.0;
  for (const auto& [x, y] : pairs) {
    const double da = x - mean_a;
    const double db = y - mean_b;
    sum_aa += da * da;
    sum_bb += db * db;
    sum_dd += (da - db) * (da - db);
  }
  return (sum_aa + sum_bb) / sum_dd;
}

}  // namespace ringtol::analysis
