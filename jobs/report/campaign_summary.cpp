#include "jobs/report/campaign_summary.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <string_view>
#include <utility>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "analysis/order_statistics.h"
#include "engine/units.h"
#include "jobs/report/report_text.h"

namespace ringtol::jobs {
namespace {

nlohmann::json Bound(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

// The rungs a path can come from: every one but auto, which picks among them.
constexpr int kLadderRungs = static_cast<int>(solvers::Rung::kAuto);

std::string RungName(std::size_t rung) { return std::string(NameOf(solvers::kRungNames, static_cast<solvers::Rung>(rung))); }

std::string ShowBound(double value) { return std::isfinite(value) ? fmt::format("{:.5g}", value) : "unbounded"; }

}  // namespace

bool IsLifeColumn(std::string_view name) {
  return std::any_of(std::begin(kLifeColumns), std::end(kLifeColumns),
                     [&](const LifeColumns& c) { return name == c.one_revolution || name == c.life; });
}

std::vector<LifeGap> LifeGaps(const std::map<std::string, std::vector<double>, std::less<>>& ok_values) {
  std::vector<LifeGap> gaps;
  for (const LifeColumns& c : kLifeColumns) {
    const auto one = ok_values.find(c.one_revolution), life = ok_values.find(c.life);
    if (one == ok_values.end() || life == ok_values.end()) continue;
    if (std::optional<LifeGap> gap = CompareLife(c.label, one->second, life->second)) gaps.push_back(std::move(*gap));
  }
  return gaps;
}

std::optional<LifeGap> CompareLife(std::string label, std::span<const double> one, std::span<const double> life) {
  std::vector<double> ones, lifes, excess;
  for (std::size_t i = 0; i < std::min(one.size(), life.size()); ++i) {
    if (!std::isfinite(one[i]) || !std::isfinite(life[i])) continue;
    ones.push_back(one[i]);
    lifes.push_back(life[i]);
    if (one[i] > 0.0) excess.push_back(life[i] / one[i] - 1.0);
  }
  if (ones.empty()) return std::nullopt;
  LifeGap gap;
  gap.label = std::move(label);
  gap.count = static_cast<std::int64_t>(ones.size());
  std::sort(ones.begin(), ones.end());
  std::sort(lifes.begin(), lifes.end());
  gap.one_q50 = analysis::EstimateQuantile(ones, 0.5).value;
  gap.one_q99 = analysis::EstimateQuantile(ones, 0.99).value;
  gap.life_q50 = analysis::EstimateQuantile(lifes, 0.5).value;
  gap.life_q99 = analysis::EstimateQuantile(lifes, 0.99).value;
  gap.median_excess = excess.empty() ? std::numeric_limits<double>::quiet_NaN() : analysis::Median(std::move(excess));
  return gap;
}

std::string LifeGapSentence(const LifeGap& gap) {
  const auto change = [](double life, double one) {
    return one > 0.0 ? fmt::format(" ({:+.1f} %)", 100.0 * (life / one - 1.0)) : std::string();
  };
  std::string sentence = fmt::format(
      "Over the stage's life, {} q99 is {:.4g} mm against {:.4g} mm over one revolution{} and q50 {:.4g} mm against "
      "{:.4g} mm{}",
      gap.label, gap.life_q99, gap.one_q99, change(gap.life_q99, gap.one_q99), gap.life_q50, gap.one_q50,
      change(gap.life_q50, gap.one_q50));
  if (std::isfinite(gap.median_excess)) {
    sentence += fmt::format("; the median sample's life value lies {:.1f} % {} its own one-revolution value",
                            100.0 * std::abs(gap.median_excess), gap.median_excess < 0.0 ? "below" : "above");
  }
  return sentence + ".";
}

nlohmann::json LifeGapJson(const LifeGap& gap) {
  return {{"count", gap.count},
          {"one_revolution_mm", {{"q50", gap.one_q50}, {"q99", gap.one_q99}}},
          {"life_mm", {{"q50", gap.life_q50}, {"q99", gap.life_q99}}},
          {"median_excess", Bound(gap.median_excess)}};
}

std::string LifeNotComputed() {
  std::string names;
  for (std::size_t k = 0; k < kOutputCount; ++k) {
    if (IsLifeOutput(k)) names += (names.empty() ? "" : ", ") + std::string(kOutputNames[k]);
  }
  return fmt::format("The life outputs ({}) were not computed: the campaign file sets [outputs] life = false.", names);
}

bool IsErrorMotionColumn(std::string_view name) { return ErrorMotionOf(name).has_value(); }

std::optional<LifeErrorMotion> LifeErrorMotionOf(
    const std::map<std::string, std::vector<double>, std::less<>>& ok_values) {
  LifeErrorMotion motion;
  bool any = false;
  for (std::size_t k = 0; k < std::size(kErrorMotionValues); ++k) {
    motion.q50[k] = motion.q99[k] = std::numeric_limits<double>::quiet_NaN();
    const auto found = ok_values.find(ErrorMotionColumn(kErrorMotionValues[k]));
    if (found == ok_values.end()) continue;
    std::vector<double> values;
    for (const double v : found->second) {
      if (std::isfinite(v)) values.push_back(v);
    }
    if (values.empty()) continue;
    std::sort(values.begin(), values.end());
    motion.q50[k] = analysis::EstimateQuantile(values, 0.5).value;
    motion.q99[k] = analysis::EstimateQuantile(values, 0.99).value;
    if (kErrorMotionValues[k] == ErrorMotionValue::kTotal) {
      motion.count = static_cast<std::int64_t>(values.size());
      any = true;
    }
  }
  if (!any) return std::nullopt;
  return motion;
}

std::string LifeErrorMotionSentence(const LifeErrorMotion& motion, const engine::ErrorMotionFilter& filter) {
  const auto list = [&](const std::array<double, 3>& mm, bool words) {
    std::vector<std::string> parts;
    for (std::size_t k = 0; k < mm.size(); ++k) {
      if (!std::isfinite(mm[k])) continue;
      parts.push_back(Micrometres(units::kMicrometresPerMillimetre * mm[k]) +
                      (words ? " " + std::string(ErrorMotionWord(kErrorMotionValues[k])) : std::string()));
    }
    std::string text;
    for (std::size_t k = 0; k < parts.size(); ++k) {
      text += (k == 0 ? "" : k + 1 == parts.size() ? " and " : ", ") + parts[k];
    }
    return text;
  };
  return fmt::format(
      "Over the stage's life, the axis's radial error motion ({}) is at q99 {} (q50 {}). No one-revolution value "
      "compares: asynchronous motion, what differs from one revolution to the next, needs several revolutions, and "
      "one revolution's indicator reading (runout) holds the bore's form too.",
      ErrorMotionConditions({.filter = filter}), list(motion.q99, true), list(motion.q50, false));
}

nlohmann::json LifeErrorMotionJson(const LifeErrorMotion& motion, const engine::ErrorMotionFilter& filter) {
  nlohmann::json j = {{"count", motion.count},
                      {"reading", ErrorMotionConditions({.filter = filter})},
                      {"filter_cutoff_upr", filter.cutoff_upr},
                      {"revolutions", "every revolution of the life"}};
  for (std::size_t k = 0; k < std::size(kErrorMotionValues); ++k) {
    j[std::string(ErrorMotionWord(kErrorMotionValues[k])) + "_mm"] = {{"q50", Bound(motion.q50[k])},
                                                                      {"q99", Bound(motion.q99[k])}};
  }
  return j;
}

nlohmann::json LifeJson(bool computed, const std::vector<LifeGap>& gaps, const std::optional<LifeErrorMotion>& motion,
                        const engine::ErrorMotionFilter& filter, std::int64_t missing) {
  if (!computed) return {{"computed", false}};
  if (gaps.empty() && !motion && missing == 0) return nullptr;
  nlohmann::json life = {{"computed", true}, {"samples_without_life", missing}};
  for (const LifeGap& gap : gaps) life[gap.label] = LifeGapJson(gap);
  if (motion) life["error_motion"] = LifeErrorMotionJson(*motion, filter);
  return life;
}

std::vector<std::int64_t> CountRungs(const CampaignReader& results, const std::vector<SampleStatus>& status,
                                     const std::vector<bool>& used, std::vector<std::int64_t>* failed_by) {
  if (results.schema_version() < kFirstSchemaWithRungs) return {};
  const std::vector<std::int8_t> rungs = ReadInBlocks<std::int8_t>(
      static_cast<std::int64_t>(status.size()),
      [&](std::int64_t begin, std::int64_t count) { return results.ReadRungs(begin, count); });
  std::vector<std::int64_t> settled_by(kLadderRungs, 0);
  if (failed_by != nullptr) failed_by->assign(kLadderRungs, 0);
  for (std::size_t i = 0; i < rungs.size(); ++i) {
    if (used[i] && status[i] != SampleStatus::kPending && rungs[i] >= 0 && rungs[i] < kLadderRungs) {
      const auto rung = static_cast<std::size_t>(rungs[i]);
      ++settled_by[rung];
      if (failed_by != nullptr && status[i] != SampleStatus::kOk) ++(*failed_by)[rung];
    }
  }
  return settled_by;
}

std::int64_t CountNotFinite(std::span<const double> values) {
  return std::count_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); });
}

