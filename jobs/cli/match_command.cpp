#include "jobs/cli/match_command.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <set>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "analysis/order_statistics.h"
#include "jobs/campaign/campaign.h"
#include "jobs/campaign/campaign_file.h"
#include "jobs/inputs/input_error.h"
#include "jobs/report/report_text.h"
#include "sampling/random.h"
#include "solvers/simulation.h"

namespace ringtol::jobs {
namespace {

using Assignment = std::vector<std::size_t>;  // slot k (the batch's k-th roller) takes batch part [k]

// One assignment of the search, judged on every base assembly (the scene as it stands, or
// the draws of the file's other tolerances): the mean of its output over those whose
// simulation gave it, the worst, the share within the spec limit, and how many failed, why.
struct Matched {
  Assignment parts;
  double value = 0.0;  // NaN when none gave the output
  double worst = 0.0;
  double within = 0.0;   // share of the bases within the spec limit (failures outside)
  std::int64_t failed = 0;
  std::string failure;  // the first failed base's status and message; empty when none failed
};

// B! / (B - Z)!, or `cap` + 1 once it exceeds `cap`.
std::int64_t AssignmentCount(std::size_t batch, std::size_t slots, std::int64_t cap) {
  std::int64_t count = 1;
  for (std::size_t k = 0; k < slots; ++k) {
    const auto factor = static_cast<std::int64_t>(batch - k);
    if (count > (cap + 1) / factor) return cap + 1;
    count *= factor;
  }
  return count;
}

// The search: evaluates assignments once each, whatever order it meets them in, a list at a
// time on `threads` threads (each with its own solver); an assignment's result does not
// depend on the thread or the order.
class Search {
 public:
  Search(const CampaignPlan& plan, std::vector<engine::Scene> bases, std::vector<std::size_t> rollers,
         std::size_t output, std::optional<double> limit, solvers::SimulationOptions options, int threads)
      : plan_(plan),
        bases_(std::move(bases)),
        rollers_(std::move(rollers)),
        output_(output),
        limit_(limit),
        options_(std::move(options)),
        threads_(threads) {}

  // The results of `list`, in its order.
  std::vector<Matched> Evaluate(const std::vector<Assignment>& list) {
    std::vector<Assignment> todo;
    std::set<Assignment> listed;  // a list may name one twice (random draws)
    for (const Assignment& parts : list) {
      if (!done_.contains(parts) && listed.insert(parts).second) todo.push_back(parts);
    }
    std::vector<Matched> judged(todo.size());
    std::atomic<std::size_t> next{0};
    const auto work = [&] {
      const std::unique_ptr<solvers::Solver> solver = solvers::MakeSolver(plan_.solver);
      for (std::size_t k = next++; k < todo.size(); k = next++) judged[k] = Judge(todo[k], *solver);
    };
    const auto helpers = static_cast<std::size_t>(std::max(1, threads_)) - 1;
    std::vector<std::jthread> pool;
    for (std::size_t t = 0; t < std::min(helpers, todo.size()); ++t) pool.emplace_back(work);
    work();
    pool.clear();  // joins
    for (Matched& matched : judged) done_.emplace(matched.parts, std::move(matched));
    std::vector<Matched> out;
    for (const Assignment& parts : list) out.push_back(done_.at(parts));
    return out;
  }

  std::vector<Matched> Evaluated() const {
    std::vector<Matched> all;
    for (const auto& [parts, matched] : done_) all.push_back(matched);
    return all;
  }

 private:
  Matched Judge(const Assignment& parts, const solvers::Solver& solver) const {
    Matched matched{parts, 0.0, 0.0, 0.0, 0, {}};
    std::int64_t given = 0;
    std::int64_t within = 0;
    for (const engine::Scene& base : bases_) {
      const engine::Scene scene =
          sampling::WithRollerParts(base, *plan_.sampling.tolerances.roller_population, rollers_, parts);
      SampleRecord record;
      try {
        RecordSimulation(solvers::Simulate(scene, solver, options_), options_.life, record);
      } catch (const std::exception& e) {
        record.status = SampleStatus::kException;
        record.message = e.what();
      }
      std::string failure;
      if (record.status != SampleStatus::kOk) {
        failure = fmt::format("{}: {}", SampleStatusName(record.status), record.message);
      } else if (std::isnan(record.outputs[output_])) {
        failure = "no life values: a roller left the bore";  // only a life output can be missing
      }
      if (!failure.empty()) {
        if (matched.failed++ == 0) matched.failure = std::move(failure);
        continue;
      }
      const double value = record.outputs[output_];
      matched.value += value;
      matched.worst = given++ == 0 ? value : std::max(matched.worst, value);
      within += limit_ && value <= *limit_ ? 1 : 0;
    }
    matched.value = given > 0 ? matched.value / static_cast<double>(given) : std::numeric_limits<double>::quiet_NaN();
    if (given == 0) matched.worst = matched.value;
    matched.within = static_cast<double>(within) / static_cast<double>(bases_.size());
    return matched;
  }

