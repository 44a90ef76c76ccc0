// The allocation report's page (AllocationReportHtml): the answer, the Pareto front as a
// chart and a table, the recommendation's distributions and sensitivities, what the
// search did, and how the numbers were made.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "jobs/report/allocation_report.h"
#include "jobs/report/allocation_summary.h"
#include "jobs/report/html_parts.h"
#include "jobs/report/report_text.h"
#include "jobs/report/svg_chart.h"

namespace ringtol::jobs {
namespace {

using svg::EscapeXml;
using namespace html;  // the shared pieces of both report pages

const CandidateReport& At(const AllocationReport& report, std::int64_t index) {
  return report.candidates[static_cast<std::size_t>(index)];
}

// "99 % quantile of D_trajectory [mm] &#8804; 0.1" or "fraction with D_trajectory [mm] &#8804; 0.1 at least
// 99.73 %", as HTML.
std::string ConstraintHtml(const analysis::Constraint& c) {
  if (c.kind == analysis::ConstraintKind::kQuantile) {
    return fmt::format("{:g} % quantile of {} &#8804; {}", 100 * c.level, EscapeXml(Label(c.output)), Num(c.upper));
  }
  return fmt::format("fraction with {} &#8804; {} at least {}", EscapeXml(Label(c.output)), Num(c.upper),
                     Percent(c.level));
}

// A judged quantity in the constraint's terms: a quantile in the output's unit, a yield in %.
std::string Estimate(const analysis::Constraint& c, const analysis::ConstraintJudgement& j) {
  // The screening rung bounds its error in D_trajectory only: it leaves other outputs unjudged.
  if (j.verdict == analysis::Verdict::kUnknown) return "not judged";
  if (c.kind == analysis::ConstraintKind::kYield) {
    return YieldWithInterval({.trials = j.samples, .value = j.estimate, .interval = j.interval});
  }
  return Num(j.estimate) + " " + Interval(j.interval);
}

// A margin in its unit: µm to the nanometre they resolve (Micrometres), others as numbers.
std::string MarginText(double margin, const std::string& unit) {
  return EscapeXml(unit == "µm" ? Micrometres(margin) : fmt::format("{} {}", Num(margin), unit));
}

std::string Classes(const AllocationReport& report, const CandidateReport& c) {
  std::string text;
  for (std::size_t k = 0; k < c.classes.size(); ++k) {
    text += fmt::format("{}{} {}", k == 0 ? "" : ", ", EscapeXml(SourceLabel(report.identity.components[k])),
                        EscapeXml(c.classes[k]));
  }
  return text;
}

std::string Yield(const CandidateReport& c) {
  if (c.outcome.yield.trials == 0) return "-";
  return YieldWithInterval(c.outcome.yield);
}

std::string SettledBy(const CandidateReport& c) {
  return c.outcome.settled_by ? std::string(NameOf(kEvaluationRoleNames, *c.outcome.settled_by)) : "-";
}

std::string Verdict(const CandidateReport& c) {
  return std::string(NameOf(analysis::kVerdictNames, c.outcome.verdict));
}

std::string Decide(std::int64_t samples) {
  return samples < 0 ? "none: its estimate sits on the limit" : fmt::format("about {}", samples);
}

void PageHead(std::string& html, const AllocationReport& report) {
  const AllocationIdentity& id = report.identity;
  OpenPage(html, "ringtol allocation: " + id.allocation_path);
  html += fmt::format(
      "<p class=\"meta\">Results {} &#183; design {} &#183; confirming solver {} &#183; screen {} &#183; search {} "
      "&#183; seed {} &#183; up to {} samples per candidate &#183; ringtol {} (ran with {}) &#183; catalogue {}</p>\n",
      EscapeXml(report.results.string()), EscapeXml(id.design), EscapeXml(id.solver), EscapeXml(id.screen),
      EscapeXml(id.search), id.seed, id.samples, RINGTOL_VERSION, EscapeXml(id.ringtol_version),
      EscapeXml(id.catalogue_version));
}

// What each component gets, against the current design, and what each constraint keeps.
void RecommendationTable(std::string& html, const AllocationReport& report, const CandidateReport& c) {
  const AllocationIdentity& id = report.identity;
  const CandidateReport* reference = id.reference ? &At(report, *id.reference) : nullptr;
  html += "<table>\n<tr><th>component</th><th>class</th><th>characteristic tolerance</th><th>cost</th>";
  html += reference ? "<th>current design</th></tr>\n" : "</tr>\n";
  for (std::size_t k = 0; k < c.classes.size(); ++k) {
    const AllocationIdentity::Option& o = id.options[k][static_cast<std::size_t>(c.outcome.options[k])];
    html += fmt::format("<tr><td>{}</td><td><b>{}</b></td><td>{} {}</td><td>{}</td>",
                        EscapeXml(SourceLabel(id.components[k])), EscapeXml(c.classes[k]), Num(o.tolerance),
                        id.components[k] == "springs" ? "%" : "µm", Num(o.cost));
    html += reference ? fmt::format("<td>{}</td></tr>\n", EscapeXml(reference->classes[k])) : "</tr>\n";
  }
  html += "</table>\n<table>\n";
  Row(html, {"constraint", fmt::format("estimate [{:g} % interval]", 100 * id.confidence), "margin", "verdict"}, true);
  for (std::size_t k = 0; k < c.outcome.constraints.size(); ++k) {
    const analysis::ConstraintJudgement& j = c.outcome.constraints[k];
    Row(html, {ConstraintHtml(id.constraints[k]), Estimate(id.constraints[k], j),
               MarginText(c.margins[k], report.margin_units[k]),
               std::string(NameOf(analysis::kVerdictNames, j.verdict))});
  }
  html += "</table>\n";
  if (const std::optional<std::string> reading = ConstrainedErrorMotionReading(id)) {
    html += fmt::format("<p class=\"note\">Error motion: {}.</p>\n", EscapeXml(*reading));
  }
}

void AnswerSection(std::string& html, const AllocationReport& report) {
  const AllocationIdentity& id = report.identity;
  html += "<div class=\"answer\" id=\"answer\">\n";
  if (report.recommendation) {
    const CandidateReport& c = At(report, *report.recommendation);
    html += fmt::format("<p>Recommended (candidate {}): <b>{}</b>.</p>\n", c.index, Classes(report, c));
    html += fmt::format(
        "<p>Cost {} {}, {} times the loosest; yield {} ({:g} % interval), from {} samples of the {} rung.</p>\n",
        Num(c.outcome.relative_cost),
        id.reference ? "relative to the current design" : "relative to the loosest candidate",
        Num(c.relative_to_loosest), Yield(c), 100 * id.confidence, c.outcome.samples, SettledBy(c));
    const bool quantiles = std::any_of(id.constraints.begin(), id.constraints.end(), [](const analysis::Constraint& k) {
      return k.kind == analysis::ConstraintKind::kQuantile;
    });
    if (quantiles) {
      html += fmt::format(
          "<p class=\"note\">The yield counts the samples within every limit at once; each quantile constraint "
          "below is judged on its own output, at its own level, from the same {} samples. So the verdict and the "
          "yield answer different questions: every quantile limit can be met while the yield is below each "
          "quantile's level, and a yield of 100 % from {} samples says only that the share outside is below the "
          "interval's far end (a campaign of more samples of the same classes may find a few).</p>\n",
          c.outcome.samples, c.outcome.samples);
    }
    RecommendationTable(html, report, c);
    if (!report.alternatives.empty()) {
      html += "<p>Next cheapest feasible:</p>\n<ul>\n";
      for (const std::int64_t i : report.alternatives) {
        const CandidateReport& a = At(report, i);
        html += fmt::format("<li>candidate {}: {} &#8212; cost {}, yield {}</li>\n", a.index, Classes(report, a),
                            Num(a.outcome.relative_cost), Yield(a));
      }
      html += "</ul>\n";
    }
  } else if (!report.complete) {
    html += "<p><b>No candidate is known to be feasible yet</b>: the search has not run to its end.</p>\n";
  } else {
    html += "<p><b>No candidate is feasible</b>: not even the tightest classes meet every constraint.</p>\n";
    if (report.tightest) {
      const CandidateReport& t = At(report, *report.tightest);
      html += fmt::format("<p>The tightest candidate ({}: {}) fails ", t.index, Classes(report, t));
      if (report.binding.empty()) {
        html += "no constraint outright: its verdict is " + Verdict(t) + ".</p>\n";
      } else {
        html += "the binding constraints:</p>\n<ul>\n";
        for (const int k : report.binding) {
          const analysis::Constraint& c = id.constraints[static_cast<std::size_t>(k)];
          const bool judged = static_cast<std::size_t>(k) < t.outcome.constraints.size();
          html += fmt::format(
              "<li class=\"binding\">{}: {}</li>\n", ConstraintHtml(c),
              judged ? fmt::format("estimate {}, short by {}",
                                   Estimate(c, t.outcome.constraints[static_cast<std::size_t>(k)]),
                                   MarginText(-t.margins[static_cast<std::size_t>(k)],
                                              report.margin_units[static_cast<std::size_t>(k)]))
                     : std::string("not judged"));
        }
        html += "</ul>\n<p>Loosen these limits, or add tighter classes for the components that dominate them.</p>\n";
      }
    }
  }
  if (!report.undecided_cheaper.empty()) {
    html += fmt::format(
        "<p class=\"warn\">{} cheaper candidate{} stayed undecided at {} samples: the recommendation holds only if "
        "{} infeasible. Samples that would decide {}:</p>\n<ul>\n",
        report.undecided_cheaper.size(), report.undecided_cheaper.size() == 1 ? "" : "s", id.samples,
        report.undecided_cheaper.size() == 1 ? "it is" : "they are",
        report.undecided_cheaper.size() == 1 ? "it" : "them");
    for (const std::int64_t i : report.undecided_cheaper) {
      const CandidateReport& u = At(report, i);
      html += fmt::format("<li class=\"undecided\">candidate {}: {} &#8212; cost {}, {} samples</li>\n", u.index,
                          Classes(report, u), Num(u.outcome.relative_cost), Decide(u.samples_to_decide));
    }
    html += "</ul>\n";
  }
  if (!report.complete) {
    html += "<p class=\"warn\">The search did not run to its end (interrupted, or still running): resume it with "
            "<code>ringtol allocate --resume</code>; what is shown may change.</p>\n";
  }
  html += "</div>\n";
}

struct Marks {
  analysis::Verdict verdict;
  std::string name;
  svg::Series::Marker marker;
  int colour;
};

// Feasible, infeasible and undecided by marker and colour, so that the legend reads in grey.
constexpr int kFeasibleColour = 5, kInfeasibleColour = 3, kUndecidedColour = 1, kFrontColour = 0, kChosenColour = 2;

std::string ParetoSvg(const AllocationReport& report) {
  svg::Chart chart;
  chart.title = "Cost against yield of every simulated candidate";
  chart.x.label = report.identity.reference ? "cost relative to the current design" : "cost relative to the loosest";
  chart.y.label = "yield (within every limit)";
  chart.height = 420.0;
  // The yields of a tolerance choice crowd below 1: the axis spans them, not [0, 1], and
  // keeps room above 1 for the recommendation's label below the legend.
  double lowest = 1.0;
  for (const std::int64_t i : report.simulated) {
    const CandidateReport& c = At(report, i);
    if (c.outcome.yield.trials > 0) lowest = std::min(lowest, c.outcome.yield.value);
  }
  chart.y.min = std::max(0.0, std::floor(20.0 * lowest) / 20.0 - 0.05);
  chart.y.max = 1.0 + 0.1 * (1.0 - *chart.y.min);
  const std::vector<Marks> marks = {
      {analysis::Verdict::kFeasible, "feasible", svg::Series::Marker::kCircle, kFeasibleColour},
      {analysis::Verdict::kInfeasible, "infeasible", svg::Series::Marker::kSquare, kInfeasibleColour},
      {analysis::Verdict::kUndecided, "undecided", svg::Series::Marker::kTriangle, kUndecidedColour}};
  svg::Series front{.name = "Pareto front", .style = svg::Series::Style::kLine, .colour = kFrontColour};
  for (const std::int64_t i : report.front) {
    const CandidateReport& c = At(report, i);
    front.x.push_back(c.outcome.relative_cost);
    front.y.push_back(c.outcome.yield.trials > 0 ? c.outcome.yield.value : std::numeric_limits<double>::quiet_NaN());
  }
  chart.series.push_back(std::move(front));
  for (const Marks& m : marks) {
    svg::Series points{.name = m.name, .style = svg::Series::Style::kPoints, .marker = m.marker, .colour = m.colour};
    for (const std::int64_t i : report.simulated) {
      const CandidateReport& c = At(report, i);
      if (c.outcome.verdict != m.verdict || c.outcome.yield.trials == 0) continue;
      points.x.push_back(c.outcome.relative_cost);
      points.y.push_back(c.outcome.yield.value);
    }
    if (!points.x.empty()) chart.series.push_back(std::move(points));
  }
  if (report.recommendation) {
    const CandidateReport& c = At(report, *report.recommendation);
    chart.series.push_back({.name = "recommended",
                            .x = {c.outcome.relative_cost},
                            .y = {c.outcome.yield.value},
                            .style = svg::Series::Style::kRings,
                            .colour = kChosenColour,
                            .labels = {fmt::format("recommended: {}", c.index)}});
  }
  for (const analysis::Constraint& c : report.identity.constraints) {
    if (c.kind == analysis::ConstraintKind::kYield) {
      chart.lines.push_back({svg::ReferenceLine::Direction::kHorizontal, c.level,
                             fmt::format("required {} of {}", Percent(c.level), Label(c.output))});
    }
  }
  return svg::RenderChart(chart);
}

void FrontTable(std::string& html, const AllocationReport& report, const std::vector<std::int64_t>& rows) {
  const AllocationIdentity& id = report.identity;
  html += "<table class=\"front\">\n<tr><th>candidate</th>";
  for (const std::string& component : id.components) html += "<th>" + EscapeXml(SourceLabel(component)) + "</th>";
  html += fmt::format("<th>relative cost</th><th>yield [{:g} % interval]</th>", 100 * id.confidence);
  for (const analysis::Constraint& c : id.constraints) html += "<th>" + ConstraintHtml(c) + "</th>";
  html += "<th>verdict</th><th>settled by</th><th>samples</th></tr>\n";
  for (const std::int64_t i : rows) {
    const CandidateReport& c = At(report, i);
    const bool chosen = report.recommendation && *report.recommendation == i;
    html += fmt::format("<tr class=\"{}\" data-candidate=\"{}\"><td>{}{}</td>", chosen ? "highlight" : Verdict(c),
                        c.index, c.index, chosen ? " (recommended)" : "");
    for (const std::string& name : c.classes) html += "<td>" + EscapeXml(name) + "</td>";
    html += fmt::format("<td>{}</td><td>{}</td>", Num(c.outcome.relative_cost), Yield(c));
    for (std::size_t k = 0; k < id.constraints.size(); ++k) {
      html += "<td>" +
              (k < c.outcome.constraints.size() ? Estimate(id.constraints[k], c.outcome.constraints[k]) : "-") +
              "</td>";
    }
    html += fmt::format("<td>{}</td><td>{}</td><td>{}</td></tr>\n", Verdict(c), SettledBy(c), c.outcome.samples);
  }
  html += "</table>\n";
}

void FrontSection(std::string& html, const AllocationReport& report) {
  html += "<h2 id=\"front\">Cost against yield</h2>\n";
  html += Figure(ParetoSvg(report),
                 "Each simulated candidate at its cost and its yield (the fraction of its samples within every "
                 "limit): circles feasible, squares infeasible, triangles undecided; the line joins the Pareto "
                 "front (no candidate is both cheaper and of higher yield); the ring marks the recommendation.");
  html += "<h3>The Pareto front, by cost</h3>\n";
  FrontTable(html, report, report.front);
  html += fmt::format("<details><summary>Every simulated candidate ({})</summary>\n", report.simulated.size());
  FrontTable(html, report, report.simulated);
  html += "</details>\n";
}

void RecommendedSection(std::string& html, const AllocationReport& report) {
  if (!report.recommendation) return;
  const CandidateReport& c = At(report, *report.recommendation);
  html += fmt::format("<h2 id=\"recommendation\">The recommendation's distributions (candidate {})</h2>\n", c.index);
  html += fmt::format("<p>From its {} samples of the {} rung (sample 0 onwards, common to every candidate).</p>\n",
                      c.outcome.samples, SettledBy(c));
  for (const RecommendedOutput& out : report.recommended_outputs) {
    const OutputReport& d = out.distribution;
    html += fmt::format("<h3>{}</h3>\n", EscapeXml(Label(d.name)));
    if (!d.distribution) {
      html += "<p>No sample finished ok.</p>\n";
      continue;
    }
    html += "<div class=\"charts\">\n";
    html += Figure(HistogramSvg(d), "Histogram of the ok samples; dashed: the tightest limit a constraint sets.");
    html += Figure(CdfSvg(d), "Fraction of assemblies at or below each value.");
    html += "</div>\n";
    DistributionTable(html, d, report.identity.confidence);
    if (!out.sensitivity) {
      html += fmt::format("<p class=\"note\">No sensitivities: {}.</p>\n", EscapeXml(out.sensitivity_problem));
      continue;
    }
    const OutputSensitivity& s = *out.sensitivity;
    html += fmt::format(
        "<p>Which component still dominates: a screening of {} samples on their design points (every candidate "
        "draws the same points, so the ranks are those of the drawn values): standardised regression coefficients on "
        "values (R&#178; = {}) and ranks (R&#178; = {}), grouped by error source, one allocated component each, and a "
        "given-data first-order estimate per input. Sobol' indices need a Saltelli design, which an allocation does "
        "not run.</p>\n",
        s.rows, s.r2 ? fmt::format("{:.3f}", *s.r2) : "n/a", s.rank_r2 ? fmt::format("{:.3f}", *s.rank_r2) : "n/a");
    if (const SensitivityLevel* by_source = FindLevel(s, "source")) {
      ContributorsBySource(html, *by_source, false);
    } else {
      html += "<p class=\"note\">Every input belongs to one source: there is nothing to rank by source.</p>\n";
    }
    html += fmt::format("<details><summary>Every input ({})</summary>\n", s.levels.front().entries.size());
    SensitivityTable(html, s.levels.front(), false, 60);
    html += "</details>\n";
  }
}

void SearchSection(std::string& html, const AllocationReport& report) {
  html += "<h2 id=\"search\">What the search did</h2>\n<table>\n";
  Row(html, {"candidates", fmt::format("{}", report.candidates.size())});
  Row(html, {"simulated", fmt::format("{}", report.simulated_count)});
  Row(html, {"of which settled by the screen", fmt::format("{}", report.settled_by_screen)});
  Row(html, {"implied by a simulated candidate", fmt::format("{}", report.implied)});
  Row(html, {"costlier than the recommendation (not needed)", fmt::format("{}", report.costlier)});
  Row(html, {"not visited", fmt::format("{}", report.not_visited)});
  Row(html, {"samples simulated by the screening rung", fmt::format("{}", report.samples_screen)});
  Row(html, {"samples simulated by the confirming rung", fmt::format("{}", report.samples_confirm)});
  Row(html, {"common random numbers: variance gain", std::isnan(report.common_random_numbers_gain)
                                                          ? std::string("n/a (no simulated neighbour)")
                                                          : EscapeXml(CommonRandomGainText(report.common_random_numbers_gain))});
  Row(html, {"search ran to its end", report.complete ? "yes" : "no"});
  html += "</table>\n";
  html += "<p class=\"note\">The variance gain compares the recommendation with its cheapest simulated neighbour (one "
          "option looser) on the first constrained output: (Var a + Var b) / Var(a &#8722; b), the factor by which "
          "independent samples would need more of them to tell the two apart as precisely.</p>\n";
}

void MethodSection(std::string& html, const AllocationReport& report) {
  const AllocationIdentity& id = report.identity;
  html += fmt::format(
      "<h2 id=\"method\">How these numbers were made</h2>\n<ul class=\"note\">\n"
      "<li>Every candidate is one class per component; its cost is the sum of its classes' costs, relative to {}. "
      "Every candidate uses the same design points (common random numbers): sample i differs between candidates "
      "only by the classes' tolerances.</li>\n"
      "<li>A candidate is simulated in stages of {} samples, doubling up to {}. A cheap screening rung ({}) may "
      "settle it infeasible from its first stage, using its bound on its own D_trajectory error; otherwise the "
      "confirming rung runs until every constraint is decided or the samples run out (undecided).</li>\n"
      "<li>A constraint is decided only from a {:g} % interval: quantiles by distribution-free order-statistic "
      "intervals, yields by Clopper-Pearson; feasible when the whole interval is within the limit, infeasible when "
      "it is wholly beyond. A failed sample counts as beyond the limit. The margin is the limit less the interval's "
      "far end.</li>\n"
      "<li>The search ({}) skips candidates whose verdict follows from others': looser than an infeasible one is "
      "infeasible, tighter than a feasible one is feasible, and one costlier than the recommendation cannot change "
      "it. An undecided candidate never prunes.</li>\n"
      "<li>The yield on the chart is the fraction of the settling rung's samples within every limit at once.</li>\n"
      "<li>Every number here is in the JSON summary (<code>ringtol report --json</code>).</li>\n</ul>\n",
      id.reference ? fmt::format("the current design (candidate {})", *id.reference) : "the loosest candidate",
      id.first_samples, id.samples, EscapeXml(id.screen), 100 * id.confidence, EscapeXml(id.search));
}

}  // namespace

std::string AllocationReportHtml(const AllocationReport& report) {
  std::string html;
  PageHead(html, report);
  AnswerSection(html, report);
  FrontSection(html, report);
  RecommendedSection(html, report);
  SearchSection(html, report);
  MethodSection(html, report);
  html += "</body>\n</html>\n";
  return html;
}

}  // namespace ringtol::jobs