std::string LifeMissingSentence(std::int64_t missing, std::int64_t ok) {
  constexpr std::string_view kWhy =
      "the life reads the linear rung's phasors, which assume every contact closed (docs/model.md §9)";
  if (missing >= ok) return fmt::format("none of the {} ok samples has life values: a roller left the bore in each, and {}", ok, kWhy);
  return fmt::format("{} of {} ok samples have no life values: a roller left the bore, and {}; the life's numbers are over the other {}",
                     missing, ok, kWhy, ok - missing);
}

std::optional<Disposition> Dispose(const DispositionRule& rule, std::int64_t within, std::int64_t done) {
  if (done < 1) return std::nullopt;
  return Disposition{rule, analysis::JudgeYield({within, within, within, done}, rule.required_yield, rule.confidence)};
}

std::string_view DispositionVerdictName(const Disposition& disposition) {
  switch (disposition.judgement.verdict) {
    case analysis::Verdict::kFeasible:
      return "pass";
    case analysis::Verdict::kInfeasible:
      return "fail";
    default:
      return "undecided";
  }
}

int DispositionExitCode(const Disposition& disposition) {
  switch (disposition.judgement.verdict) {
    case analysis::Verdict::kFeasible:
      return 0;
    case analysis::Verdict::kInfeasible:
      return kDispositionFailExitCode;
    default:
      return kDispositionUndecidedExitCode;
  }
}

