#include "jobs/report/allocation_summary.h"

#include <algorithm>
#include <cmath>
#include <string_view>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "jobs/campaign/sample_record.h"
#include "jobs/report/report_text.h"

namespace ringtol::jobs {
namespace {

// A yield judgement's percentage, to the hundredths its margin is given in.
std::string PercentToHundredths(double fraction) { return fmt::format("{:.2f} %", 100 * fraction); }

std::string Judgement(const analysis::Constraint& constraint, const analysis::ConstraintJudgement& j, double confidence) {
  if (j.verdict == analysis::Verdict::kUnknown) return "not judged (the screen bounds only d_trajectory_mm)";
  if (constraint.kind == analysis::ConstraintKind::kQuantile) {
    const std::string_view unit = OutputNamed(constraint.output).unit;
    return fmt::format("{:.4g} {}, {:.0f} % interval [{:.4g}, {:.4g}] {}", j.estimate, unit, 100 * confidence,
                       j.interval.lower, j.interval.upper, unit);
  }
  return fmt::format("{}, {:.0f} % interval [{}, {}]", PercentToHundredths(j.estimate), 100 * confidence, PercentToHundredths(j.interval.lower),
                     PercentToHundredths(j.interval.upper));
}

std::string MarginText(const analysis::Constraint& constraint, const analysis::ConstraintJudgement& j) {
  const double margin = Margin(constraint, j);
  if (constraint.kind == analysis::ConstraintKind::kYield)
    return fmt::format("{:.2f} points {} the least", 100 * std::abs(margin), margin >= 0 ? "above" : "below");
  const std::string_view unit = OutputNamed(constraint.output).unit;
  if (unit == "mm")
    return fmt::format("{:.1f} um {} the limit", 1000 * std::abs(margin), margin >= 0 ? "within" : "beyond");
  return fmt::format("{:.4g} {} {} the limit", std::abs(margin), unit, margin >= 0 ? "within" : "beyond");
}

std::string CostText(const AllocationIdentity& identity, const AllocationOutcome& outcome, const CandidateOutcome& c) {
  std::string text = fmt::format("{:.4g}", c.cost);
  if (identity.reference) {
    const bool loosest = *identity.reference == 0;
    text += fmt::format(": {:.2f} x the {}", c.relative_cost, loosest ? "loosest candidate" : "current design");
    if (!loosest && !outcome.candidates.empty() && outcome.candidates.front().cost > 0)
      text += fmt::format(", {:.2f} x the loosest", c.cost / outcome.candidates.front().cost);
  }
  return text;
}


}  // namespace

std::string ClassWithMode(const AllocationIdentity::Option& option) {
  return option.mode.empty() ? option.class_name : fmt::format("{} ({})", option.class_name, option.mode);
}

std::string CandidateClasses(const AllocationIdentity& identity, const CandidateOutcome& candidate) {
  std::string text;
  for (std::size_t k = 0; k < identity.components.size() && k < candidate.options.size(); ++k) {
    text += fmt::format("{}{} {}", k == 0 ? "" : ", ", identity.components[k],
                        ClassWithMode(identity.options[k][static_cast<std::size_t>(candidate.options[k])]));
  }
  return text;
}

std::string CommonRandomGainText(double gain) {
  // Beyond this the two candidates' values move together almost exactly (they differ in a
  // component that barely moves the output), and the ratio's digits mean nothing.
  constexpr double kLargestShownGain = 1e4;
  if (gain > kLargestShownGain) {
    return fmt::format("more than {:g} times (the two candidates differ in a component that barely moves it)",
                       kLargestShownGain);
  }
  return fmt::format("{:.3g} times", gain);
}

std::string ConstraintText(const analysis::Constraint& constraint) {
  const std::string_view unit = OutputNamed(constraint.output).unit;
  if (constraint.kind == analysis::ConstraintKind::kQuantile)
    return fmt::format("{}: {:g} % quantile <= {:g} {}", constraint.output, 100 * constraint.level, constraint.upper,
                       unit);
  return fmt::format("{}: yield >= {:g} % within {:g} {}", constraint.output, 100 * constraint.level, constraint.upper,
                     unit);
}

double Margin(const analysis::Constraint& constraint, const analysis::ConstraintJudgement& judgement) {
  return constraint.kind == analysis::ConstraintKind::kQuantile ? constraint.upper - judgement.interval.upper
                                                                : judgement.interval.lower - constraint.level;
}

void PrintAllocation(std::ostream& out, const AllocationIdentity& identity, const AllocationOutcome& outcome) {
  const std::int64_t count = static_cast<std::int64_t>(outcome.candidates.size());
  std::string shape;
  for (std::size_t k = 0; k < identity.components.size(); ++k)
    shape += fmt::format("{}{} {}", k == 0 ? "" : " x ", identity.components[k], identity.options[k].size());
  fmt::print(out, "candidates        {}: {}; search {}\n", count, shape, identity.search);
  if (identity.screen != "none")
    fmt::print(out, "rungs             screen {} (first {} samples), confirm {} ({} to {} samples, doubling)\n",
               identity.screen, identity.first_samples, identity.solver, identity.first_samples, identity.samples);
  else
    fmt::print(out, "rungs             {} ({} to {} samples, doubling)\n", identity.solver, identity.first_samples,
               identity.samples);
  for (std::size_t j = 0; j < identity.constraints.size(); ++j)
    fmt::print(out, "{}{}. {}\n", j == 0 ? "constraints       " : kSummaryIndent, j + 1, ConstraintText(identity.constraints[j]));
  if (const std::optional<std::string> reading = ConstrainedErrorMotionReading(identity)) {
    fmt::print(out, "{}error motion read {}\n", kSummaryIndent, *reading);
  }
  fmt::print(out, "{}judged at {:g} % confidence\n\n", kSummaryIndent, 100 * identity.confidence);

  if (!outcome.complete) fmt::print(out, "(the search has not finished: what follows is what it knows so far)\n");
  if (outcome.recommendation) {
    const CandidateOutcome& r = outcome.candidates[static_cast<std::size_t>(*outcome.recommendation)];
    fmt::print(out, "recommendation    candidate {}: {}\n", *outcome.recommendation, CandidateClasses(identity, r));
    fmt::print(out, "cost              {}\n", CostText(identity, outcome, r));
    for (std::size_t j = 0; j < r.constraints.size(); ++j) {
      const analysis::Constraint& c = identity.constraints[j];
      fmt::print(out, "{}{}. {} {}: {}\n", j == 0 ? "margins           " : kSummaryIndent, j + 1, c.output,
                 Judgement(c, r.constraints[j], identity.confidence), MarginText(c, r.constraints[j]));
    }
    fmt::print(out, "samples           {} ({})\n", r.samples,
               r.settled_by ? NameOf(kEvaluationRoleNames, *r.settled_by) : std::string_view("-"));
    for (std::size_t k = 0; k < outcome.alternatives.size(); ++k) {
      const CandidateOutcome& a = outcome.candidates[static_cast<std::size_t>(outcome.alternatives[k])];
      fmt::print(out, "{}{}. candidate {}: {}; cost {}\n", k == 0 ? "alternatives      " : kSummaryIndent, k + 1,
                 outcome.alternatives[k], CandidateClasses(identity, a), CostText(identity, outcome, a));
    }
  } else if (outcome.complete) {
    if (outcome.undecided_cheaper.empty()) {
      fmt::print(out, "recommendation    none: no candidate is feasible\n");
    } else {
      fmt::print(out, "recommendation    none proven feasible: {} candidate{} stayed undecided (below)\n",
                 outcome.undecided_cheaper.size(), outcome.undecided_cheaper.size() == 1 ? "" : "s");
    }
    for (std::size_t k = 0; k < outcome.binding.size(); ++k) {
      const auto j = static_cast<std::size_t>(outcome.binding[k]);
      const CandidateOutcome& t = outcome.candidates.back();
      fmt::print(out, "{}{} binds: even the tightest candidate ({}) reaches {}\n", k == 0 ? "binding           " : kSummaryIndent,
                 ConstraintText(identity.constraints[j]), CandidateClasses(identity, t),
                 j < t.constraints.size() ? Judgement(identity.constraints[j], t.constraints[j], identity.confidence)
                                          : std::string("-"));
    }
  }
  if (outcome.undecided_cheaper.empty()) {
    fmt::print(out, "undecided         {}\n", outcome.recommendation ? "none cheaper than the recommendation" : "none");
  } else {
    for (std::size_t k = 0; k < outcome.undecided_cheaper.size(); ++k) {
      const std::int64_t index = outcome.undecided_cheaper[k];
      const CandidateOutcome& u = outcome.candidates[static_cast<std::size_t>(index)];
      std::int64_t needed = 0;
      for (const analysis::ConstraintJudgement& j : u.constraints)
        needed = (needed < 0 || j.samples_to_decide < 0) ? -1 : std::max(needed, j.samples_to_decide);
      fmt::print(out, "{}candidate {}: {}; cost {}: undecided at {} samples, {}\n",
                 k == 0 ? "undecided         " : kSummaryIndent, index, CandidateClasses(identity, u),
                 CostText(identity, outcome, u), u.samples,
                 needed < 0 ? std::string("no sample count decides it (its estimate sits on a limit, or failed "
                                          "samples lie beyond the quantile)")
                            : fmt::format("about {} samples would decide it", needed));
    }
  }
  std::int64_t implied = 0;
  std::int64_t costlier = 0;
  for (const CandidateOutcome& c : outcome.candidates) {
    implied += c.settlement == analysis::Settlement::kImplied ? 1 : 0;
    costlier += c.settlement == analysis::Settlement::kCostlier ? 1 : 0;
  }
  fmt::print(out,
             "search            simulated {} of {} candidates ({} settled by the screen), {} implied by monotonicity, "
             "{} left as costlier; {} screen and {} confirm samples\n",
             outcome.simulated, count, outcome.settled_by_screen, implied, costlier, outcome.samples_screen,
             outcome.samples_confirm);
  if (std::isfinite(outcome.common_random_numbers_gain)) {
    fmt::print(out,
               "common random     the difference of mean {} between the recommendation and its nearest looser "
               "candidate is {} less variable than with independent draws\n",
               identity.constraints.empty() ? std::string("output") : identity.constraints.front().output,
               CommonRandomGainText(outcome.common_random_numbers_gain));
  }
}

std::optional<std::string> ConstrainedErrorMotionReading(const AllocationIdentity& identity) {
  const bool any = std::any_of(identity.constraints.begin(), identity.constraints.end(),
                               [](const analysis::Constraint& c) { return ErrorMotionOf(c.output).has_value(); });
  if (!any) return std::nullopt;
  return ErrorMotionConditions({.filter = identity.error_motion_filter});
}

nlohmann::json AllocationJson(const AllocationIdentity& identity, const AllocationOutcome& outcome) {
  auto candidate_json = [&](std::int64_t index) {
    const CandidateOutcome& c = outcome.candidates[static_cast<std::size_t>(index)];
    nlohmann::json json = {{"candidate", index},
                           {"classes", CandidateClasses(identity, c)},
                           {"cost", c.cost},
                           {"relative_cost", c.relative_cost},
                           {"verdict", NameOf(analysis::kVerdictNames, c.verdict)},
                           {"settlement", NameOf(analysis::kSettlementNames, c.settlement)},
                           {"samples", c.samples}};
    if (c.settled_by) json["settled_by"] = NameOf(kEvaluationRoleNames, *c.settled_by);
    nlohmann::json constraints = nlohmann::json::array();
    for (std::size_t j = 0; j < c.constraints.size(); ++j) {
      const analysis::ConstraintJudgement& judgement = c.constraints[j];
      constraints.push_back({{"constraint", ConstraintText(identity.constraints[j])},
                             {"verdict", NameOf(analysis::kVerdictNames, judgement.verdict)},
                             {"estimate", judgement.estimate},
                             {"lower", judgement.interval.lower},
                             {"upper", judgement.interval.upper},
                             {"margin", Margin(identity.constraints[j], judgement)},
                             {"samples_to_decide", judgement.samples_to_decide}});
    }
    json["constraints"] = constraints;
    if (c.yield.trials > 0)
      json["yield"] = {{"value", c.yield.value}, {"lower", c.yield.interval.lower}, {"upper", c.yield.interval.upper}};
    return json;
  };
  nlohmann::json json;
  json["candidates"] = outcome.candidates.size();
  json["complete"] = outcome.complete;
  json["search"] = identity.search;
  json["simulated"] = outcome.simulated;
  json["settled_by_screen"] = outcome.settled_by_screen;
  json["samples_screen"] = outcome.samples_screen;
  json["samples_confirm"] = outcome.samples_confirm;
  if (std::isfinite(outcome.common_random_numbers_gain))
    json["common_random_numbers_gain"] = outcome.common_random_numbers_gain;
  json["recommendation"] = outcome.recommendation ? candidate_json(*outcome.recommendation) : nlohmann::json();
  json["alternatives"] = nlohmann::json::array();
  for (const std::int64_t a : outcome.alternatives) json["alternatives"].push_back(candidate_json(a));
  json["undecided_cheaper"] = nlohmann::json::array();
  for (const std::int64_t u : outcome.undecided_cheaper) json["undecided_cheaper"].push_back(candidate_json(u));
  json["front"] = nlohmann::json::array();
  for (const std::int64_t f : outcome.front) json["front"].push_back(candidate_json(f));
  if (const std::optional<std::string> reading = ConstrainedErrorMotionReading(identity)) {
    json["error_motion_reading"] = *reading;
    json["error_motion_filter_cutoff_upr"] = identity.error_motion_filter.cutoff_upr;
  }
  json["binding"] = nlohmann::json::array();
  for (const int j : outcome.binding)
    json["binding"].push_back(ConstraintText(identity.constraints[static_cast<std::size_t>(j)]));
  return json;
}

}  // namespace ringtol::jobs
