#include "jobs/report/report_html.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string_view>

#include <fmt/format.h>

#include "engine/units.h"
#include "jobs/report/campaign_summary.h"
#include "jobs/report/html_parts.h"
#include "jobs/report/report_text.h"
#include "jobs/report/svg_chart.h"

namespace ringtol::jobs {
namespace {

using svg::EscapeXml;
using namespace html;  // the pieces the allocation report shares

const OutputReport* Find(const CampaignReport& report, std::string_view name) {
  for (const OutputReport& out : report.outputs) {
    if (out.name == name) return &out;
  }
  return nullptr;
}

const OutputSensitivity* FindSensitivity(const CampaignReport& report, std::string_view name) {
  for (const OutputSensitivity& s : report.sensitivities) {
    if (s.output == name) return &s;
  }
  return nullptr;
}

std::string ConvergenceQuantileSvg(const OutputReport& out) {
  svg::Chart chart;
  chart.title = fmt::format("{:g} % quantile of {} against sample count", 100 * kReportQuantile, Label(out.name));
  chart.x.label = "independent samples";
  chart.x.log2 = true;
  chart.y.label = Label(out.name);
  svg::Series series;
  series.name = "estimate with its interval";
  for (const analysis::ConvergencePoint& p : out.convergence) {
    series.x.push_back(static_cast<double>(p.samples));
    series.y.push_back(p.quantile.value);
    series.band_lower.push_back(p.quantile.interval.lower);
    series.band_upper.push_back(p.quantile.interval.upper);
  }
  chart.series.push_back(std::move(series));
  if (out.upper_spec_limit) {
    chart.lines.push_back({svg::ReferenceLine::Direction::kHorizontal, *out.upper_spec_limit, "spec"});
  }
  return svg::RenderChart(chart);
}

std::string ConvergenceYieldSvg(const OutputReport& out) {
  svg::Chart chart;
  chart.title = "Fraction within spec against sample count";
  chart.x.label = "independent samples";
  chart.x.log2 = true;
  chart.y.label = "within spec";
  chart.y.max = 1.0;
  svg::Series series;
  series.name = "estimate with its interval";
  series.colour = 1;
  for (const analysis::ConvergencePoint& p : out.convergence) {
    if (!p.within_spec) continue;
    series.x.push_back(static_cast<double>(p.samples));
    series.y.push_back(p.within_spec->value);
    series.band_lower.push_back(p.within_spec->interval.lower);
    series.band_upper.push_back(p.within_spec->interval.upper);
  }
  chart.series.push_back(std::move(series));
  return svg::RenderChart(chart);
}

// What the indices are, how they were estimated, and what may bias them.
void SensitivityIntro(std::string& html, const CampaignReport& report, const OutputSensitivity& s) {
  const bool sobol = s.method == "sobol";
  html += "<h2 id=\"sensitivity\">Which tolerance to tighten first</h2>\n";
  if (sobol) {
    html += fmt::format(
        "<p>Sobol' indices of {} from the Saltelli pick-and-freeze design ({} rows; estimators {}; "
        "± is the half-width of the {:g} % bootstrap interval, SALib's <code>S1_conf</code>). S1 is the share of the "
        "variance a group explains alone, ST its share with every interaction it takes part in; ST &#8805; S1 up to "
        "error.{}</p>\n",
        EscapeXml(Label(s.output)), s.rows, EscapeXml(s.estimator), 100 * report.options.confidence,
        s.rows_for_precision
            ? fmt::format(" About {} rows would bring every ST half-width to 0.05.", *s.rows_for_precision)
            : "");
  } else {
    html += fmt::format(
        "<p>The campaign's {} design has no pick-and-freeze matrices, so Sobol' indices cannot be estimated; this is a "
        "screening of {} of its samples: a given-data estimate of each input's first-order index (variance of the "
        "output's mean over classes of the input), and standardised regression coefficients on values (SRC, "
        "R&#178; = {}) and ranks (SRRC, R&#178; = {}). Groups (error sources, harmonic orders) are measured by the "
        "sum of their inputs' SRC&#178; and SRRC&#178;, their share of each fit. Caveats: regression shares mean "
        "something only where R&#178; is near 1; the first-order estimate misses interactions (an input that acts "
        "only with others scores 0) and carries a bias of up to &#177;(M &#8722; 1)/(n &#8722; 1) per input, whose "
        "sign depends on how stratified the design is, so it is shown per input only. Run a Saltelli design "
        "(<code>[design] kind = \"saltelli\"</code>) for total indices.</p>\n",
        EscapeXml(report.design), s.rows, s.r2 ? fmt::format("{:.3f}", *s.r2) : "n/a",
        s.rank_r2 ? fmt::format("{:.3f}", *s.rank_r2) : "n/a");
  }
  if (s.rows_pending > 0) {
    html += fmt::format("<p class=\"warn\">{} rows are not finished (pending samples) and were left out.</p>\n",
                        s.rows_pending);
  }
  if (s.rows_excluded > 0) {
    html += fmt::format("<p class=\"warn\">{} {} with a failed sample were excluded.</p>\n", s.rows_excluded,
                        sobol ? "rows" : "samples");
  }
  if (s.ab_correlation && s.rows > 0 && std::abs(*s.ab_correlation) > 3.0 / std::sqrt(static_cast<double>(s.rows))) {
    html += fmt::format(
        "<p class=\"warn\">The outputs of the A and B matrices correlate (r = {:.3f}; independent halves give 0 "
        "&#177; {:.3f}): the design's two halves are not independent, and every index below is biased. A Sobol' base "
        "with fewer points than twice the inputs repeats coordinates; use <code>base = \"monte_carlo\"</code> or "
        "more rows.</p>\n",
        *s.ab_correlation, 3.0 / std::sqrt(static_cast<double>(s.rows)));
  }
  if (sobol && report.redrawn > 0) {
    html += fmt::format(
        "<p class=\"warn\">{} of {} independent samples were redrawn by inspection (out-of-class parts rejected): "
        "a redrawn part no longer shares its coordinates between the matrices, which biases the indices of its "
        "source a little.</p>\n",
        report.redrawn, report.used);
  }
}

// The entry of the orders the order chart leaves out, summed.
SensitivityEntry OtherOrders(const std::vector<const SensitivityEntry*>& parts, bool sobol) {
  SensitivityEntry sum;
  sum.name = parts.size() == 1 ? "1 other order" : fmt::format("{} other orders", parts.size());
  std::vector<analysis::SobolIndex> first, total;
  for (const SensitivityEntry* e : parts) {
    first.push_back(e->first_order);
    if (e->total_order) total.push_back(*e->total_order);
    // The order level's screening entries already hold sums of squares: they add.
    sum.src += e->src;
    sum.srrc += e->srrc;
    sum.ranking += e->ranking;
  }
  sum.first_order = SumOfIndices(first, false);
  if (sobol) sum.total_order = SumOfIndices(total, true);
  return sum;
}

// By harmonic order, against the roller count: the orders that carry the variance, the
// rest summed into one bar.
void SensitivityByOrder(std::string& html, const CampaignReport& report, const SensitivityLevel& by_order, bool sobol) {
  std::vector<const SensitivityEntry*> orders;
  for (const SensitivityEntry& e : by_order.entries) {
    if (e.order > 0) orders.push_back(&e);
  }
  std::sort(orders.begin(), orders.end(),
            [](const SensitivityEntry* a, const SensitivityEntry* b) { return a->order < b->order; });
  if (orders.empty()) return;
  html += "<h3>Sensitivity by harmonic order</h3>\n";
  std::vector<double> ranking;
  for (const SensitivityEntry* e : orders) ranking.push_back(e->ranking);
  const std::vector<std::size_t> kept =
      OrdersCarryingVariance(ranking, report.options.order_chart_cumulative, report.options.order_chart_single);
  std::vector<const SensitivityEntry*> shown, others;
  for (std::size_t k = 0, next = 0; k < orders.size(); ++k) {
    const bool keep = next < kept.size() && kept[next] == k;
    (keep ? shown : others).push_back(orders[k]);
    if (keep) ++next;
  }
  std::vector<std::string> categories;
  std::vector<bool> highlighted;
  for (const SensitivityEntry* e : shown) {
    categories.push_back(fmt::format("order {}", e->order));
    highlighted.push_back(report.rollers > 0 && e->order % report.rollers == 0);
  }
  const SensitivityEntry rest = OtherOrders(others, sobol);
  if (!others.empty()) {
    categories.push_back(rest.name);
    highlighted.push_back(false);
    shown.push_back(&rest);
  }
  const std::string measure = sobol ? "ST" : "sum of SRC²";
  std::string caption = fmt::format(
      "Orders shown: the fewest that, taken largest first, together carry {:g} % of what all {} orders carry (by "
      "{}; a negative estimate counts as 0), and any other that carries at least {:g} %",
      100 * report.options.order_chart_cumulative, orders.size(), measure, 100 * report.options.order_chart_single);
  caption += others.empty() ? ": here every order. "
                            : fmt::format("; the other {} are summed into the last bar (every order is in the JSON "
                                          "summary). ",
                                          others.size());
  caption += fmt::format(
      "Highlighted: orders that are multiples of Z = {}. With Z rollers equally spaced, a ring harmonic whose order "
      "is a multiple of Z reaches every roller in the same phase: it swells and shrinks the ring at all contacts at "
      "once and pushes the centre along the spring axis, where other orders only make it circle.",
      report.rollers);
  html += Figure(SensitivitySvg(by_order, "Sensitivity by harmonic order (ring and rollers together)", sobol,
                                highlighted, fmt::format("multiple of the roller count Z = {}", report.rollers),
                                categories, shown),
                 caption);
  std::vector<const SensitivityEntry*> ranked = orders;
  std::stable_sort(ranked.begin(), ranked.end(),
                   [](const SensitivityEntry* a, const SensitivityEntry* b) { return a->ranking > b->ranking; });
  std::string top;
  for (std::size_t k = 0; k < std::min<std::size_t>(5, ranked.size()); ++k) {
    top += fmt::format("{}{}{}", k == 0 ? "" : ", ", ranked[k]->order,
                       report.rollers > 0 && ranked[k]->order % report.rollers == 0 ? " (multiple of Z)" : "");
  }
  html += fmt::format("<p>Dominant orders, largest first: {}.</p>\n", top);
}

void SensitivitySection(std::string& html, const CampaignReport& report, const OutputSensitivity& s) {
  const bool sobol = s.method == "sobol";
  SensitivityIntro(html, report, s);
  if (const SensitivityLevel* by_source = FindLevel(s, "source")) ContributorsBySource(html, *by_source, sobol);
  if (const SensitivityLevel* by_order = FindLevel(s, "order")) SensitivityByOrder(html, report, *by_order, sobol);
  const SensitivityLevel& finest = s.levels.front();
  html += fmt::format("<details><summary>Every {} ({})</summary>\n", sobol ? "design group" : "input",
                      finest.entries.size());
  SensitivityTable(html, finest, sobol, 60);
  html += "</details>\n";
}

// Orbit and sensor charts side by side: as tall as each other, about square plots.
constexpr double kOrbitChartWidth = 440.0, kOrbitChartHeight = 480.0;

// The centre's path relative to its enclosing circle's centre, equal-scaled.
std::string OrbitSvg(const ReplayedTrajectory& t) {
  svg::Chart chart;
  chart.title = fmt::format("Sample {}: ring centre, D_trajectory {} µm", t.index, Num(2 * t.circle_radius_um));
  chart.x.label = "x from the circle's centre [µm]";
  chart.y.label = "y from the circle's centre [µm]";
  chart.equal_aspect = true;
  chart.width = kOrbitChartWidth;
  chart.height = kOrbitChartHeight;
  svg::Series path{.name = "centre over one revolution", .colour = 0};
  for (std::size_t k = 0; k < t.x_um.size(); ++k) {
    path.x.push_back(t.x_um[k] - t.circle_x_um);
    path.y.push_back(t.y_um[k] - t.circle_y_um);
  }
  chart.series.push_back(std::move(path));
  chart.series.push_back({.name = "circle's centre", .x = {0.0}, .y = {0.0}, .style = svg::Series::Style::kPoints,
                          .colour = 2});
  chart.series.push_back({.name = "static equilibrium",
                          .x = {t.static_x_um - t.circle_x_um},
                          .y = {t.static_y_um - t.circle_y_um},
                          .style = svg::Series::Style::kRings,
                          .colour = 3});
  chart.circle = svg::Circle{0.0, 0.0, t.circle_radius_um, "smallest enclosing circle"};
  return svg::RenderChart(chart);
}

// The sensor's reading over the revolution, above its minimum, with max and min marked.
std::string SensorSvg(const ReplayedTrajectory& t) {
  svg::Chart chart;
  chart.title = fmt::format("Sample {}: sensor, TIR {} µm", t.index, Num(t.tir_um));
  chart.x.label = "ring angle ψ [deg]";
  chart.x.min = 0.0;
  chart.x.max = 360.0;
  chart.x.step = 90.0;
  chart.y.label = "reading above its minimum [µm]";
  chart.width = kOrbitChartWidth;
  chart.height = kOrbitChartHeight;
  chart.series.push_back({.name = "sensor reading", .x = t.angle_deg, .y = t.sensor_um, .colour = 0});
  chart.series.push_back({.name = "max and min",
                          .x = {t.max_angle_deg, t.min_angle_deg},
                          .y = {t.tir_um, 0.0},
                          .style = svg::Series::Style::kRings,
                          .colour = 3,
                          .labels = {fmt::format("max at {:.0f}°", t.max_angle_deg),
                                     fmt::format("min at {:.0f}°", t.min_angle_deg)}});
  chart.lines.push_back({svg::ReferenceLine::Direction::kHorizontal, t.tir_um,
                         fmt::format("TIR = max − min = {} µm", Num(t.tir_um))});
  chart.lines.push_back({svg::ReferenceLine::Direction::kHorizontal, 0.0, ""});
  return svg::RenderChart(chart);
}

void PageHead(std::string& html, const CampaignReport& report) {
  const CampaignIdentity& id = report.identity;
  OpenPage(html, "ringtol report: " + id.campaign_path);
  html += fmt::format(
      "<p class=\"meta\">Results {} &#183; design {} &#183; solver {} &#183; seed {} &#183; {} rollers &#183; "
      "ringtol {} (ran with {}) &#183; catalogue {}</p>\n",
      EscapeXml(report.results.string()), EscapeXml(report.design), EscapeXml(id.solver), id.seed, report.rollers,
      RINGTOL_VERSION, EscapeXml(id.ringtol_version), EscapeXml(id.catalogue_version));
  if (!report.schema_note.empty()) html += fmt::format("<p class=\"meta\">Note: {}</p>\n", EscapeXml(report.schema_note));
}

// With a spec, each limit with its 99 % quantile, its own yield and its percentile Cpk, then
// the yield within every limit at once.
void SpecAnswer(std::string& html, const CampaignReport& report) {
  const double confidence = report.options.confidence;
  std::vector<const OutputReport*> limited;
  for (const OutputReport& out : report.outputs) {
    if (out.upper_spec_limit && out.distribution && out.distribution->within_spec) limited.push_back(&out);
  }
  if (limited.empty()) return;
  html += fmt::format("<p>Against the spec, of the {} ok assemblies:</p>\n<table class=\"limits\">\n", report.ok);
  Row(html,
      {"limit", fmt::format("99 % of assemblies at most [{:g} % interval]", 100 * confidence),
       fmt::format("within the limit [{:g} % interval]", 100 * confidence), "Cpk (percentile)"},
      true);
  bool error_motion = false;
  for (const OutputReport* out : limited) {
    const analysis::DistributionSummary& d = *out->distribution;
    std::string q99 = "-";
    for (const analysis::QuantileEstimate& q : d.quantiles) {
      if (q.probability == kReportQuantile) q99 = Num(q.value) + " " + Interval(q.interval);
    }
    Row(html, {fmt::format("{} &#8804; {}", EscapeXml(Label(out->name)), Num(*out->upper_spec_limit)), q99,
               "<b>" + YieldWithInterval(*d.within_spec) + "</b>",
               d.capability.cpk_percentile ? CapabilityIndex(*d.capability.cpk_percentile) : "-"});
    error_motion = error_motion || ErrorMotionOf(out->name).has_value();
  }
  if (limited.size() > 1 && report.within_every_limit) {
    Row(html, {"every limit at once", "", "<b>" + YieldWithInterval(*report.within_every_limit) + "</b>", ""});
  }
  html += "</table>\n";
  if (report.done > report.ok && report.within_every_limit_counting_failures) {
    html += fmt::format("<p>Counting the {} failed samples as outside, {}: <b>{}</b>.</p>\n", report.done - report.ok,
                        limited.size() > 1 ? "every limit at once" : "within the limit",
                        YieldWithInterval(*report.within_every_limit_counting_failures));
  }
  if (error_motion) {
    html += fmt::format("<p class=\"note\">Error motion: {}.</p>\n",
                        EscapeXml(ErrorMotionConditions({.filter = report.identity.error_motion_filter})));
  }
}

// The answer first: what 99 % of the assemblies reach, or, with a spec, every limit with
// its own yield and the yield within all of them; how many samples say so.
void AnswerSection(std::string& html, const CampaignReport& report, const OutputReport* primary) {
  const double confidence = report.options.confidence;
  html += "<div class=\"answer\" id=\"answer\">\n";
  if (primary == nullptr || !primary->distribution) {
    html += "<p>No sample finished ok: there is no distribution to show.</p>\n";
  } else if (!primary->upper_spec_limit) {
    for (const analysis::QuantileEstimate& q : primary->distribution->quantiles) {
      if (q.probability != kReportQuantile) continue;
      html += fmt::format("<p>99 % of assemblies have {} &#8804; <b>{}</b> ({:g} % interval {}).</p>\n",
                          EscapeXml(Label(primary->name)), Num(q.value), 100 * confidence, Interval(q.interval));
    }
  } else {
    SpecAnswer(html, report);
  }
  if (report.disposition) {
    html += fmt::format("<p><strong>Disposition</strong>: {}.</p>\n", EscapeXml(DispositionSentence(*report.disposition)));
  }
  html += fmt::format("<p>{} of {} samples used are ok; {} failed; {} pending.</p>\n", report.ok, report.used,
                      report.done - report.ok, report.pending);
  if (const std::int64_t ran = RungsRan(report.settled_by); ran > 0) {
    html += fmt::format("<p>Rungs: {} (of the {} samples a rung ran on).</p>\n",
                        EscapeXml(RungShares(report.settled_by)), ran);
  }
  if (report.openings) html += fmt::format("<p>Contacts: {}.</p>\n", EscapeXml(OpeningsSentence(*report.openings)));
  if (!report.identity.life) html += fmt::format("<p>{}</p>\n", EscapeXml(LifeNotComputed()));
  if (report.life_missing > 0) {
    html += fmt::format("<p>{}.</p>\n", EscapeXml(LifeMissingSentence(report.life_missing, report.ok)));
  }
  for (const LifeGap& gap : report.life_gaps) html += fmt::format("<p>{}</p>\n", EscapeXml(LifeGapSentence(gap)));
  if (report.life_error_motion) {
    html += fmt::format("<p>{}</p>\n", EscapeXml(LifeErrorMotionSentence(*report.life_error_motion, report.identity.error_motion_filter)));
  }
  for (const PopulationView& view : report.populations) {
    html += fmt::format("<p>{}.</p>\n", EscapeXml(PopulationLine(view)));
  }
  html += "</div>\n";
}

void SamplesSection(std::string& html, const CampaignReport& report) {
  html += "<h2 id=\"samples\">Samples</h2>\n<table>\n";
  Row(html, {"samples in the campaign", fmt::format("{}", report.samples)});
  Row(html, {"independent draws (used for statistics)", fmt::format("{}", report.used)});
  Row(html, {"done / ok", fmt::format("{} / {}", report.done, report.ok)});
  Row(html, {"pending (not computed yet)", fmt::format("{}", report.pending)});
  Row(html, {"redrawn by inspection", fmt::format("{}", report.redrawn)});
  for (const auto& [status, count] : report.failures)
    Row(html, {"failed: " + EscapeXml(status), fmt::format("{}", count)});
  html += "</table>\n";
  if (report.done > report.ok) {
    html += fmt::format(
        "<p class=\"warn\">{} samples failed. They are excluded from every statistic below; the yield is also given "
        "counting them as outside the spec.</p>\n<table>\n",
        report.done - report.ok);
    Row(html, {"sample", "status", "message"}, true);
    for (const FailedSample& f : report.failed) {
      Row(html, {fmt::format("{}", f.index), EscapeXml(f.status), EscapeXml(f.message)});
    }
    html += "</table>\n";
    if (report.done - report.ok > static_cast<std::int64_t>(report.failed.size())) {
      html += fmt::format(
          "<p class=\"note\">The first {} are listed; every failed sample keeps its status and "
          "message in the results file.</p>\n",
          report.failed.size());
    }
  }
}

// A measured population's parts per harmonic order, beside the median and 95th percentile
// of the amplitudes its class draws there.
std::string PopulationSvg(const PopulationView& view) {
  svg::Chart chart;
  chart.title = fmt::format("{} population: amplitude per order, against {}", view.ring ? "Ring" : "Roller",
                            view.class_name.empty() ? std::string("no class") : view.class_name);
  chart.x.label = "harmonic order";
  chart.y.label = "amplitude [µm]";
  chart.y.min = 0.0;
  chart.x.step = 1.0;
  // The parts of one order spread over a third of an order, so that equal amplitudes stay apart.
  constexpr double kSpread = 1.0 / 3.0;
  svg::Series parts{.name = "measured parts", .style = svg::Series::Style::kPoints, .colour = 0};
  svg::Series median{.name = "measured median", .colour = 0};
  svg::Series class_median{.name = "class: median", .colour = 1, .dashed = true};
  svg::Series class_q95{.name = "class: 95th percentile", .colour = 2, .dashed = true};
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const double n = static_cast<double>(view.parts.size());
  for (std::size_t k = 0; k < view.orders.size(); ++k) {
    const OrderComparison& o = view.orders[k];
    const double x = o.order;
    for (std::size_t p = 0; p < view.parts.size(); ++p) {
      parts.x.push_back(n > 1 ? x + kSpread * (static_cast<double>(p) / (n - 1) - 0.5) : x);
      parts.y.push_back(view.parts[p].amplitudes_um[k]);
    }
    median.x.push_back(x);
    median.y.push_back(o.measured_median_um);
    class_median.x.push_back(x);
    class_median.y.push_back(o.class_median_um.value_or(kNaN));
    class_q95.x.push_back(x);
    class_q95.y.push_back(o.class_q95_um.value_or(kNaN));
  }
  chart.series = {std::move(parts), std::move(median), std::move(class_median), std::move(class_q95)};
  return svg::RenderChart(chart);
}

void PopulationSection(std::string& html, const CampaignReport& report) {
  if (report.populations.empty()) return;
  html += "<h2 id=\"measured-parts\">Measured parts</h2>\n";
  for (const PopulationView& view : report.populations) {
    html += fmt::format("<h3>The {} population</h3>\n<p>{}.</p>\n", view.ring ? "ring" : "roller",
                        EscapeXml(PopulationLine(view)));
    if (!view.class_name.empty()) {
      html += fmt::format(
          "<p class=\"note\">Each part is judged on its fitted form's {} against {}'s {} at {:g} mm{}; its size and "
          "eccentricity are shown, not judged. The class's columns are {} parts drawn from it{} by the campaign's "
          "sampler, with a fixed seed.</p>\n",
          EscapeXml(sampling::FormMeasureName(view.measure)), EscapeXml(view.class_name),
          Micrometres(view.class_limit_um), view.diameter_mm,
          view.class_chosen ? " (the report chose the class: the file names none)" : "", view.class_parts_drawn,
          view.mode == sampling::ToleranceMode::kInspected ? " as inspected" : "");
    }
    if (view.class_problem) html += fmt::format("<p class=\"warn\">{}.</p>\n", EscapeXml(*view.class_problem));
    html += "<div class=\"charts\">\n";
    html += Figure(PopulationSvg(view),
                   "Points: the parts' amplitudes (spread within each order); line: their median; dashed: the "
                   "class's median and 95th percentile.",
                   FigureWidth::kAlone);
    html += "</div>\n<table>\n";
    Row(html, {"order", "measured median [µm]", "measured largest [µm]", "class median [µm]", "class 95 % [µm]"},
        true);
    for (const OrderComparison& o : view.orders) {
      Row(html, {fmt::format("{}", o.order), Num(o.measured_median_um), Num(o.measured_max_um),
                 o.class_median_um ? Num(*o.class_median_um) : "-", o.class_q95_um ? Num(*o.class_q95_um) : "-"});
    }
    html += "</table>\n<table>\n";
    Row(html,
        {"part", view.ring ? "radius deviation [µm]" : "mean diameter deviation [µm]", "roundness RONt [µm]",
         view.ring ? "judged: RONt [µm]" : "judged: VDsp [µm]", "within the class"},
        true);
    for (const MeasuredPartView& p : view.parts) {
      Row(html, {EscapeXml(p.name), p.size_deviation_um ? Num(*p.size_deviation_um) : "-", Num(p.roundness_um),
                 Num(p.form_um), view.class_name.empty() ? "-" : (p.within_class ? "yes" : "<b>no</b>")});
    }
    html += "</table>\n";
  }
}

void DistributionSection(std::string& html, const OutputReport& primary, double confidence) {
  html += fmt::format("<h2 id=\"distribution\">Distribution of {}</h2>\n", EscapeXml(Label(primary.name)));
  html += "<div class=\"charts\">\n";
  html += Figure(HistogramSvg(primary), "Histogram of the ok independent samples; dashed: the spec limit.");
  html += Figure(CdfSvg(primary), "Fraction of assemblies at or below each value.");
  html += "</div>\n";
  DistributionTable(html, primary, confidence);
}

void ConvergenceSection(std::string& html, const CampaignReport& report, const OutputReport& primary) {
  const double confidence = report.options.confidence;
  html += "<h2 id=\"convergence\">Convergence and samples needed</h2>\n<div class=\"charts\">\n";
  html += Figure(ConvergenceQuantileSvg(primary),
                 "Estimate on the first n samples in design order, with its distribution-free interval.");
  if (primary.distribution->within_spec) {
    html += Figure(ConvergenceYieldSvg(primary), "Clopper-Pearson interval on the first n samples.");
  }
  html += "</div>\n<table>\n";
  Row(html, {"stated precision", "independent draws", "campaign samples"}, true);
  const auto row = [&](const std::string& what, const std::optional<std::int64_t>& draws) {
    Row(html, {what, draws ? fmt::format("{}", *draws) : "n/a",
               draws ? fmt::format("{}", static_cast<std::int64_t>(
                                             std::ceil(static_cast<double>(*draws) * report.samples_per_draw)))
                     : "n/a"});
  };
  row(fmt::format("99 % quantile to &#177;{} of its value", Percent(report.options.quantile_precision)),
      primary.samples_for_quantile);
  if (primary.distribution->within_spec) {
    row(fmt::format("yield to &#177;{}", Percent(report.options.yield_precision)), primary.samples_for_yield);
  }
  html += fmt::format(
      "</table>\n<p class=\"note\">At {:g} % confidence; the campaign has {} ok draws. The "
      "quantile's count extrapolates its interval's width as 1/&#8730;n; the yield's is exact "
      "(Clopper-Pearson) at the present yield.</p>\n",
      100 * confidence, primary.count);
}

constexpr double kUmPerMm = units::kMicrometresPerMetre / units::kMillimetresPerMetre;

// How far a replay's D_trajectory may lie from the stored one: picometres for most
// solvers, which no one reads; the page states at least the nanometre it resolves.
std::string ReplayAllowance(const ReplayedTrajectory& t) {
  constexpr double kFinestStatedUm = 1e-3;
  return Micrometres(std::max(kUmPerMm * t.tolerance_mm, kFinestStatedUm));
}

// The orbits of the worst and the median sample, or why there are none.
void OrbitSection(std::string& html, const CampaignReport& report) {
  html += "<h2 id=\"orbits\">Orbits of the worst and the median assembly</h2>\n";
  if (report.trajectories.empty()) {
    html += fmt::format("<p>No orbit is drawn: {}.</p>\n",
                        EscapeXml(report.replay_problem.value_or("no sample finished ok")));
    return;
  }
  // The outputs the samples were picked by, in words.
  std::vector<std::string> by;
  for (const ReplayedTrajectory& t : report.trajectories) {
    const std::string name = Label(t.by);
    if (std::find(by.begin(), by.end(), name) == by.end()) by.push_back(name);
  }
  std::string by_words;
  for (std::size_t k = 0; k < by.size(); ++k) by_words += (k == 0 ? "" : k + 1 == by.size() ? " and " : ", ") + by[k];
  html += fmt::format(
      "<p>Worst and median refer to {}{}, over the {} ok independent samples: the worst has the largest, "
      "the median sample is the one nearest the median. Each is replayed from its stored design point "
      "(<code>/inputs/u</code>) with the campaign's solver settings and drawn only if it reproduces its stored "
      "D_trajectory. Left: the ring centre over one revolution, relative to the centre of its smallest enclosing "
      "circle, whose diameter is D_trajectory; the ring sits at the static equilibrium before it turns, Dist_init "
      "from that centre. Right: the sensor's reading over the same revolution, above its minimum; the total "
      "indicator reading is TIR = max &#8722; min.</p>\n",
      EscapeXml(by_words), report.identity.spec.empty() ? "" : " (what the spec constrains)", report.ok);
  // Said where the TIR is read, before the error motion's own section: an indicator's
  // reading and the error motion are different quantities. (A file without the error
  // motion columns has nothing to set beside it.)
  const bool error_motion = report.error_motion || report.error_motion_problem;
  std::string tir_is_not_error_motion =
      "The TIR is what an indicator reads over one revolution: the bore's own form plus the axis's motion.";
  if (error_motion) {
    tir_is_not_error_motion += fmt::format(
        " An error-motion spec bounds the axis alone: its error motion ({}), which the polar plot below draws for "
        "the worst assembly, not the TIR.",
        ErrorMotionConditions({.filter = report.identity.error_motion_filter}));
  }
  for (const ReplayedTrajectory& t : report.trajectories) {
    const std::string quantity = Quantity(t.by);
    const std::string unit = Unit(t.by);
    const std::string which = fmt::format("{} {}", t.label == "worst" ? "Worst" : "Median", EscapeXml(quantity));
    // The title states D_trajectory and the TIR anyway; another ranking output besides.
    const std::string ranked_value = t.by == "d_trajectory_mm" || t.by == "runout_mm"
                                         ? std::string()
                                         : fmt::format(", {} {} {}", EscapeXml(quantity), Num(t.stored_by), unit);
    if (!t.reproduced) {
      html += fmt::format("<h3>{}: sample {}</h3>\n", which, t.index);
      const std::string replayed =
          t.status == "ok" ? fmt::format("D_trajectory {} mm against {} mm stored, {} apart; allowed: {}",
                                         Num(t.d_trajectory_mm), Num(t.stored_d_trajectory_mm),
                                         Micrometres(kUmPerMm * std::abs(t.d_trajectory_mm - t.stored_d_trajectory_mm)),
                                         ReplayAllowance(t))
                           : fmt::format("status {}{}", t.status, t.message.empty() ? "" : ": " + t.message);
      html += fmt::format(
          "<p class=\"warn\">Sample {} does not replay to its stored result ({}): this ringtol computes it "
          "otherwise than the one that ran the campaign, so its orbit is not drawn.</p>\n",
          t.index, EscapeXml(replayed));
      continue;
    }
    html += fmt::format("<h3>{}: sample {}{}, D_trajectory {} mm, TIR {} mm</h3>\n", which, t.index, ranked_value,
                        Num(t.stored_d_trajectory_mm),
                        Num(t.tir_um * units::kMetresPerMicrometre * units::kMillimetresPerMetre));
    html += "<div class=\"charts\">\n";
    html += Figure(OrbitSvg(t), "Dotted: the smallest circle enclosing the path; ring: the static equilibrium.");
    html += Figure(SensorSvg(t), fmt::format("Ringed: the reading's maximum (at {:.1f}°) and minimum (at {:.1f}°). {}",
                                             t.max_angle_deg, t.min_angle_deg, tir_is_not_error_motion));
    html += "</div>\n";
    html += fmt::format(
        "<p class=\"note\">Replayed, D_trajectory is {} mm against {} mm stored, {} apart (allowed: {}); {} angles "
        "per revolution.</p>\n",
        Num(t.d_trajectory_mm), Num(t.stored_d_trajectory_mm),
        EscapeXml(Micrometres(kUmPerMm * std::abs(t.d_trajectory_mm - t.stored_d_trajectory_mm))),
        EscapeXml(ReplayAllowance(t)), t.steps);
  }
}

// ISO 230-7's polar plot: the band of revolutions shaded, the synchronous average as a
// line, the total error motion's enclosing circles solid and the synchronous one's dashed.
std::string ErrorMotionSvg(const ErrorMotionPlot& p, double units_per_division) {
  svg::PolarChart chart;
  chart.title = fmt::format("Sample {}: radial error motion over {} revolutions", p.index, p.revolutions);
  chart.unit = "µm";
  chart.units_per_division = units_per_division;
  chart.bands.push_back(
      {.name = "revolutions", .angle_deg = p.angle_deg, .lower = p.lowest_um, .upper = p.highest_um, .colour = 0});
  chart.circles = {{.value = p.total_inner_um, .name = "total", .colour = 2},
                   {.value = p.total_outer_um, .colour = 2},
                   {.value = p.synchronous_inner_um, .name = "synchronous", .colour = 1, .dashed = true},
                   {.value = p.synchronous_outer_um, .colour = 1, .dashed = true}};
  chart.spokes.push_back({.angle_deg = p.asynchronous_angle_deg, .name = "asynchronous read here", .colour = 3});
  chart.curves.push_back({.name = "synchronous average", .angle_deg = p.angle_deg, .value = p.average_um, .colour = 1});
  return svg::RenderPolarChart(chart);
}

// The band of revolutions about their average, at its own scale: beside the total's
// circles a band a tenth as wide is a hairline.
std::string AsynchronousBandSvg(const ErrorMotionPlot& p) {
  std::vector<double> below(p.angle_deg.size()), above(p.angle_deg.size());
  double lowest = 0.0, highest = 0.0;
  for (std::size_t j = 0; j < p.angle_deg.size(); ++j) {
    below[j] = p.lowest_um[j] - p.average_um[j];
    above[j] = p.highest_um[j] - p.average_um[j];
    lowest = std::min(lowest, below[j]);
    highest = std::max(highest, above[j]);
  }
  svg::PolarChart chart;
  chart.title = fmt::format("Sample {}: the band of revolutions about their average", p.index);
  chart.unit = "µm";
  chart.units_per_division = svg::PolarDivision(lowest, highest);
  chart.bands.push_back({.name = "revolutions less their average", .angle_deg = p.angle_deg, .lower = below,
                         .upper = above, .colour = 0});
  chart.spokes.push_back({.angle_deg = p.asynchronous_angle_deg, .name = "asynchronous read here", .colour = 3});
  return svg::RenderPolarChart(chart);
}

// The polar plot of the sample with the largest total error motion, or why there is none;
// nothing for a file without the life columns.
void ErrorMotionSection(std::string& html, const CampaignReport& report) {
  if (!report.error_motion && !report.error_motion_problem) return;
  html += "<h2 id=\"error-motion\">Radial error motion of the worst assembly (ISO 230-7)</h2>\n";
  if (!report.error_motion) {
    html += fmt::format("<p>No polar plot is drawn: {}.</p>\n", EscapeXml(*report.error_motion_problem));
    return;
  }
  const ErrorMotionPlot& p = *report.error_motion;
  if (p.status != "ok") {
    html += fmt::format(
        "<p class=\"warn\">Sample {} (the largest total error motion, {} stored) does not replay over {} "
        "revolutions (status {}{}), so its polar plot is not drawn.</p>\n",
        p.index, EscapeXml(Micrometres(kUmPerMm * p.stored_total_mm)), p.revolutions, EscapeXml(p.status),
        p.message.empty() ? "" : ": " + EscapeXml(p.message));
    return;
  }
  html += fmt::format(
      "<p>Sample {} has the largest total error motion stored, {} over the stage's life, of the {} ok "
      "independent samples. It is replayed from its stored design point with the campaign's solver settings over "
      "{} successive revolutions, each with the rollers turned on by the revolutions before it, and the axis motion "
      "(the centre's component along the sensor's ray) is read as ISO 230-7 reads a radial error motion in a fixed "
      "sensitive direction: the once-per-revolution part of the synchronous average (here {}), which a fixed "
      "direction cannot tell from the artefact's centring, is removed, and the motion is drawn magnified about a "
      "base circle, its centre the plot's least-squares centre.</p>\n",
      p.index, EscapeXml(Micrometres(kUmPerMm * p.stored_total_mm)), report.ok, p.revolutions,
      EscapeXml(Micrometres(p.fundamental_um)));
  html += fmt::format(
      "<p>The replay reads a total of {} against the {} stored. The stored value is the limit over every revolution "
      "the stage will turn: every roller turns R/r times a revolution, a ratio no assembly makes whole, so over its "
      "life each roller's lobes meet every angle of the ring at every phase, and the stored value is read at the "
      "worst of them. {} successive revolutions meet only {} phases of each roller, so their band is narrower, and more "
      "revolutions widen it towards the stored value.</p>\n",
      EscapeXml(Micrometres(p.total_um)), EscapeXml(Micrometres(kUmPerMm * p.stored_total_mm)), p.revolutions,
      p.revolutions);
  const double division = svg::PolarDivision(p.total_inner_um, p.total_outer_um);
  const std::string conditions = ErrorMotionConditions({.filter = p.filter, .revolutions = p.revolutions});
  html += "<div class=\"charts\">\n";
  html += Figure(
      ErrorMotionSvg(p, division),
      fmt::format("Total error motion {} (the solid circles just enclose every revolution), synchronous {} (the "
                  "dashed circles just enclose the average over the revolutions), asynchronous {} (the widest the "
                  "shaded band is along one radius, at ψ = {:.1f}°, the marked radius); {}, {} angles a revolution. "
                  "Scale: {:g} µm per division about the base circle; ring angle ψ from +x counter-clockwise.",
                  Micrometres(p.total_um), Micrometres(p.synchronous_um), Micrometres(p.asynchronous_um),
                  p.asynchronous_angle_deg, conditions, p.steps, division),
      FigureWidth::kShare);
  html += Figure(AsynchronousBandSvg(p),
                 fmt::format("The same revolutions less their average, at the band's own scale: its widest, {} at ψ "
                             "= {:.1f}° (the marked radius), is the asynchronous error motion; {}.",
                             Micrometres(p.asynchronous_um), p.asynchronous_angle_deg, conditions),
                 FigureWidth::kShare);
  html += "</div>\n";
}

void OutputsSection(std::string& html, const CampaignReport& report) {
  html += "<h2 id=\"outputs\">Every output</h2>\n<table>\n";
  Row(html, {"output", "ok", "mean", "std", "50 %", "90 %", "99 % [interval]", "99.9 %", "spec", "within spec"}, true);
  for (const OutputReport& out : report.outputs) {
    if (!out.distribution) {
      Row(html, {EscapeXml(Label(out.name)), "0", "-", "-", "-", "-", "-", "-", "-", "-"});
      continue;
    }
    const analysis::DistributionSummary& d = *out.distribution;
    std::vector<std::string> q;
    for (const analysis::QuantileEstimate& e : d.quantiles) q.push_back(Num(e.value));
    std::string q99 = "-";
    for (const analysis::QuantileEstimate& e : d.quantiles) {
      if (e.probability == kReportQuantile) q99 = Num(e.value) + " " + Interval(e.interval);
    }
    Row(html,
        {EscapeXml(Label(out.name)), fmt::format("{}", d.count), Num(d.mean), Num(d.standard_deviation),
         q.size() > 0 ? q[0] : "-", q.size() > 1 ? q[1] : "-", q99, q.size() > 3 ? q[3] : "-",
         out.upper_spec_limit ? Num(*out.upper_spec_limit) : "-",
         d.within_spec ? YieldPercent(d.within_spec->value, d.within_spec->trials) : "-"});
  }
  html += "</table>\n";
  html += "<div class=\"charts\">\n";
  for (const OutputReport& out : report.outputs) {
    if (out.name == report.primary_output || !out.distribution) continue;
    html += Figure(HistogramSvg(out), Label(out.name));
  }
  html += "</div>\n";
}

// A table only when outputs other than the spec'd one have indices: the spec'd one's are above.
void ContributorsSection(std::string& html, const CampaignReport& report) {
  if (report.sensitivities.size() <= 1) return;
  html += "<h3>Largest contributors to every output</h3>\n<table>\n";
  Row(html, {"output", "method", "largest three"}, true);
  for (const OutputSensitivity& s : report.sensitivities) {
    const SensitivityLevel* level = FindLevel(s, "source");
    if (level == nullptr) level = &s.levels.front();
    std::string top;
    for (std::size_t k = 0; k < std::min<std::size_t>(3, level->entries.size()); ++k) {
      const SensitivityEntry& e = level->entries[k];
      top += fmt::format("{}{} ({} {})", k == 0 ? "" : "; ", EscapeXml(SourceLabel(e.name)),
                         e.total_order ? "ST" : (level->level == "input" ? "S1" : "sum of SRC&#178;"),
                         Decimals(e.ranking, 2));
    }
    Row(html, {EscapeXml(Label(s.output)), EscapeXml(s.method), top});
  }
  html += "</table>\n";
}

void MethodSection(std::string& html, const CampaignReport& report) {
  html += fmt::format(
      "<h2 id=\"method\">How these numbers were made</h2>\n<ul class=\"note\">\n"
      "<li>Statistics use the independent draws: every sample, or the A and B matrices of a Saltelli design. Failed "
      "and pending samples are excluded and counted above.</li>\n"
      "<li>Quantile intervals are distribution-free: order statistics whose ranks come from the Binomial(n, p) law; "
      "'unbounded' means n is too small to bound that side. Yield intervals are Clopper-Pearson (exact). Both assume "
      "independent samples; a randomised Sobol' net is better balanced, so for it they err wide.</li>\n"
      "<li>Runout has only an upper limit: Cpu = (USL - mean) / 3s is the normal-theory Cpk; the percentile Cpk "
      "(USL - median) / (x<sub>99.865 %</sub> - median) does not assume normality, which a skewed, positive runout "
      "breaks. Cp needs two limits.</li>\n"
      "<li>Sobol' intervals are bootstrap intervals over the design's rows ({} resamples); a small negative index "
      "is an index of zero within its error.</li>\n"
      "<li>Every number here is in the JSON summary (<code>ringtol report --json</code>), in SALib's vocabulary: S1, "
      "S1_conf, ST, ST_conf.</li>\n</ul>\n",
      report.options.bootstrap_resamples);
}

}  // namespace

std::string ReportHtml(const CampaignReport& report) {
  std::string html;
  PageHead(html, report);
  const OutputReport* primary = Find(report, report.primary_output);
  AnswerSection(html, report, primary);
  SamplesSection(html, report);
  PopulationSection(html, report);
  if (primary != nullptr && primary->distribution) {
    DistributionSection(html, *primary, report.options.confidence);
    ConvergenceSection(html, report, *primary);
  }
  if (const OutputSensitivity* s = FindSensitivity(report, report.primary_output)) {
    SensitivitySection(html, report, *s);
  }
  OrbitSection(html, report);
  ErrorMotionSection(html, report);
  OutputsSection(html, report);
  ContributorsSection(html, report);
  MethodSection(html, report);
  html += "</body>\n</html>\n";
  return html;
}

}  // namespace ringtol::jobs