namespace {

analysis::ProportionEstimate YieldOf(const Disposition& d) {
  const analysis::ConstraintJudgement& j = d.judgement;
  return {static_cast<std::int64_t>(std::llround(j.estimate * static_cast<double>(j.samples))), j.samples, j.estimate,
          j.interval, d.rule.confidence};
}

}  // namespace

std::string DispositionSentence(const Disposition& d) {
  const analysis::ConstraintJudgement& j = d.judgement;
  const std::string required = fmt::format("{} required at {} confidence", Percent(d.rule.required_yield),
                                           Percent(d.rule.confidence));
  std::string sentence = fmt::format("{}: {} of {} assemblies are within every spec limit (failures outside), ",
                                     DispositionVerdictName(d), YieldWithInterval(YieldOf(d)), j.samples);
  switch (j.verdict) {
    case analysis::Verdict::kFeasible:
      return sentence + "at least the " + required;
    case analysis::Verdict::kInfeasible:
      return sentence + "below the " + required;
    default:
      sentence += "an interval that holds the " + required;
      if (j.samples_to_decide > j.samples) {
        sentence += fmt::format("; about {} samples would decide it (--resume --samples {})", j.samples_to_decide,
                                j.samples_to_decide);
      } else if (j.samples_to_decide < 0) {
        sentence += "; its share sits on the requirement, which no sample count decides";
      }
      return sentence;
  }
}

nlohmann::json DispositionJson(const Disposition& d) {
  const analysis::ProportionEstimate y = YieldOf(d);
  return {{"verdict", DispositionVerdictName(d)},
          {"required_yield", d.rule.required_yield},
          {"confidence", d.rule.confidence},
          {"yield",
           {{"value", y.value}, {"lower", y.interval.lower}, {"upper", y.interval.upper}, {"successes", y.successes},
            {"trials", y.trials}}},
          {"samples_to_decide", d.judgement.samples_to_decide}};
}