  const CampaignPlan& plan_;
  std::vector<engine::Scene> bases_;  // what each assignment's parts are fitted to
  std::vector<std::size_t> rollers_;  // the scene rollers the slots are
  std::size_t output_;
  std::optional<double> limit_;
  solvers::SimulationOptions options_;
  int threads_;
  std::map<Assignment, Matched> done_;
};

// Fewer failed bases first, then the lower mean output.
bool Better(const Matched& a, const Matched& b) {
  if (a.failed != b.failed) return a.failed < b.failed;
  if (std::isnan(a.value) != std::isnan(b.value)) return !std::isnan(a.value);
  return a.value != b.value ? a.value < b.value : a.parts < b.parts;
}

// The assemblies every assignment is fitted to: the scene as it stands (draws = 0), or the
// first `draws` samples of the file's design with its other tolerances ([tolerances.*],
// [population.ring]; the batch left out), the same for every assignment (common random
// numbers). Throws InputError where the file draws nothing else or has fewer samples.
std::vector<engine::Scene> Bases(const CampaignPlan& plan, std::int64_t draws) {
  if (draws == 0) return {plan.sampling.scene};
  const std::string file = plan.file.string();
  if (draws > plan.sampling.samples) {
    throw InputError(fmt::format("--draws {}: more than the {} samples of {}'s design", draws, plan.sampling.samples,
                                 file));
  }
  CampaignPlan others = plan;
  others.sampling.tolerances.roller_population.reset();
  others.sampling.tolerances.batch_rollers.clear();
  others.sampling.population.clear();
  const sampling::AssemblyTolerances& t = others.sampling.tolerances;
  const auto any = [](const auto& list) {
    return std::any_of(list.begin(), list.end(), [](const auto& entry) { return entry.has_value(); });
  };
  if (!t.ring && !t.ring_population && !any(t.roller_shapes) && !any(t.roller_positions) && !any(t.springs)) {
    throw InputError(file + ": --draws draws the file's other tolerances, and it has none beside [population.rollers]");
  }
  const Campaign campaign(std::move(others), file, nullptr);
  SampleDrawer drawer(campaign);
  std::vector<engine::Scene> bases;
  for (std::int64_t k = 0; k < draws; ++k) {
    std::optional<sampling::SampledAssembly> assembly;
    const SampleRecord drawn = drawer.Draw(k, &assembly);
    if (!assembly) throw InputError(fmt::format("{}: sample {} cannot be drawn: {}", file, k, drawn.message));
    bases.push_back(std::move(assembly->scene));
  }
  return bases;
}

void EveryAssignment(std::size_t batch, Assignment& parts, std::vector<bool>& used, std::size_t slot,
                     std::vector<Assignment>& all) {
  if (slot == parts.size()) {
    all.push_back(parts);
    return;
  }
  for (std::size_t p = 0; p < batch; ++p) {
    if (used[p]) continue;
    used[p] = true;
    parts[slot] = p;
    EveryAssignment(batch, parts, used, slot + 1, all);
    used[p] = false;
  }
}

// `budget` assignments drawn uniformly (slot i among the parts left), reproducibly from the
// campaign's seed; returns them in draw order.
std::vector<Assignment> RandomAssignments(std::size_t batch, std::size_t slots, std::int64_t budget, std::uint64_t seed) {
  std::vector<Assignment> drawn;
  for (std::int64_t k = 0; k < budget; ++k) {
    std::vector<std::size_t> left(batch);
    std::iota(left.begin(), left.end(), std::size_t{0});
    Assignment parts(slots);
    for (std::size_t i = 0; i < slots; ++i) {
      parts[i] = sampling::TakePart(
          left, sampling::RandomUnit(seed, sampling::RandomStream::kMatch, static_cast<std::uint64_t>(k), i, 0));
    }
    drawn.push_back(std::move(parts));
  }
  return drawn;
}

// From `start`, the best of every move of one slot's part (to a part left in the batch, or
// a swap with another slot), repeated while a move lowers the output. Returns the moves
// made.
int SwapDescent(std::size_t batch, Assignment current, Search& search) {
  int moves = 0;
  for (bool improved = true; improved;) {
    improved = false;
    std::vector<Assignment> neighbours = {current};
    for (std::size_t slot = 0; slot < current.size(); ++slot) {
      for (std::size_t p = 0; p < batch; ++p) {
        if (p == current[slot]) continue;
        Assignment moved = current;
        const auto other = std::find(moved.begin(), moved.end(), p);
        if (other != moved.end()) *other = moved[slot];
        moved[slot] = p;
        neighbours.push_back(std::move(moved));
      }
    }
    const std::vector<Matched> tried = search.Evaluate(neighbours);
    const Matched& best = *std::min_element(tried.begin(), tried.end(), Better);
    if (best.parts != current) {
      current = best.parts;
      improved = true;
      ++moves;
    }
  }
  return moves;
}

std::string Named(const Matched& m, const engine::Scene& scene, std::span<const std::size_t> rollers,
                  const sampling::PartPopulation& batch) {
  std::string text;
  for (std::size_t k = 0; k < m.parts.size(); ++k) {
    text += fmt::format("{}{} {}", k == 0 ? "" : ", ", scene.rollers[rollers[k]].name, batch.parts[m.parts[k]].name);
  }
  return text;
}

}  // namespace

int RunMatch(const MatchCommand& command, std::ostream& out) {
  const std::string file = command.file.string();
  CampaignPlan plan = ReadCampaignFile(command.file);
  const std::optional<sampling::PartPopulation>& batch = plan.sampling.tolerances.roller_population;
  if (!batch || batch->draw != sampling::PopulationDraw::kResample) {
    throw InputError(file + ": ringtol match assigns a measured batch's rollers: the file needs [population.rollers] "
                            "with draw = \"resample\"");
  }
  const std::string name =
      command.output.value_or(plan.spec.empty() ? std::string("d_trajectory_mm") : plan.spec.front().output);
  const std::size_t output = OutputIndex(name);
  if (output == kOutputCount) {
    throw InputError(fmt::format("--output {}: not an output; allowed: {}", name, fmt::join(kOutputNames, ", ")));
  }
  solvers::SimulationOptions options = plan.solver.simulation;
  options.keep_trajectory = false;
  // The life costs 40 % of a sample: read it only for a life output.
  if (IsLifeOutput(output) && !options.life) {
    throw InputError(fmt::format("{}: --output {} is a life output, and the file sets [outputs] life = false", file, name));
  }
  options.life = IsLifeOutput(output);
  const std::optional<double> limit = [&]() -> std::optional<double> {
    for (const SpecLimit& spec : plan.spec) {
      if (spec.output == name) return spec.upper;
    }
    return std::nullopt;
  }();

  const std::size_t parts = batch->parts.size();
  const std::vector<std::size_t> rollers =
      sampling::BatchRollers(plan.sampling.tolerances, plan.sampling.scene.rollers.size());
  const std::size_t slots = rollers.size();
  const std::int64_t count = AssignmentCount(parts, slots, command.exhaustive_limit);
  const bool exhaustive = count <= command.exhaustive_limit;
  const int threads =
      command.threads > 0 ? command.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  Search search(plan, Bases(plan, command.draws), rollers, output, limit, options, threads);
  std::vector<Matched> random_choice;  // what choosing at random gives: every assignment, or the drawn ones
  int moves = 0;
  if (exhaustive) {
    Assignment assignment(slots);
    std::vector<bool> used(parts, false);
    std::vector<Assignment> all;
    EveryAssignment(parts, assignment, used, 0, all);
    random_choice = search.Evaluate(all);
  } else {
    random_choice = search.Evaluate(RandomAssignments(parts, slots, command.budget, plan.sampling.seed));
    const Matched start = *std::min_element(random_choice.begin(), random_choice.end(), Better);
    moves = SwapDescent(parts, start.parts, search);
  }
  std::vector<Matched> ranked = search.Evaluated();
  std::sort(ranked.begin(), ranked.end(), Better);
  const Matched& best = ranked.front();

  std::vector<double> values;
  std::int64_t failed = 0;
  double within_sum = 0.0;
  for (const Matched& m : random_choice) {
    within_sum += m.within;
    if (m.failed > 0) ++failed;
    if (!std::isnan(m.value)) values.push_back(m.value);
  }
  std::sort(values.begin(), values.end());
  const double mean = values.empty() ? std::numeric_limits<double>::quiet_NaN()
                                     : std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
  const double median = analysis::Median(values);
  const double worst = values.empty() ? std::numeric_limits<double>::quiet_NaN() : values.back();
  const auto trials = static_cast<std::int64_t>(random_choice.size());
  const double within = trials > 0 ? within_sum / static_cast<double>(trials) : 0.0;
  const std::string over = command.draws > 0 ? fmt::format(" mean over {} assemblies", command.draws) : std::string();
  const std::int64_t total = AssignmentCount(parts, slots, std::numeric_limits<std::int64_t>::max() - 1);
  const std::string assignments =
      total < std::numeric_limits<std::int64_t>::max() ? fmt::format("{}", total) : std::string("more than 9.2e18");
  const std::string search_text =
      exhaustive ? fmt::format("exhaustive: all {} assignments of {} parts to {} rollers", count, parts, slots)
                 : fmt::format("heuristic ({} assignments of {} parts to {} rollers, more than --exhaustive-limit {}): "
                               "{} drawn at random, then {} swap moves from the best; {} assemblies simulated, the "
                               "best not proven optimal",
                               assignments, parts, slots, command.exhaustive_limit, command.budget, moves, ranked.size());
  const std::string unit = OutputNamed(name).unit;
  const auto gain = [&](double reference) {
    return reference > 0.0 ? 100.0 * (reference - best.value) / reference : 0.0;
  };

  if (command.json) {
    nlohmann::json ranked_json = nlohmann::json::array();
    for (std::size_t k = 0; k < ranked.size() && k < static_cast<std::size_t>(command.top); ++k) {
      nlohmann::json fitted = nlohmann::json::object();
      for (std::size_t i = 0; i < slots; ++i) {
        fitted[plan.sampling.scene.rollers[rollers[i]].name] = batch->parts[ranked[k].parts[i]].name;
      }
      const auto number = [](double x) { return std::isnan(x) ? nlohmann::json(nullptr) : nlohmann::json(x); };
      nlohmann::json entry = {{"rollers", fitted},      {"value", number(ranked[k].value)},
                              {"worst", number(ranked[k].worst)}, {"failed", ranked[k].failed},
                              {"failure", ranked[k].failure}};
      if (limit) entry["within_spec"] = ranked[k].within;
      ranked_json.push_back(std::move(entry));
    }
    nlohmann::json random = {{"assignments", trials}, {"failed", failed}, {"mean", mean}, {"median", median},
                             {"worst", worst}};
    if (limit) random["within_spec"] = within;
    nlohmann::json json;
    json["output"] = name;
    json["draws"] = command.draws;
    json["upper_spec_limit"] = limit ? nlohmann::json(*limit) : nlohmann::json(nullptr);
    json["search"] = {{"exhaustive", exhaustive},
                      {"assignments", exhaustive ? nlohmann::json(count) : nlohmann::json(nullptr)},
                      {"simulated", ranked.size()},
                      {"description", search_text}};
    json["best"] = ranked_json.front();
    json["ranked"] = ranked_json;
    json["random_choice"] = random;
    json["gain_over_median_percent"] = gain(median);
    json["gain_over_mean_percent"] = gain(mean);
    out << json.dump(2) << "\n";
    return 0;
  }
  fmt::print(out, "match             {}: {} of {} measured rollers onto {} of the scene's {} rollers, {}\n", file, slots,
             parts, slots, plan.sampling.scene.rollers.size(),
             command.draws > 0 ? fmt::format("each assignment on the same {} assemblies of the file's other tolerances",
                                             command.draws)
                               : std::string("as the scene stands"));
  fmt::print(out, "search            {}\n", search_text);
  const auto judged = [&](const Matched& m) {
    std::string text = fmt::format("{} {:.5g} {}{}", name, m.value, unit, over);
    if (command.draws > 0) {
      text += fmt::format(" (worst {:.5g}{})", m.worst,
                          limit ? fmt::format("; {} within {:g}", Percent(m.within), *limit) : std::string());
    } else if (limit) {
      text += m.value <= *limit ? fmt::format(" (within {:g})", *limit) : fmt::format(" (beyond {:g})", *limit);
    }
    if (m.failed > 0) text += fmt::format("; {} of {} failed, first {}", m.failed, std::max<std::int64_t>(command.draws, 1), m.failure);
    return text;
  };
  fmt::print(out, "best              {}: {}\n", Named(best, plan.sampling.scene, rollers, *batch), judged(best));
  fmt::print(out, "random choice     {} {:.5g} median, {:.5g} mean, {:.5g} worst over {} assignments{}{}\n", name, median,
             mean, worst, trials, failed > 0 ? fmt::format(", {} failed", failed) : std::string(),
             limit ? fmt::format("; {} within {:g}", Percent(within), *limit) : std::string());
  fmt::print(out, "gain              {:.5g} {} below the median random choice ({:.1f} %), {:.5g} below the mean ({:.1f} %)\n",
             median - best.value, unit, gain(median), mean - best.value, gain(mean));
  for (std::size_t k = 0; k < ranked.size() && k < static_cast<std::size_t>(command.top); ++k) {
    fmt::print(out, "{}{}: {}\n", k == 0 ? "ranked            " : kSummaryIndent, Named(ranked[k], plan.sampling.scene, rollers, *batch),
               command.draws == 0 && ranked[k].failed > 0 ? ranked[k].failure : judged(ranked[k]));
  }
  return 0;
}

}  // namespace ringtol::jobs
