// The pieces both HTML reports are built of (the campaign's, jobs/report/report_html.h,
// and the allocation's, jobs/report/allocation_report.h): one page scaffold and style sheet
// (print style included), number formats, table rows, figures, and the distribution and
// sensitivity blocks of one output. Every function appends to or returns HTML text;
// names and captions are escaped here (svg::EscapeXml), table cells are not (they may
// hold markup: callers escape what they take from files).
#pragma once

#include <cstddef>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "analysis/order_statistics.h"
#include "analysis/sensitivity.h"
#include "jobs/report/campaign_report.h"

namespace ringtol::jobs::html {

// The inline style sheet; OpenPage embeds it.
std::string_view PageStyle();
// <!DOCTYPE html> through <body> and an <h1> of `title`; the caller closes the page with
// "</body>\n</html>\n".
void OpenPage(std::string& html, std::string_view title);

// Four significant digits; "unbounded" for a non-finite value (an interval end that n
// samples cannot bound).
std::string Num(double value);
std::string Interval(const analysis::Interval& i);
std::string PercentInterval(const analysis::Interval& i);
// An output's (one of kOutputNames) label and unit from its row of the outputs table
// (jobs/campaign/sample_record.h): "d_trajectory_mm" -> "D_trajectory" and "mm"; and both
// as a label: "D_trajectory [mm]".
std::string Quantity(std::string_view name);
std::string Unit(std::string_view name);
std::string Label(std::string_view name);
// "ring_shape" -> "ring shape".
std::string SourceLabel(std::string_view name);
std::string Index(const analysis::SobolIndex& index);  // "0.512 ± 0.031"

void Row(std::string& html, std::initializer_list<std::string> cells, bool header = false);
// In a row of charts, a figure fills its share; one alone in its row would fill the page,
// so kAlone keeps it as wide as a figure of two in a row.
enum class FigureWidth { kShare, kAlone };
std::string Figure(const std::string& svg_text, const std::string& caption, FigureWidth width = FigureWidth::kShare);

// One output's distribution: its histogram and empirical CDF with the upper spec limit
// drawn, and a table of moments, quantiles with their intervals, capability and yield.
std::string HistogramSvg(const OutputReport& out);
std::string CdfSvg(const OutputReport& out);
void DistributionTable(std::string& html, const OutputReport& out, double confidence);

// Sensitivities of one output: a level's entries as bars and as a table (at most `limit`
// rows), and the by-source block that says which source to tighten first.
const SensitivityLevel* FindLevel(const OutputSensitivity& s, std::string_view level);
std::string SensitivitySvg(const SensitivityLevel& level, const std::string& title, bool sobol,
                           const std::vector<bool>& highlighted, const std::string& highlight_label,
                           const std::vector<std::string>& categories,
                           const std::vector<const SensitivityEntry*>& entries);
void SensitivityTable(std::string& html, const SensitivityLevel& level, bool sobol, std::size_t limit);
void ContributorsBySource(std::string& html, const SensitivityLevel& by_source, bool sobol);

}  // namespace ringtol::jobs::html