std::optional<ContactOpenings> CountOpenings(const CampaignReader& results, const std::vector<SampleStatus>& status,
                                             const std::vector<bool>& used, double confidence) {
  if (!results.HasOffBore()) return std::nullopt;
  const std::vector<std::string>& names = results.identity().rollers;
  const std::size_t z = names.size();
  const std::vector<float> shares = ReadInBlocks<float>(
      static_cast<std::int64_t>(status.size()),
      [&](std::int64_t begin, std::int64_t count) { return results.ReadOffBore(begin, count); });
  ContactOpenings openings;
  std::vector<std::vector<double>> opened(z);  // per roller: its share on the samples it left the bore
  std::int64_t any = 0;
  for (std::size_t i = 0; i < status.size(); ++i) {
    if (!used[i] || status[i] != SampleStatus::kOk) continue;
    ++openings.ok;
    bool left = false;
    for (std::size_t r = 0; r < z; ++r) {
      const double share = shares[i * z + r];
      if (!(share > 0.0)) continue;
      opened[r].push_back(share);
      left = true;
    }
    if (left) ++any;
  }
  if (openings.ok == 0) return std::nullopt;
  openings.any = analysis::EstimateProportion(any, openings.ok, confidence);
  for (std::size_t r = 0; r < z; ++r) {
    RollerOpenings roller{names[r], static_cast<std::int64_t>(opened[r].size()), analysis::Median(opened[r]), 0.0};
    for (const double share : opened[r]) roller.max_percent = std::max(roller.max_percent, share);
    openings.rollers.push_back(std::move(roller));
  }
  return openings;
}

std::string OpeningsSentence(const ContactOpenings& openings) {
  if (openings.any.successes == 0) {
    return fmt::format("every roller touched the bore throughout, in all {} ok samples", openings.ok);
  }
  std::string rollers;
  for (const RollerOpenings& roller : openings.rollers) {
    if (roller.samples == 0) continue;
    rollers += fmt::format("{}{} in {} (median {:.1f} %, at most {:.1f} % of the turn)", rollers.empty() ? "" : ", ",
                           roller.roller, roller.samples, roller.median_percent, roller.max_percent);
  }
  return fmt::format("{} of {} ok samples ({}) had a roller off the bore for part of the turn: {}",
                     openings.any.successes, openings.ok, YieldWithInterval(openings.any), rollers);
}

nlohmann::json OpeningsJson(const ContactOpenings& openings) {
  nlohmann::json rollers = nlohmann::json::object();
  for (const RollerOpenings& roller : openings.rollers) {
    rollers[roller.roller] = {
        {"samples", roller.samples},
        {"median_percent_of_turn", roller.samples > 0 ? nlohmann::json(roller.median_percent) : nlohmann::json(nullptr)},
        {"max_percent_of_turn", roller.max_percent}};
  }
  return {{"samples_ok", openings.ok},
          {"samples_with_opening", openings.any.successes},
          {"share",
           {{"value", openings.any.value}, {"lower", openings.any.interval.lower}, {"upper", openings.any.interval.upper}}},
          {"rollers", std::move(rollers)}};
}

namespace {

// Why auto sent samples to the dynamic rung: the one reason it has (solvers/auto.h, step 2).
constexpr std::string_view kDynamicReason =
    "auto's bound on the ring's inertial force reached the least force its support rests on, "
    "which the time-free rungs cannot see (docs/model.md §7)";

std::int64_t DynamicSamples(const CampaignSummary& s) {
  const auto dynamic = static_cast<std::size_t>(solvers::Rung::kDynamic);
  return s.settled_by.size() > dynamic ? s.settled_by[dynamic] : 0;
}

}  // namespace

std::int64_t RungsRan(const std::vector<std::int64_t>& settled_by) {
  std::int64_t sum = 0;
  for (const std::int64_t count : settled_by) sum += count;
  return sum;
}

std::string RungShares(const std::vector<std::int64_t>& settled_by) {
  const std::int64_t ran = RungsRan(settled_by);
  std::string list;
  if (ran == 0) return list;
  for (std::size_t r = 0; r < settled_by.size(); ++r) {
    list += fmt::format("{}{} {:.1f} %", list.empty() ? "" : ", ", RungName(r),
                        100.0 * static_cast<double>(settled_by[r]) / static_cast<double>(ran));
  }
  return list;
}

nlohmann::json RungsJson(const std::vector<std::int64_t>& settled_by) {
  const std::int64_t ran = RungsRan(settled_by);
  if (ran == 0) return nullptr;
  nlohmann::json rungs = nlohmann::json::object();
  for (std::size_t r = 0; r < settled_by.size(); ++r) {
    rungs[RungName(r)] = {{"samples", settled_by[r]},
                          {"share", static_cast<double>(settled_by[r]) / static_cast<double>(ran)}};
  }
  return rungs;
}

