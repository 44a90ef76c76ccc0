#include "jobs/report/html_parts.h"

#include <algorithm>
#include <cmath>
#include <string_view>

#include <fmt/format.h>

#include "jobs/campaign/sample_record.h"
#include "jobs/report/report_text.h"
#include "jobs/report/svg_chart.h"

namespace ringtol::jobs::html {

using svg::EscapeXml;

namespace {

// Sensitivity indices and regression shares: their bootstrap half-widths are hundredths.
constexpr int kIndexDecimals = 3;

// The page's own styles: system fonts, tables and figures that flow, and a print style
// sheet that keeps every chart, table and answer box whole on paper.
constexpr const char* kStyle = R"(
body { font-family: "DejaVu Sans", Arial, sans-serif; color: #111; max-width: 60rem; margin: 1.5rem auto;
       padding: 0 1rem; line-height: 1.4; }
h1 { font-size: 1.5rem; margin-bottom: 0.2rem; }
h2 { font-size: 1.2rem; border-bottom: 1px solid #999; margin-top: 2rem; }
h3 { font-size: 1.05rem; }
table { border-collapse: collapse; margin: 0.6rem 0; font-size: 0.9rem; }
th, td { border: 1px solid #bbb; padding: 0.2rem 0.5rem; text-align: right; }
th:first-child, td:first-child { text-align: left; }
.meta { color: #444; font-size: 0.9rem; }
.answer { border: 2px solid #333; padding: 0.6rem 1rem; background: #f4f4f4; }
.answer p { margin: 0.3rem 0; }
.warn { border-left: 4px solid #b35806; padding-left: 0.6rem; }
.charts { display: flex; flex-wrap: wrap; gap: 1rem; }
.charts figure { flex: 1 1 26rem; margin: 0; }
.charts figure.alone { flex: 0 1 32rem; }
figure svg { width: 100%; height: auto; }
figcaption { font-size: 0.85rem; color: #333; }
.highlight { font-weight: bold; }
table.front { font-size: 0.8rem; }
table.limits td + td { white-space: nowrap; }
.note { font-size: 0.85rem; color: #333; }
@media print {
  body { max-width: none; margin: 0; font-size: 10pt; }
  h2 { break-after: avoid; }
  figure, table, .answer { break-inside: avoid; }
  details > *:not(summary) { display: block; }
}
)";

}  // namespace

std::string Num(double value) { return std::isfinite(value) ? fmt::format("{:.4g}", value) : "unbounded"; }

std::string Interval(const analysis::Interval& i) { return fmt::format("[{}, {}]", Num(i.lower), Num(i.upper)); }

std::string PercentInterval(const analysis::Interval& i) {
  return fmt::format("[{}, {}]", Percent(i.lower), Percent(i.upper));
}

std::string Quantity(std::string_view name) { return OutputNamed(name).label; }

std::string Unit(std::string_view name) { return OutputNamed(name).unit; }

std::string Label(std::string_view name) { return fmt::format("{} [{}]", Quantity(name), Unit(name)); }

std::string SourceLabel(std::string_view name) {
  std::string out(name);
  std::replace(out.begin(), out.end(), '_', ' ');
  return out;
}

const SensitivityLevel* FindLevel(const OutputSensitivity& s, std::string_view level) {
  for (const SensitivityLevel& l : s.levels) {
    if (l.level == level) return &l;
  }
  return nullptr;
}

std::string_view PageStyle() { return kStyle; }

void OpenPage(std::string& html, std::string_view title) {
  html += "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n";
  html += fmt::format("<title>{}</title>\n", EscapeXml(title));
  html += fmt::format("<style>{}</style>\n</head>\n<body>\n", kStyle);
  html += fmt::format("<h1>{}</h1>\n", EscapeXml(title));
}

void Row(std::string& html, std::initializer_list<std::string> cells, bool header) {
  html += "<tr>";
  const char* tag = header ? "th" : "td";
  for (const std::string& cell : cells) html += fmt::format("<{0}>{1}</{0}>", tag, cell);
  html += "</tr>\n";
}

std::string Figure(const std::string& svg_text, const std::string& caption, FigureWidth width) {
  return fmt::format("<figure{}>{}<figcaption>{}</figcaption></figure>\n",
                     width == FigureWidth::kAlone ? " class=\"alone\"" : "", svg_text, EscapeXml(caption));
}

std::vector<svg::ReferenceLine> SpecLines(const OutputReport& out) {
  std::vector<svg::ReferenceLine> lines;
  if (out.upper_spec_limit) {
    lines.push_back({svg::ReferenceLine::Direction::kVertical, *out.upper_spec_limit,
                     fmt::format("spec {}", Num(*out.upper_spec_limit))});
  }
  return lines;
}

std::string HistogramSvg(const OutputReport& out) {
  const analysis::DistributionSummary& d = *out.distribution;
  svg::HistogramChart chart;
  chart.title = "Distribution of " + Label(out.name);
  chart.x.label = Label(out.name);
  chart.lower = d.histogram.lower;
  chart.bin_width = d.histogram.bin_width;
  chart.counts.assign(d.histogram.counts.begin(), d.histogram.counts.end());
  chart.lines = SpecLines(out);
  return svg::RenderHistogram(chart);
}

std::string CdfSvg(const OutputReport& out) {
  const analysis::DistributionSummary& d = *out.distribution;
  svg::Chart chart;
  chart.title = "Empirical CDF of " + Label(out.name);
  chart.x.label = Label(out.name);
  chart.y.label = "fraction of assemblies";
  chart.y.min = 0.0;
  chart.y.max = 1.0;
  svg::Series series;
  series.name = "empirical CDF";
  series.style = svg::Series::Style::kStep;
  for (const analysis::EcdfPoint& p : d.ecdf) {
    series.x.push_back(p.value);
    series.y.push_back(p.probability);
  }
  chart.series.push_back(std::move(series));
  chart.lines = SpecLines(out);
  chart.lines.push_back({svg::ReferenceLine::Direction::kHorizontal, kReportQuantile, "99 %"});
  return svg::RenderChart(chart);
}

void DistributionTable(std::string& html, const OutputReport& out, double confidence) {
  const analysis::DistributionSummary& d = *out.distribution;
  html += "<table>\n";
  Row(html, {"statistic", "value", fmt::format("{:g} % interval", 100 * confidence)}, true);
  Row(html, {"ok samples", fmt::format("{}", d.count), ""});
  Row(html, {"mean", Num(d.mean), ""});
  Row(html, {"standard deviation", Num(d.standard_deviation), ""});
  Row(html, {"min / max", Num(d.min) + " / " + Num(d.max), ""});
  for (const analysis::QuantileEstimate& q : d.quantiles) {
    Row(html, {fmt::format("{:g} % quantile", 100 * q.probability), Num(q.value), Interval(q.interval)});
  }
  if (out.upper_spec_limit) {
    Row(html, {"upper spec limit", Num(*out.upper_spec_limit), ""});
    const analysis::Capability& c = d.capability;
    Row(html, {"Cpu = Cpk (normal theory)", c.cpu ? CapabilityIndex(*c.cpu) : "-", ""});
    Row(html,
        {"Cpk (percentile method, ISO 22514-2)",
         c.cpk_percentile ? CapabilityIndex(*c.cpk_percentile) + (c.percentile_extrapolated ? " (too few samples)" : "")
                          : "-",
         ""});
    Row(html, {"Cp", "needs two limits", ""});
    if (d.within_spec) {
      Row(html, {"within spec (failures excluded)", YieldWithInterval(*d.within_spec), ""});
    }
    if (out.within_spec_counting_failures) {
      Row(html, {"within spec (failures counted as out)", YieldWithInterval(*out.within_spec_counting_failures), ""});
    }
  }
  html += "</table>\n";
}

std::string Index(const analysis::SobolIndex& index) {
  return fmt::format("{} ± {}", Decimals(index.value, kIndexDecimals), Decimals(index.conf, kIndexDecimals));
}

// Sensitivity bars of one level: S1 (and ST) with their intervals.
std::string SensitivitySvg(const SensitivityLevel& level, const std::string& title, bool sobol,
                           const std::vector<bool>& highlighted, const std::string& highlight_label,
                           const std::vector<std::string>& categories,
                           const std::vector<const SensitivityEntry*>& entries) {
  svg::BarChart chart;
  chart.title = title;
  chart.categories = categories;
  chart.highlighted = highlighted;
  chart.highlight_label = highlight_label;

  // Screening: a group's shares of the linear and the rank regression (sums of SRC^2 and
  // SRRC^2); an input's given-data first order beside its SRC^2.
  const bool group = !sobol && level.level != "input";
  chart.value.label = sobol ? "Sobol' index" : (group ? "share of the output's variance" : "index");
  svg::Bars s1{
      sobol ? "first order S1" : (group ? "linear share (sum of SRC^2)" : "first order (given data)"), {}, {}, {}, 0};
  svg::Bars second{sobol ? "total ST" : (group ? "rank share (sum of SRRC^2)" : "SRC^2"), {}, {}, {}, 1};
  for (const SensitivityEntry* e : entries) {
    if (group) {
      s1.value.push_back(e->src);
      second.value.push_back(e->srrc);
      continue;
    }
    s1.value.push_back(e->first_order.value);
    s1.lower.push_back(e->first_order.interval.lower);
    s1.upper.push_back(e->first_order.interval.upper);
    if (e->total_order) {
      second.value.push_back(e->total_order->value);
      second.lower.push_back(e->total_order->interval.lower);
      second.upper.push_back(e->total_order->interval.upper);
    } else {
      second.value.push_back(e->src * e->src);
    }
  }
  chart.series.push_back(std::move(s1));
  chart.series.push_back(std::move(second));
  return svg::RenderBarChart(chart);
}

void SensitivityTable(std::string& html, const SensitivityLevel& level, bool sobol, std::size_t limit) {
  html += "<table>\n";
  const bool group = !sobol && level.level != "input";
  if (sobol) {
    Row(html, {"group", "S1 ± conf", "S1 interval", "ST ± conf", "ST interval"}, true);
  } else if (group) {
    Row(html, {"group", "sum of SRC&#178;", "sum of SRRC&#178;"}, true);
  } else {
    Row(html, {"input", "first order ± conf", "SRC", "SRRC"}, true);
  }
  std::size_t shown = 0;
  for (const SensitivityEntry& e : level.entries) {
    if (shown++ == limit) break;
    if (sobol) {
      Row(html, {EscapeXml(SourceLabel(e.name)), Index(e.first_order), Interval(e.first_order.interval),
                 Index(*e.total_order), Interval(e.total_order->interval)});
    } else if (group) {
      Row(html, {EscapeXml(SourceLabel(e.name)), Decimals(e.src, kIndexDecimals), Decimals(e.srrc, kIndexDecimals)});
    } else {
      Row(html, {EscapeXml(e.name), Index(e.first_order), Decimals(e.src, kIndexDecimals),
                 Decimals(e.srrc, kIndexDecimals)});
    }
  }
  html += "</table>\n";
  if (level.entries.size() > limit) {
    html += fmt::format("<p class=\"note\">{} more in the JSON summary.</p>\n", level.entries.size() - limit);
  }
}

// Contributors: by source when the design allows, with what to tighten first.
void ContributorsBySource(std::string& html, const SensitivityLevel& by_source, bool sobol) {
  html += "<h3>Contributors by error source</h3>\n";
  if (!by_source.entries.empty()) {
    const SensitivityEntry& top = by_source.entries.front();
    html += fmt::format("<p class=\"answer\">Tighten <b>{}</b> first: it carries {} of the variance{}.</p>\n",
                        EscapeXml(SourceLabel(top.name)),
                        top.total_order ? fmt::format("ST = {}", Index(*top.total_order))
                                        : fmt::format("a share of {} in the linear fit (sum of SRC&#178;) "
                                                      "and {} in the rank fit (sum of SRRC&#178;)",
                                                      Decimals(top.src, kIndexDecimals),
                                                      Decimals(top.srrc, kIndexDecimals)),
                        sobol && by_source.aggregation == Aggregation::kBounds ? " (a sum over its parts)" : "");
  }
  std::vector<std::string> categories;
  std::vector<const SensitivityEntry*> entries;
  for (const SensitivityEntry& e : by_source.entries) {
    categories.push_back(SourceLabel(e.name));
    entries.push_back(&e);
  }
  html += Figure(SensitivitySvg(by_source, "Sensitivity by error source", sobol, {}, "", categories, entries),
                 !sobol ? "Shares of the variance the source's inputs explain in the linear and the rank fit."
                 : by_source.aggregation == Aggregation::kExact
                     ? "Each source frozen as one group by the design."
                     : "Sums over the design's smaller groups: the S1 sum is at most the source's S1, the ST sum "
                       "at least its ST; ± adds the parts' half-widths in quadrature.");
  SensitivityTable(html, by_source, sobol, 12);
}

}  // namespace ringtol::jobs::html
