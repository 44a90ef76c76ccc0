#include "jobs/report/allocation_report.h"

#include <algorithm>
#include <cmath>
#include <span>
#include <stdexcept>
#include <string_view>
#include <utility>

#include <fmt/format.h>

#include "engine/units.h"
#include "jobs/campaign/sample_record.h"
#include "jobs/report/allocation_summary.h"
#include "jobs/report/campaign_summary.h"

namespace ringtol::jobs {
namespace {

constexpr double kPercentPerFraction = 100.0;

// A constraint's margin in a unit a designer reads: µm for lengths (outputs in mm),
// percentage points for yields, else the output's own unit.
std::pair<std::string, double> MarginUnit(const analysis::Constraint& constraint) {
  if (constraint.kind == analysis::ConstraintKind::kYield) return {"points", kPercentPerFraction};
  const std::string_view unit = OutputNamed(constraint.output).unit;
  if (unit == "mm") return {"µm", units::kMicrometresPerMetre / units::kMillimetresPerMetre};
  return {std::string(unit), 1.0};
}

double MarginInUnit(const analysis::Constraint& constraint, const analysis::ConstraintJudgement& judgement) {
  const double scale = MarginUnit(constraint).second;
  return constraint.kind == analysis::ConstraintKind::kYield ? scale * (judgement.interval.lower - constraint.level)
                                                             : scale * (constraint.upper - judgement.interval.upper);
}

void Require(bool condition, const std::string& what) {
  if (!condition) throw std::invalid_argument("allocation report: " + what);
}

void CheckIndex(std::int64_t index, std::size_t count, std::string_view what) {
  Require(index >= 0 && static_cast<std::size_t>(index) < count,
          fmt::format("{} {} is not a candidate (there are {})", what, index, count));
}

void Validate(const AllocationReportInput& input) {
  const AllocationIdentity& id = input.identity;
  const AllocationOutcome& out = input.outcome;
  Require(id.components.size() == id.options.size(), "components and option lists differ in number");
  std::size_t expected = id.components.empty() ? 0 : 1;
  for (const auto& options : id.options) expected *= options.size();
  Require(out.candidates.size() == expected,
          fmt::format("the outcome has {} candidates, the options make {}", out.candidates.size(), expected));
  for (std::size_t i = 0; i < out.candidates.size(); ++i) {
    const CandidateOutcome& c = out.candidates[i];
    Require(c.options.size() == id.components.size(), fmt::format("candidate {} has {} options for {} components", i,
                                                                  c.options.size(), id.components.size()));
    for (std::size_t k = 0; k < c.options.size(); ++k) {
      Require(c.options[k] >= 0 && static_cast<std::size_t>(c.options[k]) < id.options[k].size(),
              fmt::format("candidate {} takes option {} of component {}", i, c.options[k], id.components[k]));
    }
    Require(c.constraints.empty() || c.constraints.size() == id.constraints.size(),
            fmt::format("candidate {} is judged on {} constraints of {}", i, c.constraints.size(), id.constraints.size()));
  }
  const std::size_t n = out.candidates.size();
  if (out.recommendation) CheckIndex(*out.recommendation, n, "the recommendation");
  for (const auto* list : {&out.alternatives, &out.undecided_cheaper, &out.front}) {
    for (const std::int64_t i : *list) CheckIndex(i, n, "a listed candidate");
  }
  for (const int k : out.binding) {
    Require(k >= 0 && static_cast<std::size_t>(k) < id.constraints.size(), fmt::format("binding constraint {}", k));
  }
}

CandidateReport Candidate(const AllocationReportInput& input, std::int64_t index) {
  const AllocationIdentity& id = input.identity;
  CandidateReport c;
  c.index = index;
  c.outcome = input.outcome.candidates[static_cast<std::size_t>(index)];
  for (std::size_t k = 0; k < c.outcome.options.size(); ++k) {
    c.classes.push_back(ClassWithMode(id.options[k][static_cast<std::size_t>(c.outcome.options[k])]));
  }
  const double loosest = input.outcome.candidates.front().cost;
  if (loosest > 0.0) c.relative_to_loosest = c.outcome.cost / loosest;
  for (std::size_t k = 0; k < c.outcome.constraints.size(); ++k) {
    const analysis::ConstraintJudgement& j = c.outcome.constraints[k];
    c.margins.push_back(MarginInUnit(id.constraints[k], j));
    if (j.verdict != analysis::Verdict::kUndecided) continue;
    if (j.samples_to_decide < 0 || c.samples_to_decide < 0) {
      c.samples_to_decide = -1;
    } else {
      c.samples_to_decide = std::max(c.samples_to_decide, j.samples_to_decide);
    }
  }
  return c;
}

// The outputs the constraints name, once each, in constraint order.
std::vector<std::string> ConstrainedOutputs(const std::vector<analysis::Constraint>& constraints) {
  std::vector<std::string> outputs;
  for (const analysis::Constraint& c : constraints) {
    if (std::find(outputs.begin(), outputs.end(), c.output) == outputs.end()) outputs.push_back(c.output);
  }
  return outputs;
}

// The tightest limit on an output and the quantile levels its constraints ask for.
std::pair<std::optional<double>, std::vector<double>> LimitAndLevels(const std::vector<analysis::Constraint>& constraints,
                                                                     const std::string& output) {
  std::optional<double> limit;
  std::vector<double> levels(std::begin(kSummaryProbabilities), std::end(kSummaryProbabilities));
  for (const analysis::Constraint& c : constraints) {
    if (c.output != output) continue;
    limit = limit ? std::min(*limit, c.upper) : c.upper;
    if (c.kind == analysis::ConstraintKind::kQuantile) levels.push_back(c.level);
  }
  std::sort(levels.begin(), levels.end());
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
  return {limit, levels};
}

RecommendedOutput Recommended(const AllocationReportInput& input, const std::string& output,
                              const ReportOptions& options, std::int64_t screening_samples) {
  const auto found = input.recommendation_samples.find(output);
  const std::vector<double> none;
  const std::vector<double>& all = found == input.recommendation_samples.end() ? none : found->second;
  std::vector<double> ok;
  for (const double v : all) {
    if (std::isfinite(v)) ok.push_back(v);
  }
  const auto [limit, levels] = LimitAndLevels(input.identity.constraints, output);
  RecommendedOutput out;
  out.distribution = DescribeOutput(output, limit, ok, static_cast<std::int64_t>(all.size() - ok.size()), levels, options);

  const std::size_t d = input.identity.inputs.size();
  if (input.design_points.empty() || d == 0) {
    out.sensitivity_problem = "the design points were not given";
    return out;
  }
  Require(input.design_points.size() == all.size() * d,
          fmt::format("{} design-point coordinates for {} samples of {} inputs", input.design_points.size(), all.size(), d));
  if (!out.distribution.distribution || !(out.distribution.distribution->standard_deviation > 0.0)) {
    out.sensitivity_problem = "the output does not vary over the recommendation's samples";
    return out;
  }
  std::vector<double> y, x;
  const std::size_t take = std::min(all.size(), static_cast<std::size_t>(std::max<std::int64_t>(1, screening_samples)));
  for (std::size_t i = 0; i < take; ++i) {
    if (!std::isfinite(all[i])) continue;
    y.push_back(all[i]);
    x.insert(x.end(), input.design_points.begin() + static_cast<std::ptrdiff_t>(i * d),
             input.design_points.begin() + static_cast<std::ptrdiff_t>((i + 1) * d));
  }
  if (y.size() < d + 2) {
    out.sensitivity_problem =
        fmt::format("{} ok samples are too few to fit {} inputs (the regression needs {})", y.size(), d, d + 2);
    return out;
  }
  try {
    out.sensitivity = ScreenOutput(output, y, x, static_cast<int>(d), input.identity.inputs, options);
  } catch (const std::invalid_argument& e) {
    out.sensitivity_problem = e.what();
  }
  return out;
}

}  // namespace

AllocationReport MakeAllocationReport(const AllocationReportInput& input, const AllocationReportOptions& options) {
  Validate(input);
  const AllocationIdentity& id = input.identity;
  const AllocationOutcome& outcome = input.outcome;
  AllocationReport report;
  report.results = input.results;
  report.identity = id;
  report.options = options;
  for (const analysis::Constraint& c : id.constraints) report.margin_units.push_back(MarginUnit(c).first);

  for (std::size_t i = 0; i < outcome.candidates.size(); ++i) {
    report.candidates.push_back(Candidate(input, static_cast<std::int64_t>(i)));
    switch (outcome.candidates[i].settlement) {
      case analysis::Settlement::kSimulated:
        report.simulated.push_back(static_cast<std::int64_t>(i));
        break;
      case analysis::Settlement::kImplied:
        ++report.implied;
        break;
      case analysis::Settlement::kCostlier:
        ++report.costlier;
        break;
      case analysis::Settlement::kNotVisited:
        ++report.not_visited;
        break;
    }
  }
  std::stable_sort(report.simulated.begin(), report.simulated.end(), [&](std::int64_t a, std::int64_t b) {
    return outcome.candidates[static_cast<std::size_t>(a)].cost < outcome.candidates[static_cast<std::size_t>(b)].cost;
  });
  report.recommendation = outcome.recommendation;
  report.alternatives = outcome.alternatives;
  report.undecided_cheaper = outcome.undecided_cheaper;
  report.front = outcome.front;
  report.binding = outcome.binding;
  if (!outcome.recommendation && outcome.complete && !outcome.candidates.empty()) {
    report.tightest = static_cast<std::int64_t>(outcome.candidates.size()) - 1;
  }
  report.complete = outcome.complete;
  report.simulated_count = outcome.simulated;
  report.settled_by_screen = outcome.settled_by_screen;
  report.samples_screen = outcome.samples_screen;
  report.samples_confirm = outcome.samples_confirm;
  report.common_random_numbers_gain = outcome.common_random_numbers_gain;

  if (outcome.recommendation) {
    ReportOptions campaign_options;
    campaign_options.confidence = id.confidence;
    campaign_options.bootstrap_resamples = options.bootstrap_resamples;
    for (const std::string& output : ConstrainedOutputs(id.constraints)) {
      report.recommended_outputs.push_back(Recommended(input, output, campaign_options, options.screening_samples));
    }
  }
  return report;
}

namespace {

nlohmann::json CandidateJson(const AllocationReport& report, std::int64_t index) {
  const CandidateReport& c = report.candidates[static_cast<std::size_t>(index)];
  const CandidateOutcome& o = c.outcome;
  nlohmann::json j = {{"index", c.index},
                      {"classes", c.classes},
                      {"options", o.options},
                      {"cost", JsonNumber(o.cost)},
                      {"relative_cost", JsonNumber(o.relative_cost)},
                      {"relative_to_loosest", JsonNumber(c.relative_to_loosest)},
                      {"verdict", NameOf(analysis::kVerdictNames, o.verdict)},
                      {"settlement", NameOf(analysis::kSettlementNames, o.settlement)},
                      {"samples", o.samples},
                      {"samples_to_decide", c.samples_to_decide}};
  j["settled_by"] = o.settled_by ? nlohmann::json(NameOf(kEvaluationRoleNames, *o.settled_by)) : nlohmann::json(nullptr);
  j["implied_by"] = o.implied_by >= 0 ? nlohmann::json(o.implied_by) : nlohmann::json(nullptr);
  j["yield"] = o.yield.trials > 0 ? Json(o.yield) : nlohmann::json(nullptr);
  nlohmann::json constraints = nlohmann::json::array();
  for (std::size_t k = 0; k < o.constraints.size(); ++k) {
    const analysis::ConstraintJudgement& judgement = o.constraints[k];
    constraints.push_back({{"verdict", NameOf(analysis::kVerdictNames, judgement.verdict)},
                           {"estimate", JsonNumber(judgement.estimate)},
                           {"interval", Json(judgement.interval)},
                           {"samples", judgement.samples},
                           {"samples_to_decide", judgement.samples_to_decide},
                           {"margin", JsonNumber(c.margins[k])}});
  }
  j["constraints"] = std::move(constraints);
  return j;
}

nlohmann::json CandidatesJson(const AllocationReport& report, const std::vector<std::int64_t>& indices) {
  nlohmann::json list = nlohmann::json::array();
  for (const std::int64_t i : indices) list.push_back(CandidateJson(report, i));
  return list;
}

}  // namespace

nlohmann::json AllocationReportJson(const AllocationReport& report) {
  const AllocationIdentity& id = report.identity;
  nlohmann::json j;
  j["format"] = "ringtol allocation report";
  j["schema_version"] = 1;
  j["results"] = report.results.string();
  j["allocation"] = {{"path", id.allocation_path},
                     {"ringtol_version", id.ringtol_version},
                     {"catalogue_version", id.catalogue_version},
                     {"design", id.design},
                     {"solver", id.solver},
                     {"screen", id.screen},
                     {"search", id.search},
                     {"seed", id.seed},
                     {"samples", id.samples},
                     {"first_samples", id.first_samples},
                     {"confidence", id.confidence}};
  j["allocation"]["reference"] = id.reference ? nlohmann::json(*id.reference) : nlohmann::json(nullptr);
  nlohmann::json components = nlohmann::json::array();
  for (std::size_t k = 0; k < id.components.size(); ++k) {
    nlohmann::json options = nlohmann::json::array();
    for (const AllocationIdentity::Option& o : id.options[k]) {
      options.push_back({{"class", o.class_name}, {"mode", o.mode}, {"tolerance", o.tolerance}, {"cost", o.cost}});
    }
    components.push_back({{"name", id.components[k]}, {"options", std::move(options)}});
  }
  j["components"] = std::move(components);
  nlohmann::json constraints = nlohmann::json::array();
  for (std::size_t k = 0; k < id.constraints.size(); ++k) {
    const analysis::Constraint& c = id.constraints[k];
    constraints.push_back({{"output", c.output},
                           {"kind", NameOf(analysis::kConstraintKindNames, c.kind)},
                           {"level", c.level},
                           {"upper", c.upper},
                           {"margin_unit", report.margin_units[k]}});
  }
  j["constraints"] = std::move(constraints);
  j["recommendation"] = report.recommendation ? CandidateJson(report, *report.recommendation) : nlohmann::json(nullptr);
  j["alternatives"] = CandidatesJson(report, report.alternatives);
  j["undecided_cheaper"] = CandidatesJson(report, report.undecided_cheaper);
  j["binding"] = report.binding;
  j["tightest"] = report.tightest ? CandidateJson(report, *report.tightest) : nlohmann::json(nullptr);
  j["front"] = CandidatesJson(report, report.front);
  j["simulated"] = CandidatesJson(report, report.simulated);
  nlohmann::json outputs = nlohmann::json::object();
  for (const RecommendedOutput& out : report.recommended_outputs) {
    nlohmann::json o = {{"distribution", OutputJson(out.distribution, 1.0)}};
    o["sensitivity"] = out.sensitivity ? SensitivityJson(*out.sensitivity) : nlohmann::json(nullptr);
    o["sensitivity_problem"] = out.sensitivity_problem;
    outputs[out.distribution.name] = std::move(o);
  }
  j["recommended_outputs"] = std::move(outputs);
  j["search"] = {{"complete", report.complete},
                 {"candidates", report.candidates.size()},
                 {"simulated", report.simulated_count},
                 {"settled_by_screen", report.settled_by_screen},
                 {"implied", report.implied},
                 {"costlier", report.costlier},
                 {"not_visited", report.not_visited},
                 {"samples_screen", report.samples_screen},
                 {"samples_confirm", report.samples_confirm},
                 {"common_random_numbers_gain", JsonNumber(report.common_random_numbers_gain)}};
  return j;
}

}  // namespace ringtol::jobs