std::string SchemaNote(const CampaignReader& results) {
  if (results.schema_version() >= 2) return {};
  return fmt::format(
      "schema {} file: runout_mm is its runout_total_mm (max - min); its own runout_mm, an ill-posed peak to "
      "nearest valley, is not read, and it has no swing_mm",
      results.schema_version());
}

CampaignSummary Summarise(const CampaignReader& results, const std::function<bool(std::int64_t)>& independent,
                          double confidence) {
  CampaignSummary summary;
  summary.confidence = confidence;
  summary.samples = results.samples();
  const std::vector<SampleStatus> status = ReadInBlocks<SampleStatus>(
      summary.samples, [&](std::int64_t begin, std::int64_t count) { return results.ReadStatus(begin, count); });
  std::vector<bool> used(status.size());
  for (std::size_t i = 0; i < status.size(); ++i) {
    used[i] = !independent || independent(static_cast<std::int64_t>(i));
    if (!used[i]) continue;
    ++summary.used;
    if (status[i] == SampleStatus::kPending) continue;
    ++summary.done;
    if (status[i] == SampleStatus::kOk) {
      ++summary.ok;
    } else {
      ++summary.failures[std::string(SampleStatusName(status[i]))];
    }
  }

  summary.schema_note = SchemaNote(results);
  summary.settled_by = CountRungs(results, status, used, &summary.failed_by);
  summary.auto_rung = results.identity().solver.starts_with(NameOf(solvers::kRungNames, solvers::Rung::kAuto));
  summary.openings = CountOpenings(results, status, used, confidence);

  std::vector<bool> within(status.size(), true);
  bool any_spec = false;
  // kLifeColumns' and the error motion's ok values, in sample order.
  std::map<std::string, std::vector<double>, std::less<>> paired;
  for (const char* name : kOutputNames) {
    if (!results.HasOutput(name) || !ShowsOutput(results.identity(), name)) continue;
    OutputSummary output;
    output.name = name;
    for (const SpecLimit& limit : results.identity().spec) {
      if (limit.output == name) output.upper_spec_limit = limit.upper;
    }
    const std::vector<double> all = ReadInBlocks<double>(summary.samples, [&](std::int64_t begin, std::int64_t count) {
      return results.ReadOutput(name, begin, count);
    });
    std::vector<double> values;
    values.reserve(static_cast<std::size_t>(summary.ok));
    std::vector<double> ok_values;  // every used ok sample's, in sample order: pairs are by sample
    std::int64_t within_limit = 0;
    for (std::size_t i = 0; i < all.size(); ++i) {
      if (!used[i] || status[i] != SampleStatus::kOk) continue;
      ok_values.push_back(all[i]);
      // An ok sample without a value (a life output where a roller left the bore) is out of
      // the distribution and, like a failure, outside a limit on it.
      if (std::isfinite(all[i])) values.push_back(all[i]);
      if (!output.upper_spec_limit) continue;
      if (all[i] <= *output.upper_spec_limit) {
        ++within_limit;
      } else {
        within[i] = false;
      }
    }
    if (output.upper_spec_limit && summary.done > 0) {
      summary.in_spec_by_limit.push_back(
          {name, *output.upper_spec_limit, analysis::EstimateProportion(within_limit, summary.done, confidence)});
    }
    any_spec = any_spec || output.upper_spec_limit.has_value();
    output.count = static_cast<std::int64_t>(values.size());
    // The life outputs are NaN together: any one's count is theirs.
    if (IsLifeOutput(OutputIndex(name))) summary.life_missing = CountNotFinite(ok_values);
    if (IsLifeColumn(name) || IsErrorMotionColumn(name)) paired[name] = std::move(ok_values);
    if (!values.empty()) {
      std::sort(values.begin(), values.end());
      double sum = 0.0;
      for (const double v : values) sum += v;
      output.mean = sum / static_cast<double>(values.size());
      double squares = 0.0;
      for (const double v : values) squares += (v - output.mean) * (v - output.mean);
      output.standard_deviation =
          values.size() > 1 ? std::sqrt(squares / static_cast<double>(values.size() - 1)) : 0.0;
      output.min = values.front();
      output.max = values.back();
      for (const double p : kSummaryProbabilities) {
        output.quantiles.push_back(analysis::EstimateQuantile(values, p, confidence));
      }
    }
    summary.outputs.push_back(std::move(output));
  }
  summary.life = results.identity().life;
  summary.life_gaps = LifeGaps(paired);
  summary.error_motion_filter = results.identity().error_motion_filter;
  summary.life_error_motion = LifeErrorMotionOf(paired);
  if (any_spec && summary.done > 0) {
    std::int64_t good = 0;
    for (std::size_t i = 0; i < status.size(); ++i) {
      if (used[i] && status[i] == SampleStatus::kOk && within[i]) ++good;
    }
    summary.in_spec = analysis::EstimateProportion(good, summary.done, confidence);
    if (summary.ok > 0) summary.in_spec_ok = analysis::EstimateProportion(good, summary.ok, confidence);
  }
  return summary;
}

