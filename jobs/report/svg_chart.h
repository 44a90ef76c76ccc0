// Charts as inline SVG for the campaign's self-contained HTML report: no scripts, no
// stylesheets, no external fonts or files. Each chart is one <svg> element with a viewBox
// (it scales to the width of its container), a <title> for screen readers, system fonts,
// black and grey text, and colours from a palette that stays readable in greyscale print.
//
// Four kinds of chart:
//   RenderChart      x-y data: lines, steps (an empirical CDF), points (labelled, of four
//                    marker shapes, or ringed to single some out), shaded bands (a confidence band), log2 axes
//                    (estimate vs sample count), log10 axes (error vs time over decades),
//                    equal aspect (a trajectory in µm, with its minimum enclosing circle);
//   RenderBarChart   horizontal grouped bars with error bars (sensitivity indices S1, ST
//                    per category), categories optionally highlighted;
//   RenderHistogram  bins of equal width (the distribution of an output);
//   RenderPolarChart small radial deviations about a base circle, magnified (ISO 230-7's
//                    polar plot of error motion): closed curves, shaded bands between two
//                    curves, circles concentric with the base one.
// Each can carry reference lines (a spec limit, the 99 % level) with a label.
//
// Rendering never fails: a point with a non-finite coordinate (or <= 0 on a log axis) is
// skipped and breaks a line there; a chart without drawable data says "no data"; a
// zero-width range is widened; of vectors that should be as long as each other, the
// entries beyond the shortest are ignored. Band bounds of ±infinity reach the edge of the
// plot. Nothing outside the plot area is drawn (lines are clipped, points dropped).
// Coordinates are written with two decimals of a pixel; long lines are thinned to a few
// points per pixel column, so a step line of a million samples stays small. A curve that
// doubles back on itself (a path in the plane) is thinned less that way: DecimateCurve
// picks its points before they reach a chart.
//
// Text (titles, labels, names, categories, colours) is plain UTF-8 and escaped here. The page that
// embeds the SVG must be served as UTF-8 (µ, ≤).
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace ringtol::jobs::svg {

// Every member has an initialiser, `{}` at least, so that designated initialisers may leave
// members out under -Wextra (GCC's -Wmissing-field-initializers).

// Okabe & Ito's colour-blind-safe colours, in an order whose first three differ in
// lightness (blue, orange, black) and so stay apart in greyscale; beyond three, tell
// series apart by `dashed` too. An index is taken modulo kPaletteSize.
inline constexpr int kPaletteSize = 6;
std::string_view PaletteColour(int index);

struct Axis {
  std::string label{};                 // with its unit, e.g. "runout [µm]"; empty: none
  bool log2 = false;                   // logarithmic, ticks at powers of two (64, 1k, 16k, 1M)
  bool log10 = false;                  // logarithmic, ticks at powers of ten (0.001, 1, 1000);
                                       // log2 wins if both are set
  std::optional<double> min{}, max{};  // fixed ends (used only if finite, and > 0 on a log axis);
                                       // otherwise the data's range widened by 4 % on each side,
                                       // except a linear end at exactly 0, which stays
  // > 0: ticks at the multiples of this (90 for degrees) instead of nice numbers; linear
  // axes without equal aspect only, and only while at most 16 ticks result.
  std::optional<double> step{};
};

struct ReferenceLine {
  enum class Direction { kVertical, kHorizontal };
  Direction direction = Direction::kVertical;
  double at = 0.0;      // on the x axis (vertical line) or the y axis (horizontal line)
  std::string label{};  // drawn next to the line; empty: none
};

struct Series {
  enum class Style {
    kLine,    // straight segments through the points, in the order given
    kStep,    // y[i] holds from x[i] to x[i + 1] (right-continuous, like an empirical CDF)
    kPoints,  // a marker per point
    kRings,   // an open ring around each point, wider than a marker: singles out points of
              // another series
  };
  // The shape of a kPoints marker, also in the legend: shapes tell series apart where
  // colours do not (greyscale print).
  enum class Marker { kCircle, kSquare, kTriangle, kDiamond };
  std::string name{};  // legend entry; empty: not in the legend
  std::vector<double> x{}, y{};
  Style style = Style::kLine;
  Marker marker = Marker::kCircle;  // kPoints only
  int colour = 0;       // index into the palette
  bool dashed = false;  // for lines and steps
  // Empty, or one per point: a band shaded between them (drawn under all lines). A bound of
  // ±infinity (or <= 0 on a log axis) reaches the plot's edge; a NaN one breaks the band.
  std::vector<double> band_lower{}, band_upper{};
  // An SVG colour ("#1b9e77", "red") in place of the palette's, for charts whose colours
  // are fixed elsewhere; empty: the palette's.
  std::string custom_colour{};
  // Empty, or one per point: a short text beside the point, over everything (a key into
  // the legend, say); an empty one draws nothing.
  std::vector<std::string> labels{};
};

struct Circle {
  double x = 0.0, y = 0.0;  // centre, in data units
  double radius = 0.0;      // in data units; drawn as an ellipse unless the chart has equal aspect
  std::string name{};       // legend entry; empty: not in the legend
};

struct Chart {
  std::string title{};
  Axis x{}, y{};
  std::vector<Series> series{};  // drawn in order, the last on top
  std::vector<ReferenceLine> lines{};
  std::optional<Circle> circle{};  // drawn dotted, in black; not on log axes
  // One data unit is as long in x as in y (a trajectory); the range of the shorter axis is
  // widened about its centre to fit, fixed ends included. Both axes then share one tick
  // step. Ignored if an axis is logarithmic.
  bool equal_aspect = false;
  double width = 640.0, height = 360.0;  // of the viewBox [px]; the page scales it
};

struct Bars {
  std::string name{};           // legend entry, e.g. "first order S1"
  std::vector<double> value{};  // one per category; NaN: no bar
  std::vector<double> lower{};  // empty, or one per category: error bars (±infinity reach the edge)
  std::vector<double> upper{};
  int colour = 0;  // index into the palette
};

struct BarChart {
  std::string title{};
  std::vector<std::string> categories{};  // top to bottom
  // Empty, or one per category: drawn on a grey band with a bold label (e.g. harmonic
  // orders that are multiples of the roller count).
  std::vector<bool> highlighted{};
  std::string highlight_label{};       // legend entry for the highlight; empty: none
  std::vector<Bars> series{};          // side by side within a category, the first on top
  Axis value{};                        // the horizontal axis; always includes 0 and every value and
                                       // error bar (negative ones too); log scales are ignored
  std::vector<ReferenceLine> lines{};  // vertical ones only; horizontal ones are ignored
  double width = 640.0;                // of the viewBox [px]; the height follows from the rows
  double category_height = 28.0;       // [px] per category
};

struct HistogramChart {
  std::string title{};
  Axis x{};  // the output, e.g. "runout [µm]"
  std::string count_label = "samples";
  double lower = 0.0;            // lower edge of the first bin, in x units
  double bin_width = 1.0;        // in x units, > 0 (otherwise nothing is drawn)
  std::vector<double> counts{};  // per bin, >= 0 (or a density); others are skipped
  int colour = 0;
  std::vector<ReferenceLine> lines{};  // e.g. the spec limit, vertical
  double width = 640.0, height = 360.0;
};

// A polar plot of deviations far smaller than the radius they are measured at (an axis's
// error motion, micrometres on a ring of metres): the base circle is drawn at a fixed
// radius, and a deviation v at angle a (degrees from +x, counter-clockwise) at
// kPolarBaseDivisions + v / units_per_division divisions from the centre. Grid rings mark
// each division, spokes every 30 degrees. A deviation beyond the plot (more than
// kPolarDivisionsOut divisions out, or in past the centre) is drawn at its edge.
inline constexpr int kPolarBaseDivisions = 6;  // the base circle's radius
inline constexpr int kPolarDivisionsOut = 4;   // the plot reaches this far beyond it

struct PolarCurve {
  std::string name{};                        // legend entry; empty: not in the legend
  std::vector<double> angle_deg{}, value{};  // closed: the last point joins the first
  int colour = 0;
  bool dashed = false;
};

// The region between two closed curves at the same angles, shaded (a band of revolutions).
struct PolarBand {
  std::string name{};
  std::vector<double> angle_deg{}, lower{}, upper{};
  int colour = 0;
};

// A circle concentric with the base one, `value` out from it.
struct PolarCircle {
  double value = 0.0;
  std::string name{};
  int colour = 2;
  bool dashed = false;
};

// A radius from the centre to the plot's edge at one angle: where a value is read.
struct PolarSpoke {
  double angle_deg = 0.0;
  std::string name{};
  int colour = 3;
};

struct PolarChart {
  std::string title{};
  std::string unit{};  // of the values, for the scale's label ("µm")
  // > 0: the scale; otherwise PolarDivision of every value drawn.
  double units_per_division = 0.0;
  std::vector<PolarBand> bands{};  // drawn first
  std::vector<PolarCircle> circles{};
  std::vector<PolarSpoke> spokes{};
  std::vector<PolarCurve> curves{};  // drawn last, in order
  double width = 440.0, height = 480.0;  // of the viewBox [px]
};

// The finest step of 1, 2 or 5 x 10^k that keeps values in [lowest, highest] within
// kPolarDivisionsOut divisions of the base circle on either side; 1 when both are 0 or
// either is not finite.
double PolarDivision(double lowest, double highest);

std::string RenderChart(const Chart& chart);
std::string RenderBarChart(const BarChart& chart);
std::string RenderHistogram(const HistogramChart& chart);
std::string RenderPolarChart(const PolarChart& chart);

// Tick positions with their labels, as the charts draw them.
struct Ticks {
  std::vector<double> values{};
  std::vector<std::string> labels{};
};

// Nice numbers after Heckbert ("Nice numbers for graph labels", Graphics Gems, 1990): a step
// of 1, 2 or 5 x 10^k, the finest that keeps at most `max_ticks` (>= 2) multiples of it in
// [lo, hi]; the ticks are those multiples. Values are the doubles nearest the decimals
// (0.3, not 3 x 0.1), labels the shortest decimals ("0.3", "-0.05", "2.5e+07").
Ticks NiceTicks(double lo, double hi, int max_ticks = 8);
// Powers of two in [lo, hi] (0 < lo < hi), every m-th from the lowest so that at most
// `max_ticks` remain, labelled compactly: 0.5, 1, 64, 1k (1024), 16k, 1M (2^20), 1G.
Ticks Log2Ticks(double lo, double hi, int max_ticks = 8);

// Indices, ascending, of at most max(max_points, 7) points of the curve (x[i], y[i]) that
// draw like all of it: the curve is cut into runs of consecutive points, and of each run
// its first and last points are kept, those with the least and the greatest x and y, and,
// given `from`, the one farthest from that point. Each extreme of the whole curve is an
// extreme of its run, so it survives: a path keeps its reach in every axis direction and,
// about the centre of a circle that encloses it, its points on that circle; a signal keeps
// its maximum and minimum. A curve of at most max_points points comes back whole. A NaN
// coordinate is never an extreme of its axis, nor its point the farthest. Of x and y, the
// entries beyond the shorter are ignored.
std::vector<std::size_t> DecimateCurve(std::span<const double> x, std::span<const double> y, std::size_t max_points,
                                       std::optional<std::array<double, 2>> from = std::nullopt);

// Text for XML content and attribute values: & < > " ' escaped, control characters that
// XML 1.0 forbids dropped.
std::string EscapeXml(std::string_view text);

}  // namespace ringtol::jobs::svg
