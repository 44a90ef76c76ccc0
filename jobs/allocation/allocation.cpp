#include "jobs/allocation/allocation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include "engine/check.h"
#include "jobs/inputs/scene_writer.h"

namespace ringtol::jobs {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInfinity = std::numeric_limits<double>::infinity();
// The screening rung's refusal of a path beyond its range: unknown, unlike a failure of
// the assembly itself, which every rung reports alike (solvers/validity.h).
constexpr SampleStatus kRefused = static_cast<SampleStatus>(solvers::Status::kBeyondLinearRange);
// The one output a rung bounds its own error of (SampleRecord::d_trajectory_error).
constexpr std::string_view kBoundedOutput = "d_trajectory_mm";

bool SameInputs(const std::vector<sampling::SampledInput>& a, const std::vector<sampling::SampledInput>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](const auto& x, const auto& y) {
    return x.name == y.name && x.quantity == y.quantity && x.component == y.component && x.source == y.source &&
           x.roller == y.roller && x.order == y.order;
  });
}

std::vector<std::string> StoredOutputs(const std::vector<analysis::Constraint>& constraints) {
  std::vector<std::string> outputs;
  for (const char* name : kOutputNames) {
    const bool named = std::any_of(constraints.begin(), constraints.end(),
                                   [&](const analysis::Constraint& c) { return c.output == name; });
    if (named) outputs.emplace_back(name);
  }
  return outputs;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Allocation

Allocation::Allocation(const std::filesystem::path& file)
    : plan_(ReadAllocationFile(file)),
      space_(plan_.Space()),
      stored_outputs_(StoredOutputs(plan_.constraints)),
      calibrations_(std::make_shared<sampling::CalibrationCache>()) {
  identity_.ringtol_version = RINGTOL_VERSION;
  identity_.catalogue_version = plan_.campaign.sampling.catalogue.version;
  identity_.allocation_path = file.string();
  identity_.allocation_file = plan_.text;
  identity_.base_scene = WriteScene(plan_.campaign.sampling.scene);
  identity_.error_motion_filter = plan_.campaign.sampling.scene.error_motion_filter;
  identity_.design = sampling::DesignName(plan_.campaign.sampling.design.kind);
  identity_.solver = solvers::SolverDescription(plan_.campaign.solver);
  identity_.screen = plan_.screen ? std::string(NameOf(solvers::kRungNames, *plan_.screen)) : "none";
  identity_.search = std::string(NameOf(analysis::kSearchKindNames, plan_.search.kind));
  identity_.seed = plan_.campaign.sampling.seed;
  identity_.samples = samples();
  identity_.first_samples = plan_.first_samples;
  identity_.confidence = plan_.confidence;
  for (const ComponentChoice& choice : plan_.components) {
    identity_.components.emplace_back(NameOf(kAllocatedComponentNames, choice.component));
    std::vector<AllocationIdentity::Option>& options = identity_.options.emplace_back();
    for (const AllocationOption& option : choice.options)
      options.push_back({option.class_name, std::string(NameOf(sampling::kToleranceModeNames, option.mode)),
                         option.tolerance, option.cost});
  }
  identity_.constraints = plan_.constraints;
  identity_.reference = plan_.reference == CostReference::kCurrent ? plan_.current : std::optional<std::int64_t>(0);
  // The loosest candidate's inputs stand for all: CandidateCampaign refuses any other.
  identity_.inputs = CandidateCampaign(0, EvaluationRole::kConfirm).identity().inputs;
}

Allocation::~Allocation() = default;

const Campaign& Allocation::CandidateCampaign(std::int64_t candidate, EvaluationRole role) const {
  const auto key = std::make_pair(candidate, role);
  {
    std::lock_guard lock(mutex_);
    if (const auto found = campaigns_.find(key); found != campaigns_.end()) return *found->second;
  }
  CampaignPlan plan = plan_.campaign;
  plan.sampling.tolerances = plan_.Tolerances(candidate);
  plan.spec.clear();
  if (role == EvaluationRole::kScreen) plan.solver.rung = *plan_.screen;
  // The life values cost what a sample's revolution costs again; only a constraint on one
  // of them pays for it (the other outputs are not stored).
  plan.solver.simulation.life = std::any_of(stored_outputs_.begin(), stored_outputs_.end(), [](const std::string& name) {
    const std::size_t output = OutputIndex(name);
    return output < kOutputCount && IsLifeOutput(output);
  });
  const std::vector<int> options = space_.Options(candidate);
  std::string name = fmt::format("{}, candidate {} (", plan_.campaign.file.string(), candidate);
  for (std::size_t k = 0; k < plan_.components.size(); ++k) {
    name += fmt::format("{}{} {}", k == 0 ? "" : ", ", NameOf(kAllocatedComponentNames, plan_.components[k].component),
                        plan_.components[k].options[static_cast<std::size_t>(options[k])].class_name);
  }
  name += ")";
  auto campaign = std::make_unique<Campaign>(std::move(plan), name, calibrations_);
  // ReadAllocationFile refuses options that would draw other inputs.
  RINGTOL_CHECK(identity_.inputs.empty() || SameInputs(campaign->identity().inputs, identity_.inputs), name,
                campaign->identity().inputs.size(), identity_.inputs.size());
  std::lock_guard lock(mutex_);
  const auto [at, inserted] = campaigns_.emplace(key, std::move(campaign));
  return *at->second;
}

std::vector<double> Allocation::DesignPoints() const {
  const Campaign& campaign = CandidateCampaign(0, EvaluationRole::kConfirm);
  sampling::Design design(campaign.sampling().design.dimension(), campaign.sampling().design.options());
  const auto d = static_cast<std::size_t>(design.dimension());
  std::vector<double> points(static_cast<std::size_t>(samples()) * d);
  for (std::int64_t i = 0; i < samples(); ++i)
    design.Point(i, std::span<double>(points).subspan(static_cast<std::size_t>(i) * d, d));
  return points;
}

// ---------------------------------------------------------------------------------------
// AllocationEvaluator

AllocationEvaluator::AllocationEvaluator(const Allocation& allocation) : allocation_(&allocation) {}
AllocationEvaluator::~AllocationEvaluator() = default;

SampleRecord AllocationEvaluator::Evaluate(EvaluationRole role, std::int64_t candidate, std::int64_t sample) {
  // An evaluator lives for one round, whose candidates are one batch; the bound only
  // matters for batches larger than this, where it trades rebuilding for memory.
  constexpr std::size_t kKeptEvaluators = 64;
  const auto key = std::make_pair(candidate, role);
  auto found = evaluators_.find(key);
  if (found == evaluators_.end()) {
    if (evaluators_.size() >= kKeptEvaluators) evaluators_.clear();
    found = evaluators_
                .emplace(key, std::make_unique<SampleEvaluator>(allocation_->CandidateCampaign(candidate, role)))
                .first;
  }
  SampleRecord record = found->second->Evaluate(sample);
  record.u.clear();
  record.values.clear();
  return record;
}

// ---------------------------------------------------------------------------------------
// AllocationDriver

namespace {

// Where one candidate of the current batch stands.
struct Progress {
  std::int64_t candidate = 0;
  EvaluationRole role = EvaluationRole::kConfirm;
  std::int64_t judged = 0;  // samples of `role` already judged (the previous stage's end)
  std::int64_t target = 0;  // the current stage's end
  bool settled = false;
};

}  // namespace

struct AllocationDriver::State {
  const Allocation* allocation;
  analysis::AllocationSearch search;
  std::vector<Progress> batch;
  std::vector<CandidateOutcome> outcomes;
  std::vector<std::int64_t> covered_screen;   // samples simulated per candidate and role
  std::vector<std::int64_t> covered_confirm;
  std::int64_t rounds = 0;
  bool done = false;

  explicit State(const Allocation& a)
      : allocation(&a),
        search(a.space(), a.plan().search),
        outcomes(static_cast<std::size_t>(a.space().size())),
        covered_screen(outcomes.size(), 0),
        covered_confirm(outcomes.size(), 0) {}

  std::int64_t FirstStage() const { return std::min(allocation->plan().first_samples, allocation->samples()); }

  void Start(std::int64_t candidate) {
    Progress p;
    p.candidate = candidate;
    p.role = allocation->plan().screen ? EvaluationRole::kScreen : EvaluationRole::kConfirm;
    p.target = FirstStage();
    batch.push_back(p);
  }

  // Judges `p`'s samples [0, p.target) in its role and moves it on.
  void Judge(Progress& p, const StoredSamples& samples) {
    const AllocationPlan& plan = allocation->plan();
    const std::int64_t n = p.target;
    const std::vector<SampleStatus> status = samples.Status(p.role, p.candidate, 0, n);
    const bool screen = p.role == EvaluationRole::kScreen;
    std::vector<double> bound;
    if (screen) bound = samples.ErrorBound(p.candidate, 0, n);

    std::map<std::string, std::vector<double>> values;
    for (const std::string& output : allocation->stored_outputs()) {
      std::vector<double> v = samples.Output(p.role, output, p.candidate, 0, n);
      for (std::size_t i = 0; i < v.size(); ++i)
        if (status[i] != SampleStatus::kOk) v[i] = kNaN;
      values.emplace(output, std::move(v));
    }
    std::vector<analysis::ConstraintJudgement> judgements;
    std::vector<analysis::Verdict> verdicts;
    for (const analysis::Constraint& constraint : plan.constraints) {
      const std::vector<double>& v = values.at(constraint.output);
      if (screen && constraint.output != kBoundedOutput) {
        // The screening rung says nothing of an output it does not bound.
        analysis::ConstraintJudgement unknown;
        unknown.estimate = unknown.interval.lower = unknown.interval.upper = kNaN;
        unknown.samples = n;
        judgements.push_back(unknown);
        verdicts.push_back(analysis::Verdict::kUnknown);
        continue;
      }
      std::vector<double> lower = v;
      std::vector<double> upper = v;
      if (screen) {
        for (std::size_t i = 0; i < v.size(); ++i) {
          lower[i] = v[i] - bound[i];
          upper[i] = v[i] + bound[i];
          // A path the linear rung refuses says nothing of the exact one: anywhere, not
          // beyond the limit as a failed assembly would be.
          if (status[i] == kRefused) {
            lower[i] = -kInfinity;
            upper[i] = kInfinity;
          }
        }
      }
      judgements.push_back(analysis::JudgeConstraint(constraint, v, lower, upper, plan.confidence));
      verdicts.push_back(judgements.back().verdict);
    }
    const analysis::Verdict verdict = analysis::CombineVerdicts(verdicts);
    (screen ? covered_screen : covered_confirm)[static_cast<std::size_t>(p.candidate)] = n;

    const bool decided = verdict == analysis::Verdict::kFeasible || verdict == analysis::Verdict::kInfeasible;
    if (decided || (!screen && n >= allocation->samples())) {
      Settle(p, decided ? verdict : analysis::Verdict::kUndecided, std::move(judgements), values, status, n);
      return;
    }
    if (screen) {
      p.role = EvaluationRole::kConfirm;
      p.judged = 0;
      p.target = FirstStage();
    } else {
      p.judged = n;
      p.target = std::min(2 * n, allocation->samples());
    }
  }

  void Settle(Progress& p, analysis::Verdict verdict, std::vector<analysis::ConstraintJudgement> judgements,
              const std::map<std::string, std::vector<double>>& values, const std::vector<SampleStatus>& status,
              std::int64_t n) {
    p.settled = true;
    search.Report(p.candidate, verdict);
    CandidateOutcome& outcome = outcomes[static_cast<std::size_t>(p.candidate)];
    outcome.settled_by = p.role;
    outcome.samples = n;
    outcome.constraints = std::move(judgements);
    std::int64_t within = 0;
    std::int64_t trials = 0;
    for (std::int64_t i = 0; i < n; ++i) {
      if (status[static_cast<std::size_t>(i)] == kRefused) continue;  // unknown, not outside
      bool all = true;
      for (const analysis::Constraint& constraint : allocation->plan().constraints) {
        const double v = values.at(constraint.output)[static_cast<std::size_t>(i)];
        all = all && v <= constraint.upper;  // NaN (failed) is outside
      }
      within += all ? 1 : 0;
      ++trials;
    }
    if (trials > 0) outcome.yield = analysis::EstimateProportion(within, trials, allocation->plan().confidence);
  }
};

AllocationDriver::AllocationDriver(const Allocation& allocation) : state_(std::make_unique<State>(allocation)) {}
AllocationDriver::~AllocationDriver() = default;

bool AllocationDriver::done() const { return state_->done; }
std::int64_t AllocationDriver::simulated() const { return state_->search.simulated(); }
std::int64_t AllocationDriver::rounds() const { return state_->rounds; }

std::vector<RoundSegment> AllocationDriver::Advance(const StoredSamples& samples) {
  State& s = *state_;
  while (!s.done) {
    if (std::all_of(s.batch.begin(), s.batch.end(), [](const Progress& p) { return p.settled; })) {
      s.batch.clear();
      for (const std::int64_t candidate : s.search.Next()) s.Start(candidate);
      if (s.batch.empty()) {
        s.done = true;
        break;
      }
    }
    std::vector<RoundSegment> round;
    for (const Progress& p : s.batch) {
      if (!p.settled && !samples.AllDone(p.role, p.candidate, p.judged, p.target))
        round.push_back({p.role, p.candidate, p.judged, p.target});
    }
    if (!round.empty()) return round;
    for (Progress& p : s.batch) {
      if (!p.settled) s.Judge(p, samples);
    }
    ++s.rounds;
  }
  return {};
}

AllocationOutcome AllocationDriver::Outcome(const StoredSamples& samples) const {
  const State& s = *state_;
  const Allocation& allocation = *s.allocation;
  const analysis::AllocationSpace& space = allocation.space();
  const auto count = static_cast<std::size_t>(space.size());
  AllocationOutcome outcome;
  outcome.complete = s.done;
  outcome.candidates = s.outcomes;
  const std::optional<std::int64_t> reference = allocation.identity().reference;
  const double reference_cost = reference ? space.Cost(*reference) : kNaN;

  std::vector<std::int64_t> simulated;
  for (std::size_t c = 0; c < count; ++c) {
    const auto index = static_cast<std::int64_t>(c);
    CandidateOutcome& candidate = outcome.candidates[c];
    candidate.options = space.Options(index);
    candidate.cost = space.Cost(index);
    candidate.relative_cost = candidate.cost / reference_cost;
    candidate.verdict = s.search.verdict(index);
    candidate.settlement = s.search.settlement(index);
    if (candidate.settlement == analysis::Settlement::kSimulated) {
      simulated.push_back(index);
      if (candidate.settled_by == EvaluationRole::kScreen) ++outcome.settled_by_screen;
    }
    outcome.samples_screen += s.covered_screen[c];
    outcome.samples_confirm += s.covered_confirm[c];
  }
  outcome.simulated = static_cast<std::int64_t>(simulated.size());
  for (CandidateOutcome& candidate : outcome.candidates) {
    if (candidate.settlement != analysis::Settlement::kImplied) continue;
    const std::int64_t index = space.Candidate(candidate.options);
    for (const std::int64_t source : simulated) {
      const analysis::Verdict verdict = s.search.verdict(source);
      const bool implies = (verdict == analysis::Verdict::kInfeasible && space.AtLeastAsTight(source, index)) ||
                           (verdict == analysis::Verdict::kFeasible && space.AtLeastAsTight(index, source));
      if (implies && verdict == candidate.verdict) {
        candidate.implied_by = source;
        break;
      }
    }
  }

  outcome.recommendation = s.search.best();
  auto by_cost = [&](std::int64_t a, std::int64_t b) {
    const double ca = space.Cost(a);
    const double cb = space.Cost(b);
    return ca != cb ? ca < cb : a < b;
  };
  std::vector<std::int64_t> feasible;
  for (const std::int64_t c : simulated)
    if (s.search.verdict(c) == analysis::Verdict::kFeasible && c != outcome.recommendation) feasible.push_back(c);
  std::sort(feasible.begin(), feasible.end(), by_cost);
  for (std::size_t k = 0; k < feasible.size() && k < 2; ++k) outcome.alternatives.push_back(feasible[k]);
  for (const std::int64_t c : simulated) {
    const bool cheaper = !outcome.recommendation || by_cost(c, *outcome.recommendation);
    if (s.search.verdict(c) == analysis::Verdict::kUndecided && cheaper) outcome.undecided_cheaper.push_back(c);
  }
  std::sort(outcome.undecided_cheaper.begin(), outcome.undecided_cheaper.end(), by_cost);

  std::vector<double> costs;
  std::vector<double> yields;
  for (const std::int64_t c : simulated) {
    costs.push_back(space.Cost(c));
    yields.push_back(outcome.candidates[static_cast<std::size_t>(c)].yield.value);
  }
  outcome.front = analysis::ParetoFront(simulated, costs, yields);

  const std::int64_t tightest = space.size() - 1;
  if (s.done && !outcome.recommendation && s.search.settlement(tightest) == analysis::Settlement::kSimulated) {
    const CandidateOutcome& t = outcome.candidates[static_cast<std::size_t>(tightest)];
    for (std::size_t j = 0; j < t.constraints.size(); ++j) {
      const analysis::Verdict v = t.constraints[j].verdict;
      if (v == analysis::Verdict::kInfeasible || v == analysis::Verdict::kUndecided)
        outcome.binding.push_back(static_cast<int>(j));
    }
  }

  // Common random numbers at work: the recommendation against its nearest looser
  // neighbour (one option looser in one component; of those simulated, the costliest, so
  // the closest in cost), on the first constraint's output over the samples both have in
  // one role (the confirming rung's where both have two or more).
  outcome.common_random_numbers_gain = kNaN;
  if (outcome.recommendation && !allocation.plan().constraints.empty()) {
    const std::int64_t r = *outcome.recommendation;
    std::optional<std::int64_t> neighbour;
    std::vector<int> options = space.Options(r);
    for (std::size_t k = 0; k < options.size(); ++k) {
      if (options[k] == 0) continue;
      --options[k];
      const std::int64_t n = space.Candidate(options);
      ++options[k];
      if (s.search.settlement(n) == analysis::Settlement::kSimulated && (!neighbour || by_cost(*neighbour, n)))
        neighbour = n;
    }
    if (neighbour) {
      const std::string& output = allocation.plan().constraints.front().output;
      const auto rc = static_cast<std::size_t>(r);
      const auto nc = static_cast<std::size_t>(*neighbour);
      EvaluationRole role = EvaluationRole::kConfirm;
      std::int64_t n = std::min(s.covered_confirm[rc], s.covered_confirm[nc]);
      if (n < 2) {
        role = EvaluationRole::kScreen;
        n = std::min(s.covered_screen[rc], s.covered_screen[nc]);
      }
      if (n >= 2) {
        outcome.common_random_numbers_gain = analysis::CommonRandomNumbersGain(
            samples.Output(role, output, r, 0, n), samples.Output(role, output, *neighbour, 0, n));
      }
    }
  }
  return outcome;
}

}  // namespace ringtol::jobs