void PrintSummary(std::ostream& out, const CampaignSummary& s) {
  if (!s.schema_note.empty()) fmt::print(out, "note              {}\n", s.schema_note);
  fmt::print(out, "samples           {} in the campaign, {} used for statistics, {} done, {} ok\n", s.samples, s.used,
             s.done, s.ok);
  if (s.failures.empty()) {
    fmt::print(out, "failures          none\n");
  } else {
    std::string list;
    for (const auto& [reason, count] : s.failures) list += fmt::format("{}{} {}", list.empty() ? "" : ", ", count, reason);
    fmt::print(out, "failures          {} (excluded from the distributions)\n", list);
  }
  if (const std::int64_t ran = RungsRan(s.settled_by); ran > 0) {
    fmt::print(out, "rungs             {} (of the {} samples a rung ran on)\n", RungShares(s.settled_by), ran);
  }
  if (const std::int64_t dynamic = DynamicSamples(s); s.auto_rung && dynamic > 0) {
    fmt::print(out, "dynamic           {} samples, {} of them failed: {}\n", dynamic,
               s.failed_by[static_cast<std::size_t>(solvers::Rung::kDynamic)], kDynamicReason);
  }
  if (s.openings) fmt::print(out, "contacts          {}\n", OpeningsSentence(*s.openings));
  if (!s.life) fmt::print(out, "life              {}\n", LifeNotComputed());
  if (s.life_missing > 0) fmt::print(out, "life              {}\n", LifeMissingSentence(s.life_missing, s.ok));
  for (const LifeGap& gap : s.life_gaps) fmt::print(out, "life              {}\n", LifeGapSentence(gap));
  if (s.life_error_motion) fmt::print(out, "life              {}\n", LifeErrorMotionSentence(*s.life_error_motion, s.error_motion_filter));
  const int level = static_cast<int>(std::lround(100.0 * s.confidence));
  fmt::print(out, "\n{:<28} {:>10} {:>10}", "output", "mean", "std");
  for (const double p : kSummaryProbabilities) fmt::print(out, " {:>30}", fmt::format("q{} [{} % CI]", Percent(p), level));
  fmt::print(out, " {:>10}\n", "spec <=");
  for (const OutputSummary& o : s.outputs) {
    if (o.count == 0) continue;
    fmt::print(out, "{:<28} {:>10.5g} {:>10.4g}", o.name, o.mean, o.standard_deviation);
    for (const analysis::QuantileEstimate& q : o.quantiles) {
      fmt::print(out, " {:>30}",
                 fmt::format("{:.5g} [{}, {}]", q.value, ShowBound(q.interval.lower), ShowBound(q.interval.upper)));
    }
    fmt::print(out, " {:>10}\n", o.upper_spec_limit ? fmt::format("{:g}", *o.upper_spec_limit) : "-");
  }
  if (std::any_of(s.outputs.begin(), s.outputs.end(),
                  [](const OutputSummary& o) { return o.count > 0 && IsErrorMotionColumn(o.name); })) {
    fmt::print(out, "{:<28} {}\n", "error_motion_*", ErrorMotionConditions({.filter = s.error_motion_filter}));
  }
  if (s.in_spec) {
    // One line per limit, then, with more than one, every limit at once: each its yield
    // over the done samples, failures counted as outside.
    std::vector<std::pair<std::string, analysis::ProportionEstimate>> lines;
    for (const LimitYield& limit : s.in_spec_by_limit) {
      lines.emplace_back(fmt::format("{} <= {:g}", limit.output, limit.limit), limit.within);
    }
    const std::string joint = lines.size() == 1 ? lines.front().first : "every limit at once";
    if (lines.size() != 1) lines.emplace_back(joint, *s.in_spec);
    std::size_t width = 0;
    for (const auto& line : lines) width = std::max(width, line.first.size());
    // A limit on a life output cannot pass a sample that has no life value: it counts as
    // outside, as a failure does, and the line says so where it happened.
    const bool life_limit = std::any_of(s.in_spec_by_limit.begin(), s.in_spec_by_limit.end(),
                                        [](const LimitYield& l) { return OutputNamed(l.output).span == OutputSpan::kLife; });
    const char* outside = life_limit && s.life_missing > 0 ? "; failures and ok samples without life values count as outside"
                                                           : "; failures count as outside";
    for (std::size_t k = 0; k < lines.size(); ++k) {
      const analysis::ProportionEstimate& p = lines[k].second;
      fmt::print(out, "{}{:<{}}  {} ({} of {} done samples{})\n", k == 0 ? "\nwithin spec       " : kSummaryIndent,
                 lines[k].first, width, YieldWithInterval(p), p.successes, p.trials, k + 1 == lines.size() ? outside : "");
    }
    if (s.in_spec_ok) {
      fmt::print(out, "within spec, ok   {:<{}}  {} (of the {} ok samples)\n", joint, width,
                 YieldWithInterval(*s.in_spec_ok), s.in_spec_ok->trials);
    }
  }
  if (s.disposition) fmt::print(out, "disposition       {}\n", DispositionSentence(*s.disposition));
}

nlohmann::json SummaryJson(const CampaignSummary& s) {
  nlohmann::json j;
  j["samples"] = s.samples;
  j["samples_used"] = s.used;
  j["samples_done"] = s.done;
  j["samples_ok"] = s.ok;
  j["failures"] = s.failures;
  j["confidence"] = s.confidence;
  if (!s.schema_note.empty()) j["schema_note"] = s.schema_note;
  if (RungsRan(s.settled_by) > 0) {
    j["rungs"] = RungsJson(s.settled_by);
    for (std::size_t r = 0; r < s.failed_by.size(); ++r) j["rungs"][RungName(r)]["failed"] = s.failed_by[r];
    if (s.auto_rung && DynamicSamples(s) > 0) j["rungs"]["dynamic"]["reason"] = kDynamicReason;
  }
  if (s.openings) j["contacts"] = OpeningsJson(*s.openings);
  nlohmann::json outputs = nlohmann::json::object();
  for (const OutputSummary& o : s.outputs) {
    nlohmann::json x;
    x["count"] = o.count;
    if (o.count > 0) {
      x["mean"] = o.mean;
      x["std"] = o.standard_deviation;
      x["min"] = o.min;
      x["max"] = o.max;
      nlohmann::json quantiles = nlohmann::json::array();
      for (const analysis::QuantileEstimate& q : o.quantiles) {
        quantiles.push_back({{"probability", q.probability},
                             {"value", q.value},
                             {"lower", Bound(q.interval.lower)},
                             {"upper", Bound(q.interval.upper)}});
      }
      x["quantiles"] = quantiles;
    }
    x["upper_spec_limit"] = o.upper_spec_limit ? nlohmann::json(*o.upper_spec_limit) : nlohmann::json(nullptr);
    if (IsErrorMotionColumn(o.name)) x["reading"] = ErrorMotionConditions({.filter = s.error_motion_filter});
    outputs[o.name] = x;
  }
  j["outputs"] = outputs;
  if (nlohmann::json life = LifeJson(s.life, s.life_gaps, s.life_error_motion, s.error_motion_filter, s.life_missing);
      !life.is_null()) {
    j["life"] = std::move(life);
  }
  auto proportion = [](const std::optional<analysis::ProportionEstimate>& p) {
    if (!p) return nlohmann::json(nullptr);
    return nlohmann::json{{"value", p->value}, {"lower", p->interval.lower}, {"upper", p->interval.upper},
                          {"successes", p->successes}, {"trials", p->trials}};
  };
  j["in_spec"] = proportion(s.in_spec);
  j["in_spec_ok"] = proportion(s.in_spec_ok);
  nlohmann::json by_limit = nlohmann::json::array();
  for (const LimitYield& limit : s.in_spec_by_limit) {
    nlohmann::json entry = proportion(limit.within);
    entry["output"] = limit.output;
    entry["limit"] = limit.limit;
    by_limit.push_back(std::move(entry));
  }
  j["in_spec_by_limit"] = std::move(by_limit);
  if (s.disposition) j["disposition"] = DispositionJson(*s.disposition);
  return j;
}

}  // namespace ringtol::jobs
