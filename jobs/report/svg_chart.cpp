#include "jobs/report/svg_chart.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <numbers>
#include <span>
#include <tuple>
#include <utility>

#include <fmt/format.h>

namespace ringtol::jobs::svg {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

constexpr std::string_view kPalette[kPaletteSize] = {"#0072B2", "#E69F00", "#000000", "#D55E00", "#56B4E9", "#009E73"};
constexpr std::string_view kFont = "DejaVu Sans, Arial, sans-serif";
constexpr std::string_view kDash = "6 4";
constexpr std::string_view kCircleDash = "2 3";  // unlike any dashed series
constexpr double kPixelsPerXTick = 60.0;         // a label of up to 7 characters and a gap
constexpr double kPixelsPerYTick = 36.0;         // three lines of text

// Layout [px]. The left margin holds tick labels of up to about 8 characters and the
// rotated axis label; the right one half of the last x tick label.
constexpr double kTitleBand = 30.0;
constexpr double kLegendRow = 20.0;
constexpr double kLegendGap = 6.0;
constexpr double kMarginLeft = 72.0;
constexpr double kMarginRight = 24.0;
constexpr double kMarginBottom = 48.0;
constexpr double kFontSize = 12.0;
// Average advance of DejaVu Sans, the widest of the fonts named [em]: text is measured by
// this estimate only, so it errs on the wide side.
constexpr double kCharWidth = 0.6;
constexpr double kPadding = 0.04;  // auto ranges are widened by this fraction on each side
// Ranges narrower than this, relative to their ends, are widened: below it the ticks
// would be indistinguishable in print and the step underflows the doubles' resolution.
constexpr double kMinRelativeWidth = 1e-9;
// Data beyond this magnitude are treated as non-finite: their differences would overflow.
constexpr double kHuge = 1e150;
// Mapped coordinates are clamped to this far outside the plot [px], so clipping only ever
// sees finite numbers; the clamp moves a clipped line by far less than a pixel.
constexpr double kFarOutside = 1e7;
// Tick multiples within this fraction of a step of an end count as inside: 0.3 / 0.1 is
// 2.9999999999999996.
constexpr double kTickTolerance = 1e-9;
constexpr double kInsideTolerance = 0.01;  // [px], the rounding of written coordinates
constexpr double kColumnsPerPixel = 2.0;   // long lines keep <= 4 points per half-pixel column

// Coordinates with two decimals of a pixel, trailing zeros dropped.
std::string Num(double value) {
  if (!std::isfinite(value)) value = 0.0;  // unreachable for clipped data; keeps the SVG valid regardless
  std::string text = fmt::format("{:.2f}", value);
  // Trimmed by length, not pop_back: GCC 12 at -O2 with sanitizers misreads the pops
  // followed by an assignment as an overlapping copy (-Wrestrict).
  std::size_t length = text.find_last_not_of('0') + 1;
  if (text[length - 1] == '.') --length;
  text.resize(length);
  return text == "-0" ? std::string("0") : text;
}

double TextWidth(std::string_view text, double font_size) {
  std::size_t glyphs = 0;
  for (const char c : text) {
    if ((static_cast<unsigned char>(c) & 0xC0) != 0x80) ++glyphs;  // UTF-8 lead bytes
  }
  return kCharWidth * font_size * static_cast<double>(glyphs);
}

class Svg {
 public:
  Svg(std::string_view title, double width, double height) {
    const std::string escaped = EscapeXml(title);
    Add("<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {0} {1}\" width=\"{0}\" height=\"{1}\" "
        "style=\"width:100%;height:auto\" role=\"img\" aria-label=\"{2}\" font-family=\"{3}\" font-size=\"{4}\">\n"
        "<title>{2}</title>\n",
        Num(width), Num(height), escaped, kFont, Num(kFontSize));
    if (!title.empty()) {
      Add("<text x=\"8\" y=\"20\" font-size=\"14\" font-weight=\"bold\" fill=\"#000\">{}</text>\n", escaped);
    }
  }

  template <typename... Args>
  void Add(fmt::format_string<Args...> format, Args&&... args) {
    fmt::format_to(std::back_inserter(text_), format, std::forward<Args>(args)...);
  }

  std::string Finish() {
    text_ += "</svg>\n";
    return std::move(text_);
  }

 private:
  std::string text_;
};

struct Point {
  double x = 0.0, y = 0.0;
};

struct Rect {
  double left = 0.0, top = 0.0, right = 0.0, bottom = 0.0;
  double Width() const { return right - left; }
  double Height() const { return bottom - top; }
  bool Contains(Point p) const {
    return p.x >= left - kInsideTolerance && p.x <= right + kInsideTolerance && p.y >= top - kInsideTolerance &&
           p.y <= bottom + kInsideTolerance;
  }
};

// An axis's scale: the base of its logarithm (2 or 10), or kLinear.
constexpr int kLinear = 0;

int LogBase(const Axis& axis) { return axis.log2 ? 2 : axis.log10 ? 10 : kLinear; }

// A data axis mapped onto pixels; on a log axis the ends are exponents of its base.
struct Scale {
  int log_base = kLinear;
  double lo = 0.0, hi = 1.0;    // the ends, transformed
  double from = 0.0, to = 1.0;  // their pixels

  // NaN for a value that cannot be drawn (non-finite, <= 0 on a log axis, huge).
  double Transform(double value) const {
    const double t = log_base == kLinear ? value
                     : !(value > 0.0)    ? -kInfinity
                     : log_base == 2     ? std::log2(value)
                                         : std::log10(value);
    return std::isfinite(t) && std::abs(t) <= kHuge ? t : std::numeric_limits<double>::quiet_NaN();
  }
  double operator()(double value) const {
    const double t = Transform(value);
    if (std::isnan(t)) return t;
    return std::clamp(from + (t - lo) / (hi - lo) * (to - from), -kFarOutside, kFarOutside);
  }
  double PixelsPerUnit() const { return std::abs(to - from) / (hi - lo); }
};

// The range of the drawable values of one axis, transformed.
struct Extent {
  double lo = kInfinity, hi = -kInfinity;
  void Add(double t) {
    if (std::isnan(t)) return;
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  bool empty() const { return !(lo <= hi); }
};

double Transform(int log_base, double value) { return Scale{.log_base = log_base}.Transform(value); }

std::optional<double> FixedEnd(const std::optional<double>& end, int log_base) {
  if (!end) return std::nullopt;
  const double t = Transform(log_base, *end);
  return std::isnan(t) ? std::nullopt : std::optional<double>(t);
}

// The axis ends (transformed): the data's range widened by kPadding, except a linear end
// at 0 (counts and indices start there), then the fixed ends; never of zero width.
std::pair<double, double> Ends(const Axis& axis, const Extent& data) {
  const int log_base = LogBase(axis);
  const bool log = log_base != kLinear;
  double lo = 0.0, hi = 1.0;
  if (!data.empty()) {
    lo = data.lo;
    hi = data.hi;
    const double pad = kPadding * (hi - lo);
    if (log || lo != 0.0) lo -= pad;
    if (log || hi != 0.0) hi += pad;
  }
  const std::optional<double> fixed_lo = FixedEnd(axis.min, log_base), fixed_hi = FixedEnd(axis.max, log_base);
  if (fixed_lo) lo = *fixed_lo;
  if (fixed_hi) hi = *fixed_hi;
  if (!(hi - lo > kMinRelativeWidth * std::max(std::abs(lo), std::abs(hi)))) {
    const double half = log ? 1.0 : (lo == 0.0 ? 1.0 : 0.1 * std::abs(lo));
    if (fixed_lo && !fixed_hi) {
      hi = lo + 2.0 * half;
    } else if (fixed_hi && !fixed_lo) {
      lo = hi - 2.0 * half;
    } else {
      const double centre = 0.5 * (lo + hi);
      lo = centre - half;
      hi = centre + half;
    }
  }
  return {lo, hi};
}

// A tick step mantissa x 10^exponent, mantissa 1, 2 or 5.
struct Step {
  int mantissa = 1;
  int exponent = 0;

  // k steps, computed so that it is the double nearest the decimal (0.3, not 3 x 0.1).
  double Multiple(std::int64_t k) const {
    const double units = static_cast<double>(k) * mantissa;
    return exponent >= 0 ? units * std::pow(10.0, exponent) : units / std::pow(10.0, -exponent);
  }
  double value() const { return Multiple(1); }
  Step Next() const {
    if (mantissa == 1) return {2, exponent};
    if (mantissa == 2) return {5, exponent};
    return {1, exponent + 1};
  }
  Step Previous() const {
    if (mantissa == 5) return {2, exponent};
    if (mantissa == 2) return {1, exponent};
    return {5, exponent - 1};
  }
};

// Heckbert's nicenum: the nice number nearest x (round) or not below it.
Step NiceNumber(double x, bool round) {
  const int exponent = static_cast<int>(std::floor(std::log10(x)));
  const double fraction = x / std::pow(10.0, exponent);
  int mantissa = 10;
  if (round) {
    mantissa = fraction < 1.5 ? 1 : fraction < 3.0 ? 2 : fraction < 7.0 ? 5 : 10;
  } else {
    mantissa = fraction <= 1.0 ? 1 : fraction <= 2.0 ? 2 : fraction <= 5.0 ? 5 : 10;
  }
  return mantissa == 10 ? Step{1, exponent + 1} : Step{mantissa, exponent};
}

// The multiples k of `step` in [lo, hi]: k from first to last.
std::pair<std::int64_t, std::int64_t> MultiplesWithin(double lo, double hi, Step step) {
  const double d = step.value();
  return {static_cast<std::int64_t>(std::ceil(lo / d - kTickTolerance)),
          static_cast<std::int64_t>(std::floor(hi / d + kTickTolerance))};
}

bool UsableRange(double lo, double hi) {
  return std::isfinite(lo) && std::isfinite(hi) && std::abs(lo) <= kHuge && std::abs(hi) <= kHuge &&
         hi - lo > kMinRelativeWidth * std::max(std::abs(lo), std::abs(hi));
}

std::int64_t CountWithin(double lo, double hi, Step step) {
  const auto [first, last] = MultiplesWithin(lo, hi, step);
  return last - first + 1;
}

// Heckbert's step is a good first guess, but it assumes the axis extends to the outer
// ticks; the axes here end at the data, so the step is refined to the finest that fits.
std::optional<Step> ChooseStep(double lo, double hi, int max_ticks) {
  if (!UsableRange(lo, hi)) return std::nullopt;
  max_ticks = std::max(max_ticks, 2);
  Step step = NiceNumber(NiceNumber(hi - lo, false).value() / (max_ticks - 1), true);
  while (CountWithin(lo, hi, step) > max_ticks) step = step.Next();
  while (CountWithin(lo, hi, step.Previous()) <= max_ticks) step = step.Previous();
  return step;
}

std::string TickLabel(double value, Step step) {
  if (value == 0.0) return "0";
  const double magnitude = std::abs(value);
  if (magnitude >= 1e-4 && magnitude < 1e6) return fmt::format("{}", value);  // shortest round-trip decimal
  const int digits = static_cast<int>(std::floor(std::log10(magnitude))) - step.exponent + 1;
  return fmt::format("{:.{}g}", value, std::clamp(digits, 1, 17));
}

Ticks TicksWithStep(double lo, double hi, Step step) {
  Ticks ticks;
  const auto [first, last] = MultiplesWithin(lo, hi, step);
  for (std::int64_t k = first; k <= last; ++k) {
    ticks.values.push_back(step.Multiple(k));
    ticks.labels.push_back(TickLabel(ticks.values.back(), step));
  }
  return ticks;
}

std::string PowerOfTwoLabel(int exponent) {
  if (exponent < 0) return fmt::format("{}", std::ldexp(1.0, exponent));
  if (exponent < 10) return fmt::format("{}", 1 << exponent);
  constexpr std::string_view kPrefixes = "kMGTPE";
  const std::size_t prefix = static_cast<std::size_t>(exponent / 10 - 1);
  if (prefix >= kPrefixes.size()) return fmt::format("2^{}", exponent);
  return fmt::format("{}{}", 1 << (exponent % 10), kPrefixes[prefix]);
}

// Powers of the base (2 or 10) between exponents lo and hi.
Ticks PowerTicksOfExponents(int log_base, double lo, double hi, int max_ticks) {
  Ticks ticks;
  if (!UsableRange(lo, hi) || lo < -1000.0 || hi > 1000.0) return ticks;
  const int first = static_cast<int>(std::ceil(lo - kTickTolerance));
  const int last = static_cast<int>(std::floor(hi + kTickTolerance));
  if (last < first) return ticks;
  const int every = (last - first + std::max(max_ticks, 2)) / std::max(max_ticks, 2);  // ceil(count / max)
  for (int k = first; k <= last; k += every) {
    if (log_base == 2) {
      ticks.values.push_back(std::ldexp(1.0, k));
      ticks.labels.push_back(PowerOfTwoLabel(k));
    } else {
      const Step decade{1, k};
      ticks.values.push_back(decade.value());
      ticks.labels.push_back(TickLabel(decade.value(), decade));
    }
  }
  return ticks;
}

// Less than an octave (a decade) holds fewer than two powers: plain nice numbers then.
Ticks AxisTicks(const Scale& scale, int max_ticks) {
  if (scale.log_base == kLinear) return NiceTicks(scale.lo, scale.hi, max_ticks);
  Ticks ticks = PowerTicksOfExponents(scale.log_base, scale.lo, scale.hi, max_ticks);
  if (ticks.values.size() < 2) {
    ticks = scale.log_base == 2 ? NiceTicks(std::exp2(scale.lo), std::exp2(scale.hi), max_ticks)
                                : NiceTicks(std::pow(10.0, scale.lo), std::pow(10.0, scale.hi), max_ticks);
  }
  return ticks;
}

// Between 2 and 8 ticks, as many as fit at a spacing that keeps their labels apart.
int MaxTicks(double pixels, double per_tick) { return std::clamp(static_cast<int>(pixels / per_tick), 2, 8); }

// A fixed step (Axis::step) is followed while it gives at most this many ticks.
constexpr std::int64_t kMaxFixedStepTicks = 16;

// The multiples of the axis's own step where it has a usable one, else AxisTicks.
Ticks ChartTicks(const Axis& axis, const Scale& scale, int max_ticks) {
  const double step = axis.step.value_or(0.0);
  if (scale.log_base == kLinear && std::isfinite(step) && step > 0.0 && UsableRange(scale.lo, scale.hi)) {
    const auto first = static_cast<std::int64_t>(std::ceil(scale.lo / step - kTickTolerance));
    const auto last = static_cast<std::int64_t>(std::floor(scale.hi / step + kTickTolerance));
    if (last >= first && last - first < kMaxFixedStepTicks) {
      Ticks ticks;
      for (std::int64_t k = first; k <= last; ++k) {
        ticks.values.push_back(static_cast<double>(k) * step);
        ticks.labels.push_back(k == 0 ? "0" : fmt::format("{:.6g}", ticks.values.back()));
      }
      return ticks;
    }
  }
  return AxisTicks(scale, max_ticks);
}

double ValidSize(double size, double fallback, double minimum) {
  return std::isfinite(size) ? std::max(size, minimum) : fallback;
}

// ---------------------------------------------------------------- drawing helpers

// One axis's ticks inside the plot: grid lines, marks on the frame, labels (`anchor`ed).
void AddTicks(Svg& svg, const std::string& grid, const std::string& marks, const std::string& labels,
              std::string_view anchor) {
  if (grid.empty()) return;
  svg.Add("<path d=\"{}\" stroke=\"#e0e0e0\" fill=\"none\"/>\n<path d=\"{}\" stroke=\"#666\" fill=\"none\"/>\n", grid,
          marks);
  svg.Add("<g fill=\"#444\" font-size=\"11\" text-anchor=\"{}\">\n{}</g>\n", anchor, labels);
}

void DrawXTicks(Svg& svg, const Scale& scale, const Ticks& ticks, const Rect& r) {
  std::string grid, marks, labels;
  for (std::size_t i = 0; i < ticks.values.size(); ++i) {
    const double x = scale(ticks.values[i]);
    if (!(x >= r.left - kInsideTolerance && x <= r.right + kInsideTolerance)) continue;
    fmt::format_to(std::back_inserter(grid), "M{} {}V{}", Num(x), Num(r.top), Num(r.bottom));
    fmt::format_to(std::back_inserter(marks), "M{} {}v5", Num(x), Num(r.bottom));
    fmt::format_to(std::back_inserter(labels), "<text x=\"{}\" y=\"{}\">{}</text>\n", Num(x), Num(r.bottom + 18.0),
                   EscapeXml(ticks.labels[i]));
  }
  AddTicks(svg, grid, marks, labels, "middle");
}

void DrawYTicks(Svg& svg, const Scale& scale, const Ticks& ticks, const Rect& r) {
  std::string grid, marks, labels;
  for (std::size_t i = 0; i < ticks.values.size(); ++i) {
    const double y = scale(ticks.values[i]);
    if (!(y >= r.top - kInsideTolerance && y <= r.bottom + kInsideTolerance)) continue;
    fmt::format_to(std::back_inserter(grid), "M{} {}H{}", Num(r.left), Num(y), Num(r.right));
    fmt::format_to(std::back_inserter(marks), "M{} {}h-5", Num(r.left), Num(y));
    fmt::format_to(std::back_inserter(labels), "<text x=\"{}\" y=\"{}\">{}</text>\n", Num(r.left - 8.0), Num(y + 4.0),
                   EscapeXml(ticks.labels[i]));
  }
  AddTicks(svg, grid, marks, labels, "end");
}

void DrawFrame(Svg& svg, const Rect& r) {
  svg.Add("<rect class=\"frame\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#666\"/>\n",
          Num(r.left), Num(r.top), Num(r.Width()), Num(r.Height()));
}

void DrawAxisLabels(Svg& svg, const Rect& r, std::string_view x_label, std::string_view y_label) {
  if (!x_label.empty()) {
    svg.Add("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" fill=\"#222\">{}</text>\n", Num(0.5 * (r.left + r.right)),
            Num(r.bottom + 38.0), EscapeXml(x_label));
  }
  if (!y_label.empty()) {
    svg.Add("<text transform=\"translate(16 {}) rotate(-90)\" text-anchor=\"middle\" fill=\"#222\">{}</text>\n",
            Num(0.5 * (r.top + r.bottom)), EscapeXml(y_label));
  }
}

void DrawNoData(Svg& svg, const Rect& r) {
  svg.Add("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" font-size=\"14\" fill=\"#444\">no data</text>\n",
          Num(0.5 * (r.left + r.right)), Num(0.5 * (r.top + r.bottom) + 5.0));
}

// Text over data, on a white halo so that it stays readable. The halo is a copy of the text
// drawn first rather than paint-order, which older renderers (and PDF converters) lack.
//
// A label has places to go, the one it prefers first; DrawLabels puts each, in order, at
// the first of its places where its box stays inside the plot and clear of every label put
// before it, so that no label is drawn over another (the box is measured by TextWidth, an
// estimate that errs wide). Where no place is clear, the one it overlaps least.
struct Place {
  double x = 0.0, y = 0.0;  // of the baseline's anchor [px]
  bool anchor_end = false;
};

struct Label {
  std::vector<Place> places;
  std::string text;
};

// A label's extent above and below its baseline [em]: capitals and digits reach 0.73 em,
// most labels have no descender (they reach 0.24 em).
constexpr double kLabelAscent = 0.8, kLabelDescent = 0.2;
// Rows of labels stacked beside a vertical line [px]: a box's height and a gap.
constexpr double kLabelRow = 14.0;

Rect LabelBox(const Place& place, std::string_view text) {
  const double width = TextWidth(text, kFontSize);
  const double left = place.anchor_end ? place.x - width : place.x;
  return {left, place.y - kLabelAscent * kFontSize, left + width, place.y + kLabelDescent * kFontSize};
}

double OverlapArea(const Rect& a, const Rect& b) {
  const double w = std::min(a.right, b.right) - std::max(a.left, b.left);
  const double h = std::min(a.bottom, b.bottom) - std::max(a.top, b.top);
  return w > 0.0 && h > 0.0 ? w * h : 0.0;
}

// The area of `box` outside the plot `r`, and over boxes already placed.
double Clash(const Rect& box, const Rect& r, const std::vector<Rect>& placed) {
  const double area = box.Width() * box.Height();
  double clash = area - OverlapArea(box, r);
  for (const Rect& other : placed) clash += OverlapArea(box, other);
  return clash;
}

void DrawLabels(Svg& svg, const std::vector<Label>& labels, const Rect& r) {
  std::vector<Rect> placed;
  for (const Label& label : labels) {
    if (label.places.empty()) continue;
    const Place* best = &label.places.front();
    double least = kInfinity;
    for (const Place& place : label.places) {
      const double clash = Clash(LabelBox(place, label.text), r, placed);
      if (clash < least) {
        least = clash;
        best = &place;
      }
      if (clash <= 0.0) break;
    }
    placed.push_back(LabelBox(*best, label.text));
    const std::string at = fmt::format("x=\"{}\" y=\"{}\" text-anchor=\"{}\"", Num(best->x), Num(best->y),
                                       best->anchor_end ? "end" : "start");
    const std::string text = EscapeXml(label.text);
    svg.Add(
        "<text {} fill=\"#fff\" stroke=\"#fff\" stroke-width=\"4\" stroke-linejoin=\"round\" "
        "aria-hidden=\"true\">{}</text>\n<text {} fill=\"#000\">{}</text>\n",
        at, text, at, text);
  }
}

// The places of a vertical line's label: beside the line at the top of the plot, on the
// side it fits (the right unless it would leave the plot), then row by row down it; then
// the same on the other side.
std::vector<Place> VerticalLinePlaces(double p, std::string_view text, const Rect& r) {
  const bool right_fits = p + 4.0 + TextWidth(text, kFontSize) <= r.right;
  std::vector<Place> places;
  for (const bool anchor_end : {!right_fits, right_fits}) {
    for (double y = r.top + kLabelRow; y + kLabelDescent * kFontSize <= r.bottom; y += kLabelRow) {
      places.push_back({anchor_end ? p - 4.0 : p + 4.0, y, anchor_end});
    }
  }
  return places;
}

// The places of a horizontal line's label: above it at the right end, below it, then the
// same at the left end.
std::vector<Place> HorizontalLinePlaces(double p, const Rect& r) {
  return {{r.right - 4.0, p - 4.0, true},
          {r.right - 4.0, p + kLabelRow, true},
          {r.left + 4.0, p - 4.0, false},
          {r.left + 4.0, p + kLabelRow, false}};
}

// Lines now, their labels appended to `labels` to be drawn over everything. `y` is null for
// a chart without a vertical data axis.
void DrawReferenceLines(Svg& svg, const std::vector<ReferenceLine>& lines, const Rect& r, const Scale& x,
                        const Scale* y, std::vector<Label>& labels) {
  std::string path;
  for (const ReferenceLine& line : lines) {
    if (line.direction == ReferenceLine::Direction::kVertical) {
      const double p = x(line.at);
      if (!(p >= r.left - kInsideTolerance && p <= r.right + kInsideTolerance)) continue;
      fmt::format_to(std::back_inserter(path), "M{} {}V{}", Num(p), Num(r.top), Num(r.bottom));
      if (!line.label.empty()) labels.push_back({VerticalLinePlaces(p, line.label, r), line.label});
    } else if (y != nullptr) {
      const double p = (*y)(line.at);
      if (!(p >= r.top - kInsideTolerance && p <= r.bottom + kInsideTolerance)) continue;
      fmt::format_to(std::back_inserter(path), "M{} {}H{}", Num(r.left), Num(p), Num(r.right));
      if (!line.label.empty()) labels.push_back({HorizontalLinePlaces(p, r), line.label});
    }
  }
  if (path.empty()) return;
  svg.Add(
      "<path class=\"reference\" d=\"{}\" fill=\"none\" stroke=\"#333\" stroke-width=\"1.2\" "
      "stroke-dasharray=\"{}\"/>\n",
      path, kDash);
}

struct LegendEntry {
  enum class Swatch { kLine, kPoint, kRing, kBar, kCircle, kHighlight, kBand };
  Swatch swatch = Swatch::kLine;
  std::string name;
  std::string colour{};  // escaped; for lines, points, rings and bars
  bool dashed = false;
  bool band = false;
  Series::Marker marker = Series::Marker::kCircle;  // for points
};

// A point marker centred on (x, y), about as large as a circle of radius r, in the
// enclosing group's fill: shapes of equal ink, so that none looks weightier.
std::string MarkerShape(Series::Marker marker, double x, double y, double r) {
  switch (marker) {
    case Series::Marker::kCircle:
      break;
    case Series::Marker::kSquare: {
      const double h = 0.89 * r;  // a square of the circle's area: side sqrt(pi) r
      return fmt::format("<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/>", Num(x - h), Num(y - h), Num(2 * h),
                         Num(2 * h));
    }
    case Series::Marker::kTriangle: {
      const double h = 1.35 * r;  // an equilateral triangle of the circle's area, centroid on the point
      return fmt::format("<path d=\"M{} {}L{} {}L{} {}Z\"/>", Num(x), Num(y - h), Num(x + 0.866 * h),
                         Num(y + 0.5 * h), Num(x - 0.866 * h), Num(y + 0.5 * h));
    }
    case Series::Marker::kDiamond: {
      const double h = 1.25 * r;  // a square of the circle's area, turned by 45 degrees
      return fmt::format("<path d=\"M{} {}L{} {}L{} {}L{} {}Z\"/>", Num(x), Num(y - h), Num(x + h), Num(y), Num(x),
                         Num(y + h), Num(x - h), Num(y));
    }
  }
  return fmt::format("<circle cx=\"{}\" cy=\"{}\" r=\"{}\"/>", Num(x), Num(y), Num(r));
}

// Entries left to right from x = 8, wrapping into rows; returns the number of rows.
int PlaceLegend(const std::vector<LegendEntry>& entries, double width, std::vector<Point>& places) {
  if (entries.empty()) return 0;
  double x = 8.0;
  int row = 0;
  for (const LegendEntry& entry : entries) {
    const double extent = 24.0 + TextWidth(entry.name, kFontSize);
    if (x > 8.0 && x + extent > width - 8.0) {
      x = 8.0;
      ++row;
    }
    places.push_back({x, kTitleBand + kLegendRow * (row + 0.5)});
    x += extent + 16.0;
  }
  return row + 1;
}

void DrawLegend(Svg& svg, const std::vector<LegendEntry>& entries, const std::vector<Point>& places) {
  if (entries.empty()) return;
  svg.Add("<g class=\"legend\" fill=\"#222\">\n");
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const LegendEntry& e = entries[i];
    const double x = places[i].x, y = places[i].y;
    const std::string_view colour = e.colour;
    if (e.band) {
      svg.Add("<rect x=\"{}\" y=\"{}\" width=\"18\" height=\"10\" fill=\"{}\" fill-opacity=\"0.25\"/>", Num(x),
              Num(y - 5.0), colour);
    }
    switch (e.swatch) {
      case LegendEntry::Swatch::kLine:
        svg.Add("<path d=\"M{} {}h18\" stroke=\"{}\" stroke-width=\"2\"{}/>", Num(x), Num(y), colour,
                e.dashed ? fmt::format(" stroke-dasharray=\"{}\"", kDash) : "");
        break;
      case LegendEntry::Swatch::kPoint:
        svg.Add("<g fill=\"{}\">{}</g>", colour, MarkerShape(e.marker, x + 9.0, y, 3.5));
        break;
      case LegendEntry::Swatch::kRing:
        svg.Add("<circle cx=\"{}\" cy=\"{}\" r=\"5\" fill=\"none\" stroke=\"{}\" stroke-width=\"2\"/>", Num(x + 9.0),
                Num(y), colour);
        break;
      case LegendEntry::Swatch::kBar:
        svg.Add("<rect x=\"{}\" y=\"{}\" width=\"18\" height=\"10\" fill=\"{}\"/>", Num(x), Num(y - 5.0), colour);
        break;
      case LegendEntry::Swatch::kCircle:
        svg.Add("<circle cx=\"{}\" cy=\"{}\" r=\"6\" fill=\"none\" stroke=\"#000\" stroke-dasharray=\"{}\"/>",
                Num(x + 9.0), Num(y), kCircleDash);
        break;
      case LegendEntry::Swatch::kHighlight:
        svg.Add("<rect x=\"{}\" y=\"{}\" width=\"18\" height=\"12\" fill=\"#e3e3e3\" stroke=\"#999\"/>", Num(x),
                Num(y - 6.0));
        break;
      case LegendEntry::Swatch::kBand:  // the shaded rectangle alone, drawn above
        break;
    }
    svg.Add("<text x=\"{}\" y=\"{}\">{}</text>\n", Num(x + 24.0), Num(y + 4.0), EscapeXml(e.name));
  }
  svg.Add("</g>\n");
}

// ---------------------------------------------------------------- geometry in pixels

// Liang and Barsky: the part of segment p-q inside r, as parameters 0 <= t0 <= t1 <= 1.
bool ClipSegment(Point p, Point q, const Rect& r, double& t0, double& t1) {
  t0 = 0.0;
  t1 = 1.0;
  const double dx = q.x - p.x, dy = q.y - p.y;
  const double direction[4] = {-dx, dx, -dy, dy};
  const double room[4] = {p.x - r.left, r.right - p.x, p.y - r.top, r.bottom - p.y};
  for (int i = 0; i < 4; ++i) {
    if (direction[i] == 0.0) {
      if (room[i] < 0.0) return false;
      continue;
    }
    const double t = room[i] / direction[i];
    if (direction[i] < 0.0) {
      if (t > t1) return false;
      t0 = std::max(t0, t);
    } else {
      if (t < t0) return false;
      t1 = std::min(t1, t);
    }
  }
  return true;
}

// The visible pieces of a polyline.
std::vector<std::vector<Point>> ClipPolyline(const std::vector<Point>& line, const Rect& r) {
  std::vector<std::vector<Point>> pieces;
  std::vector<Point> piece;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const Point p = line[i], q = line[i + 1];
    double t0 = 0.0, t1 = 0.0;
    if (!ClipSegment(p, q, r, t0, t1)) {
      if (!piece.empty()) pieces.push_back(std::move(piece));
      piece.clear();
      continue;
    }
    if (t0 > 0.0 && !piece.empty()) {
      pieces.push_back(std::move(piece));
      piece.clear();
    }
    if (piece.empty()) piece.push_back({p.x + t0 * (q.x - p.x), p.y + t0 * (q.y - p.y)});
    piece.push_back({p.x + t1 * (q.x - p.x), p.y + t1 * (q.y - p.y)});
    if (t1 < 1.0) {
      pieces.push_back(std::move(piece));
      piece.clear();
    }
  }
  if (!piece.empty()) pieces.push_back(std::move(piece));
  return pieces;
}

// Sutherland and Hodgman: the part of a polygon inside r.
std::vector<Point> ClipPolygon(std::vector<Point> polygon, const Rect& r) {
  struct Edge {
    bool vertical;  // compares x (else y)
    double at;
    bool keep_below;
  };
  const Edge edges[4] = {{true, r.left, false}, {true, r.right, true}, {false, r.top, false}, {false, r.bottom, true}};
  for (const Edge& edge : edges) {
    const auto coordinate = [&](Point p) { return edge.vertical ? p.x : p.y; };
    const auto inside = [&](Point p) { return edge.keep_below ? coordinate(p) <= edge.at : coordinate(p) >= edge.at; };
    const auto crossing = [&](Point a, Point b) {
      const double t = (edge.at - coordinate(a)) / (coordinate(b) - coordinate(a));
      return Point{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
    };
    std::vector<Point> kept;
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const Point current = polygon[i], previous = polygon[(i + polygon.size() - 1) % polygon.size()];
      if (inside(current)) {
        if (!inside(previous)) kept.push_back(crossing(previous, current));
        kept.push_back(current);
      } else if (inside(previous)) {
        kept.push_back(crossing(previous, current));
      }
    }
    polygon = std::move(kept);
  }
  return polygon;
}

// Of each run of consecutive points in one half-pixel column, keeps the first, the lowest,
// the highest and the last (the M4 reduction): the drawn line covers the same pixels.
std::vector<Point> Thin(const std::vector<Point>& line) {
  std::vector<Point> kept;
  std::size_t begin = 0;
  while (begin < line.size()) {
    const double column = std::floor(line[begin].x * kColumnsPerPixel);
    std::size_t end = begin + 1, low = begin, high = begin;
    for (; end < line.size() && std::floor(line[end].x * kColumnsPerPixel) == column; ++end) {
      if (line[end].y < line[low].y) low = end;
      if (line[end].y > line[high].y) high = end;
    }
    std::size_t picks[4] = {begin, std::min(low, high), std::max(low, high), end - 1};
    for (std::size_t i = 0; i < 4; ++i) {
      if (i > 0 && picks[i] == picks[i - 1]) continue;
      kept.push_back(line[picks[i]]);
    }
    begin = end;
  }
  return kept;
}

std::string PointList(const std::vector<Point>& points) {
  std::string text;
  for (const Point& p : points) {
    if (!text.empty()) text += ' ';
    text += Num(p.x);
    text += ',';
    text += Num(p.y);
  }
  return text;
}

// ---------------------------------------------------------------- x-y charts

std::string SeriesColour(const Series& s) {
  return s.custom_colour.empty() ? std::string(PaletteColour(s.colour)) : EscapeXml(s.custom_colour);
}

// Each drawable point's label inside the plot, beside it (DrawLabels keeps it clear of the others).
void AddPointLabels(const Series& s, const Scale& x, const Scale& y, const Rect& r, std::vector<Label>& labels) {
  for (std::size_t i = 0; i < std::min({s.x.size(), s.y.size(), s.labels.size()}); ++i) {
    const Point p{x(s.x[i]), y(s.y[i])};
    if (s.labels[i].empty() || std::isnan(p.x) || std::isnan(p.y) || !r.Contains(p)) continue;
    // Above and to the right of the point, or to the left near the right edge; else below.
    const bool left = p.x + 6.0 + TextWidth(s.labels[i], kFontSize) > r.right;
    const Place beside{left ? p.x - 6.0 : p.x + 6.0, p.y - 6.0, left};
    labels.push_back({{beside, {beside.x, p.y + 6.0 + kFontSize, left}}, s.labels[i]});
  }
}

// Runs of consecutive drawable points, in pixels; steps expanded into their corners.
std::vector<std::vector<Point>> Runs(const Series& s, const Scale& x, const Scale& y) {
  const std::size_t n = std::min(s.x.size(), s.y.size());
  std::vector<std::vector<Point>> runs;
  std::vector<Point> run;
  for (std::size_t i = 0; i < n; ++i) {
    const Point p{x(s.x[i]), y(s.y[i])};
    if (std::isnan(p.x) || std::isnan(p.y)) {
      if (!run.empty()) runs.push_back(std::move(run));
      run.clear();
      continue;
    }
    if (s.style == Series::Style::kStep && !run.empty()) run.push_back({p.x, run.back().y});
    run.push_back(p);
  }
  if (!run.empty()) runs.push_back(std::move(run));
  return runs;
}

// A band bound in pixels: ±infinity (and <= 0 on a log axis) at the edge.
double BandPixel(const Scale& y, double value) {
  if (std::isnan(value)) return value;
  if (value == kInfinity) return y.to;
  if (value == -kInfinity || (y.log_base != kLinear && value <= 0.0)) return y.from;
  return y(value);
}

void DrawBand(Svg& svg, const Series& s, const Scale& x, const Scale& y, const Rect& r) {
  const std::size_t n = std::min({s.x.size(), s.band_lower.size(), s.band_upper.size()});
  std::vector<Point> upper, lower;
  const auto flush = [&] {
    if (!upper.empty()) {
      std::vector<Point> polygon = upper;
      polygon.insert(polygon.end(), lower.rbegin(), lower.rend());
      polygon = ClipPolygon(std::move(polygon), r);
      if (polygon.size() >= 3) {
        svg.Add("<polygon points=\"{}\" fill=\"{}\" fill-opacity=\"0.25\" stroke=\"none\"/>\n", PointList(polygon),
                SeriesColour(s));
      }
    }
    upper.clear();
    lower.clear();
  };
  for (std::size_t i = 0; i < n; ++i) {
    const double px = x(s.x[i]), low = BandPixel(y, s.band_lower[i]), high = BandPixel(y, s.band_upper[i]);
    if (std::isnan(px) || std::isnan(low) || std::isnan(high)) {
      flush();
      continue;
    }
    upper.push_back({px, high});
    lower.push_back({px, low});
  }
  flush();
}

void DrawSeries(Svg& svg, const Series& s, const Scale& x, const Scale& y, const Rect& r) {
  const std::string colour = SeriesColour(s);
  if (s.style == Series::Style::kPoints || s.style == Series::Style::kRings) {
    const bool rings = s.style == Series::Style::kRings;
    std::string circles;
    for (const std::vector<Point>& run : Runs(s, x, y)) {
      for (const Point& p : run) {
        if (!r.Contains(p)) continue;
        circles += rings ? MarkerShape(Series::Marker::kCircle, p.x, p.y, 6.0) : MarkerShape(s.marker, p.x, p.y, 3.0);
      }
    }
    if (circles.empty()) return;
    if (rings) {
      svg.Add("<g class=\"series\" fill=\"none\" stroke=\"{}\" stroke-width=\"2\">{}</g>\n", colour, circles);
    } else {
      svg.Add("<g class=\"series\" fill=\"{}\">{}</g>\n", colour, circles);
    }
    return;
  }
  std::string lines;
  for (const std::vector<Point>& run : Runs(s, x, y)) {
    for (const std::vector<Point>& piece : ClipPolyline(run, r)) {
      fmt::format_to(std::back_inserter(lines), "<polyline points=\"{}\"/>\n", PointList(Thin(piece)));
    }
  }
  if (lines.empty()) return;
  svg.Add("<g class=\"series\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.8\" stroke-linejoin=\"round\"{}>\n{}</g>\n",
          colour, s.dashed ? fmt::format(" stroke-dasharray=\"{}\"", kDash) : "", lines);
}

void DrawCircle(Svg& svg, const Circle& c, const Scale& x, const Scale& y, const Rect& r, bool equal_aspect) {
  const Point centre{x(c.x), y(c.y)};
  const double rx = c.radius * x.PixelsPerUnit(), ry = c.radius * y.PixelsPerUnit();
  if (std::isnan(centre.x) || std::isnan(centre.y) || !(rx >= 0.0 && ry >= 0.0)) return;
  const std::string style =
      fmt::format("fill=\"none\" stroke=\"#000\" stroke-width=\"1.2\" stroke-dasharray=\"{}\"", kCircleDash);
  if (r.Contains({centre.x - rx, centre.y - ry}) && r.Contains({centre.x + rx, centre.y + ry})) {
    if (equal_aspect) {
      svg.Add("<circle class=\"circle\" cx=\"{}\" cy=\"{}\" r=\"{}\" {}/>\n", Num(centre.x), Num(centre.y), Num(rx),
              style);
    } else {
      svg.Add("<ellipse class=\"circle\" cx=\"{}\" cy=\"{}\" rx=\"{}\" ry=\"{}\" {}/>\n", Num(centre.x), Num(centre.y),
              Num(rx), Num(ry), style);
    }
    return;
  }
  // Partly outside the plot: a clipped polygon of many sides instead.
  constexpr int kSides = 180;
  std::vector<Point> outline;
  for (int i = 0; i <= kSides; ++i) {
    const double angle = 2.0 * std::numbers::pi * i / kSides;
    outline.push_back({centre.x + rx * std::cos(angle), centre.y + ry * std::sin(angle)});
  }
  for (const std::vector<Point>& piece : ClipPolyline(outline, r)) {
    svg.Add("<polyline class=\"circle\" points=\"{}\" {}/>\n", PointList(piece), style);
  }
}

// Both axes get one scale [px per unit] and one tick step: the narrower range is widened
// about its centre.
void EqualiseAspect(Scale& x, Scale& y) {
  const double pixels_per_unit = std::min(x.PixelsPerUnit(), y.PixelsPerUnit());
  for (Scale* scale : {&x, &y}) {
    const double centre = 0.5 * (scale->lo + scale->hi);
    const double half = 0.5 * std::abs(scale->to - scale->from) / pixels_per_unit;
    scale->lo = centre - half;
    scale->hi = centre + half;
  }
}

// ---------------------------------------------------------------- polar plots

// The plot's centre and the pixels of one division.
struct Polar {
  Point centre;
  double division = 1.0;        // [px]
  double units_per_division = 1.0;

  double Radius(double value) const {
    const double divisions = kPolarBaseDivisions + value / units_per_division;
    return division * std::clamp(divisions, 0.0, static_cast<double>(kPolarBaseDivisions + kPolarDivisionsOut));
  }
  Point At(double angle_deg, double value) const {
    const double a = angle_deg * std::numbers::pi / 180.0, r = Radius(value);
    return {centre.x + r * std::cos(a), centre.y - r * std::sin(a)};  // SVG's y points down
  }
};

// A closed curve as a path's subpath; non-finite points are left out.
std::string PolarLoop(const Polar& polar, std::span<const double> angle_deg, std::span<const double> value) {
  std::string d;
  for (std::size_t i = 0; i < std::min(angle_deg.size(), value.size()); ++i) {
    if (!std::isfinite(angle_deg[i]) || !std::isfinite(value[i])) continue;
    const Point p = polar.At(angle_deg[i], value[i]);
    fmt::format_to(std::back_inserter(d), "{}{} {}", d.empty() ? "M" : "L", Num(p.x), Num(p.y));
  }
  return d.empty() ? d : d + "Z";
}

std::string Dash(bool dashed) { return dashed ? fmt::format(" stroke-dasharray=\"{}\"", kDash) : std::string(); }

}  // namespace

double PolarDivision(double lowest, double highest) {
  const double reach = std::max(std::abs(lowest), std::abs(highest));
  if (!std::isfinite(lowest) || !std::isfinite(highest) || !(reach > 0.0) || reach > kHuge) return 1.0;
  Step step = NiceNumber(reach / kPolarDivisionsOut, false);
  while (step.Multiple(kPolarDivisionsOut) < reach) step = step.Next();  // the decimal may round below
  return step.value();
}

std::string RenderPolarChart(const PolarChart& chart) {
  const double width = ValidSize(chart.width, 440.0, 200.0), height = ValidSize(chart.height, 480.0, 200.0);
  Svg svg(chart.title, width, height);

  std::vector<LegendEntry> legend;
  const auto add_entry = [&](LegendEntry::Swatch swatch, const std::string& name, int colour, bool dashed) {
    if (name.empty()) return;
    legend.push_back({swatch, name, std::string(PaletteColour(colour)), dashed, swatch == LegendEntry::Swatch::kBand});
  };
  for (const PolarBand& band : chart.bands) add_entry(LegendEntry::Swatch::kBand, band.name, band.colour, false);
  for (const PolarCurve& curve : chart.curves) {
    add_entry(LegendEntry::Swatch::kLine, curve.name, curve.colour, curve.dashed);
  }
  for (const PolarCircle& circle : chart.circles) {
    add_entry(LegendEntry::Swatch::kLine, circle.name, circle.colour, circle.dashed);
  }
  for (const PolarSpoke& spoke : chart.spokes) add_entry(LegendEntry::Swatch::kLine, spoke.name, spoke.colour, false);
  std::vector<Point> legend_places;
  const int legend_rows = PlaceLegend(legend, width, legend_places);

  double lowest = kInfinity, highest = -kInfinity;
  const auto extend = [&](std::span<const double> values) {
    for (const double v : values) {
      if (!std::isfinite(v)) continue;
      lowest = std::min(lowest, v);
      highest = std::max(highest, v);
    }
  };
  for (const PolarBand& band : chart.bands) {
    extend(band.lower);
    extend(band.upper);
  }
  for (const PolarCurve& curve : chart.curves) extend(curve.value);
  for (const PolarCircle& circle : chart.circles) extend(std::span(&circle.value, 1));

  // The angles' labels sit outside the outermost ring, the scale's below the plot.
  constexpr double kLabelRoom = 22.0;
  const double top = kTitleBand + kLegendRow * legend_rows + kLegendGap + kLabelRoom;
  const double bottom = height - kLabelRoom - 24.0;
  const double outer = std::max(10.0, 0.5 * std::min(width - 2.0 * kLabelRoom - 16.0, bottom - top));
  Polar polar;
  polar.centre = {0.5 * width, top + 0.5 * (bottom - top)};
  polar.division = outer / (kPolarBaseDivisions + kPolarDivisionsOut);
  polar.units_per_division = std::isfinite(chart.units_per_division) && chart.units_per_division > 0.0
                                 ? chart.units_per_division
                                 : PolarDivision(lowest, highest);

  // Grid: a ring per division, the base circle darker; spokes every 30 degrees.
  std::string rings;
  for (int k = 1; k <= kPolarBaseDivisions + kPolarDivisionsOut; ++k) {
    if (k == kPolarBaseDivisions) continue;
    fmt::format_to(std::back_inserter(rings), "<circle cx=\"{}\" cy=\"{}\" r=\"{}\"/>", Num(polar.centre.x),
                   Num(polar.centre.y), Num(k * polar.division));
  }
  std::string spokes;
  for (int a = 0; a < 360; a += 30) {
    const double rad = a * std::numbers::pi / 180.0;
    fmt::format_to(std::back_inserter(spokes), "M{} {}L{} {}", Num(polar.centre.x), Num(polar.centre.y),
                   Num(polar.centre.x + outer * std::cos(rad)), Num(polar.centre.y - outer * std::sin(rad)));
  }
  svg.Add("<g class=\"grid\" fill=\"none\" stroke=\"#ddd\" stroke-width=\"1\">{}<path d=\"{}\"/></g>\n", rings,
          spokes);
  svg.Add(
      "<circle class=\"base\" cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"none\" stroke=\"#999\" stroke-width=\"1.2\"/>\n",
      Num(polar.centre.x), Num(polar.centre.y), Num(kPolarBaseDivisions * polar.division));
  std::string angle_labels;
  for (int a = 0; a < 360; a += 30) {
    const double rad = a * std::numbers::pi / 180.0, r = outer + 12.0;
    fmt::format_to(std::back_inserter(angle_labels), "<text x=\"{}\" y=\"{}\">{}°</text>",
                   Num(polar.centre.x + r * std::cos(rad)), Num(polar.centre.y - r * std::sin(rad) + 4.0), a);
  }
  svg.Add("<g class=\"angles\" text-anchor=\"middle\" fill=\"#444\">{}</g>\n", angle_labels);

  for (const PolarBand& band : chart.bands) {
    const std::string upper = PolarLoop(polar, band.angle_deg, band.upper);
    const std::string lower = PolarLoop(polar, band.angle_deg, band.lower);
    if (upper.empty() || lower.empty()) continue;
    // Each angle's lower point lies inside its upper one, so even-odd fills the ring between.
    svg.Add(
        "<path class=\"band\" d=\"{}{}\" fill=\"{}\" fill-opacity=\"0.25\" fill-rule=\"evenodd\" "
        "stroke=\"none\"/>\n",
        upper, lower, PaletteColour(band.colour));
  }
  for (const PolarCircle& circle : chart.circles) {
    if (!std::isfinite(circle.value)) continue;
    svg.Add(
        "<circle class=\"circle\" cx=\"{}\" cy=\"{}\" r=\"{}\" fill=\"none\" stroke=\"{}\" "
        "stroke-width=\"1.2\"{}/>\n",
        Num(polar.centre.x), Num(polar.centre.y), Num(polar.Radius(circle.value)), PaletteColour(circle.colour),
        Dash(circle.dashed));
  }
  for (const PolarSpoke& spoke : chart.spokes) {
    if (!std::isfinite(spoke.angle_deg)) continue;
    const double rad = spoke.angle_deg * std::numbers::pi / 180.0;
    svg.Add("<path class=\"spoke\" d=\"M{} {}L{} {}\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\"/>\n",
            Num(polar.centre.x), Num(polar.centre.y), Num(polar.centre.x + outer * std::cos(rad)),
            Num(polar.centre.y - outer * std::sin(rad)), PaletteColour(spoke.colour));
  }
  for (const PolarCurve& curve : chart.curves) {
    const std::string d = PolarLoop(polar, curve.angle_deg, curve.value);
    if (d.empty()) continue;
    svg.Add(
        "<path class=\"series\" d=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\" "
        "stroke-linejoin=\"round\"{}/>\n",
        d, PaletteColour(curve.colour), Dash(curve.dashed));
  }
  svg.Add("<text class=\"scale\" x=\"{}\" y=\"{}\" text-anchor=\"middle\" fill=\"#222\">{}</text>\n", Num(0.5 * width),
          Num(height - 12.0),
          EscapeXml(fmt::format("{:g} {} per division", polar.units_per_division, chart.unit)));
  DrawLegend(svg, legend, legend_places);
  return svg.Finish();
}

std::string_view PaletteColour(int index) {
  return kPalette[static_cast<std::size_t>(((index % kPaletteSize) + kPaletteSize) % kPaletteSize)];
}

std::string EscapeXml(std::string_view text) {
  std::string escaped;
  escaped.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&':
        escaped += "&amp;";
        break;
      case '<':
        escaped += "&lt;";
        break;
      case '>':
        escaped += "&gt;";
        break;
      case '"':
        escaped += "&quot;";
        break;
      case '\'':
        escaped += "&apos;";
        break;
      case '\t':
      case '\n':
      case '\r':
        escaped += c;
        break;
      default:
        if (static_cast<unsigned char>(c) >= 0x20) escaped += c;  // XML 1.0 allows no other control characters
    }
  }
  return escaped;
}

std::vector<std::size_t> DecimateCurve(std::span<const double> x, std::span<const double> y, std::size_t max_points,
                                       std::optional<std::array<double, 2>> from) {
  // Kept of each run: first, last, least and greatest x and y, farthest from `from`.
  constexpr std::size_t kPerRun = 7;
  const std::size_t n = std::min(x.size(), y.size());
  std::vector<std::size_t> kept;
  if (n <= max_points) {
    kept.resize(n);
    for (std::size_t i = 0; i < n; ++i) kept[i] = i;
    return kept;
  }
  const std::size_t runs = std::max<std::size_t>(1, max_points / kPerRun);
  const auto distance2 = [&](std::size_t i) {
    const double dx = x[i] - (*from)[0], dy = y[i] - (*from)[1];
    return dx * dx + dy * dy;
  };
  for (std::size_t run = 0; run < runs; ++run) {
    const std::size_t begin = n * run / runs, end = n * (run + 1) / runs;
    if (begin == end) continue;
    std::size_t picks[kPerRun] = {begin, end - 1, begin, begin, begin, begin, begin};
    for (std::size_t i = begin; i < end; ++i) {
      // A NaN loses every comparison: it is never an extreme (but one may start the run).
      if (x[i] < x[picks[2]] || std::isnan(x[picks[2]])) picks[2] = i;
      if (x[i] > x[picks[3]] || std::isnan(x[picks[3]])) picks[3] = i;
      if (y[i] < y[picks[4]] || std::isnan(y[picks[4]])) picks[4] = i;
      if (y[i] > y[picks[5]] || std::isnan(y[picks[5]])) picks[5] = i;
      if (from && (distance2(i) > distance2(picks[6]) || std::isnan(distance2(picks[6])))) picks[6] = i;
    }
    std::sort(std::begin(picks), std::end(picks));
    for (const std::size_t i : picks) {
      if (kept.empty() || kept.back() != i) kept.push_back(i);
    }
  }
  return kept;
}

Ticks NiceTicks(double lo, double hi, int max_ticks) {
  const std::optional<Step> step = ChooseStep(lo, hi, max_ticks);
  return step ? TicksWithStep(lo, hi, *step) : Ticks{};
}

Ticks Log2Ticks(double lo, double hi, int max_ticks) {
  if (!(lo > 0.0 && hi > lo)) return {};
  return PowerTicksOfExponents(2, std::log2(lo), std::log2(hi), max_ticks);
}

std::string RenderChart(const Chart& chart) {
  const double width = ValidSize(chart.width, 640.0, 200.0), height = ValidSize(chart.height, 360.0, 160.0);
  Svg svg(chart.title, width, height);

  std::vector<LegendEntry> legend;
  for (const Series& s : chart.series) {
    if (s.name.empty()) continue;
    const LegendEntry::Swatch swatch = s.style == Series::Style::kPoints  ? LegendEntry::Swatch::kPoint
                                       : s.style == Series::Style::kRings ? LegendEntry::Swatch::kRing
                                                                          : LegendEntry::Swatch::kLine;
    legend.push_back({swatch, s.name, SeriesColour(s), s.dashed, !s.band_lower.empty(), s.marker});
  }
  // A circle needs one scale for all directions, which log axes do not have.
  const int log_x = LogBase(chart.x), log_y = LogBase(chart.y);
  const bool linear = log_x == kLinear && log_y == kLinear;
  const std::optional<Circle> circle = linear ? chart.circle : std::nullopt;
  if (circle && !circle->name.empty()) {
    legend.push_back({LegendEntry::Swatch::kCircle, circle->name});
  }
  std::vector<Point> legend_places;
  const int legend_rows = PlaceLegend(legend, width, legend_places);
  const Rect r{kMarginLeft, kTitleBand + kLegendRow * legend_rows + kLegendGap, width - kMarginRight,
               height - kMarginBottom};

  Extent ex, ey;
  bool has_data = false;
  for (const Series& s : chart.series) {
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      const double tx = Transform(log_x, s.x[i]), ty = Transform(log_y, s.y[i]);
      if (std::isnan(tx) || std::isnan(ty)) continue;
      ex.Add(tx);
      ey.Add(ty);
      has_data = true;
    }
    for (std::size_t i = 0; i < std::min({s.x.size(), s.band_lower.size(), s.band_upper.size()}); ++i) {
      const double tx = Transform(log_x, s.x[i]);
      if (std::isnan(tx) || std::isnan(s.band_lower[i]) || std::isnan(s.band_upper[i])) continue;
      ex.Add(tx);
      ey.Add(Transform(log_y, s.band_lower[i]));
      ey.Add(Transform(log_y, s.band_upper[i]));
      has_data = true;
    }
  }
  for (const ReferenceLine& line : chart.lines) {
    (line.direction == ReferenceLine::Direction::kVertical ? ex : ey)
        .Add(Transform(line.direction == ReferenceLine::Direction::kVertical ? log_x : log_y, line.at));
  }
  if (circle && std::isfinite(circle->radius) && circle->radius >= 0.0) {
    for (const double sign : {-1.0, 1.0}) {
      ex.Add(Transform(kLinear, circle->x + sign * circle->radius));
      ey.Add(Transform(kLinear, circle->y + sign * circle->radius));
    }
    has_data = has_data || (std::isfinite(circle->x) && std::isfinite(circle->y));
  }

  Scale xs{log_x, 0.0, 1.0, r.left, r.right}, ys{log_y, 0.0, 1.0, r.bottom, r.top};
  std::tie(xs.lo, xs.hi) = Ends(chart.x, ex);
  std::tie(ys.lo, ys.hi) = Ends(chart.y, ey);
  const bool equal_aspect = chart.equal_aspect && linear;
  Ticks x_ticks, y_ticks;
  if (equal_aspect) {
    EqualiseAspect(xs, ys);
    const std::optional<Step> sx = ChooseStep(xs.lo, xs.hi, MaxTicks(r.Width(), kPixelsPerXTick));
    const std::optional<Step> sy = ChooseStep(ys.lo, ys.hi, MaxTicks(r.Height(), kPixelsPerYTick));
    if (sx && sy) {
      const Step step = sx->value() >= sy->value() ? *sx : *sy;
      x_ticks = TicksWithStep(xs.lo, xs.hi, step);
      y_ticks = TicksWithStep(ys.lo, ys.hi, step);
    }
  } else {
    x_ticks = ChartTicks(chart.x, xs, MaxTicks(r.Width(), kPixelsPerXTick));
    y_ticks = ChartTicks(chart.y, ys, MaxTicks(r.Height(), kPixelsPerYTick));
  }

  if (has_data) {
    DrawXTicks(svg, xs, x_ticks, r);
    DrawYTicks(svg, ys, y_ticks, r);
    for (const Series& s : chart.series) DrawBand(svg, s, xs, ys, r);
  }
  DrawFrame(svg, r);
  std::vector<Label> labels;
  DrawReferenceLines(svg, chart.lines, r, xs, &ys, labels);
  if (has_data) {
    for (const Series& s : chart.series) {
      DrawSeries(svg, s, xs, ys, r);
      AddPointLabels(s, xs, ys, r, labels);
    }
    if (circle) DrawCircle(svg, *circle, xs, ys, r, equal_aspect);
  } else {
    DrawNoData(svg, r);
  }
  DrawLabels(svg, labels, r);
  DrawAxisLabels(svg, r, chart.x.label, chart.y.label);
  DrawLegend(svg, legend, legend_places);
  return svg.Finish();
}

std::string RenderBarChart(const BarChart& chart) {
  const double width = ValidSize(chart.width, 640.0, 200.0);
  const double row = ValidSize(chart.category_height, 28.0, 8.0);

  std::vector<LegendEntry> legend;
  for (const Bars& bars : chart.series) {
    if (!bars.name.empty()) {
      legend.push_back({LegendEntry::Swatch::kBar, bars.name, std::string(PaletteColour(bars.colour))});
    }
  }
  const auto highlighted = [&](std::size_t i) { return i < chart.highlighted.size() && chart.highlighted[i]; };
  bool any_highlighted = false;
  for (std::size_t i = 0; i < chart.categories.size(); ++i) any_highlighted = any_highlighted || highlighted(i);
  if (any_highlighted && !chart.highlight_label.empty()) {
    legend.push_back({LegendEntry::Swatch::kHighlight, chart.highlight_label});
  }
  std::vector<Point> legend_places;
  const int legend_rows = PlaceLegend(legend, width, legend_places);

  // Bold labels run about a tenth wider than regular ones.
  double label_width = 0.0;
  for (const std::string& category : chart.categories) {
    label_width = std::max(label_width, 1.1 * TextWidth(category, kFontSize));
  }
  const double left = std::clamp(label_width + 20.0, 48.0, 0.45 * width);
  const bool has_rows = !chart.categories.empty() && !chart.series.empty();
  const double top = kTitleBand + kLegendRow * legend_rows + kLegendGap;
  const double plot_height = has_rows ? row * static_cast<double>(chart.categories.size()) : 60.0;
  const Rect r{left, top, width - kMarginRight, top + plot_height};
  Svg svg(chart.title, width, r.bottom + kMarginBottom);

  // The value axis starts at 0 (the bars do) and reaches every value and error bar.
  Extent extent;
  bool has_data = false;
  extent.Add(0.0);
  for (const Bars& bars : chart.series) {
    for (std::size_t i = 0; i < chart.categories.size(); ++i) {
      if (i < bars.value.size() && std::isfinite(bars.value[i])) {
        extent.Add(Transform(kLinear, bars.value[i]));
        has_data = true;
      }
      if (i < bars.lower.size()) extent.Add(Transform(kLinear, bars.lower[i]));
      if (i < bars.upper.size()) extent.Add(Transform(kLinear, bars.upper[i]));
    }
  }
  for (const ReferenceLine& line : chart.lines) {
    if (line.direction == ReferenceLine::Direction::kVertical) extent.Add(Transform(kLinear, line.at));
  }
  Axis value_axis = chart.value;
  value_axis.log2 = value_axis.log10 = false;
  Scale xs{false, 0.0, 1.0, r.left, r.right};
  std::tie(xs.lo, xs.hi) = Ends(value_axis, extent);

  if (has_data) {
    for (std::size_t i = 0; i < chart.categories.size(); ++i) {
      if (!highlighted(i)) continue;
      svg.Add("<rect class=\"highlight\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"#e3e3e3\"/>\n",
              Num(r.left), Num(r.top + row * static_cast<double>(i)), Num(r.Width()), Num(row));
    }
    DrawXTicks(svg, xs, AxisTicks(xs, MaxTicks(r.Width(), kPixelsPerXTick)), r);
  }
  DrawFrame(svg, r);
  std::vector<Label> labels;
  if (has_data) {
    const double zero = std::clamp(xs(0.0), r.left, r.right);
    if (xs.lo < 0.0 && xs.hi > 0.0) {
      svg.Add("<path d=\"M{} {}V{}\" stroke=\"#666\"/>\n", Num(zero), Num(r.top), Num(r.bottom));
    }
    const double thickness = 0.7 * row / static_cast<double>(chart.series.size());
    const double gap = thickness > 4.0 ? 1.0 : 0.0;
    std::string whiskers;
    for (std::size_t s = 0; s < chart.series.size(); ++s) {
      const Bars& bars = chart.series[s];
      std::string rects;
      for (std::size_t i = 0; i < chart.categories.size(); ++i) {
        const double y = r.top + row * static_cast<double>(i) + 0.15 * row + thickness * static_cast<double>(s);
        const double mid = y + 0.5 * thickness;
        if (i < bars.value.size() && std::isfinite(bars.value[i])) {
          const double end = std::clamp(xs(bars.value[i]), r.left, r.right);
          fmt::format_to(std::back_inserter(rects), "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/>",
                         Num(std::min(zero, end)), Num(y + 0.5 * gap), Num(std::abs(end - zero)), Num(thickness - gap));
        }
        if (i >= bars.lower.size() || i >= bars.upper.size()) continue;
        const double lo = bars.lower[i], hi = bars.upper[i];
        if (std::isnan(lo) || std::isnan(hi)) continue;
        const double from = lo == -kInfinity ? r.left : std::clamp(xs(lo), r.left, r.right);
        const double to = hi == kInfinity ? r.right : std::clamp(xs(hi), r.left, r.right);
        const double cap = 0.3 * thickness;
        fmt::format_to(std::back_inserter(whiskers), "M{} {}H{}", Num(from), Num(mid), Num(to));
        // A cap marks a finite bound; a clipped or unbounded side has none.
        if (std::isfinite(lo) && xs(lo) >= r.left) {
          fmt::format_to(std::back_inserter(whiskers), "M{} {}V{}", Num(from), Num(mid - cap), Num(mid + cap));
        }
        if (std::isfinite(hi) && xs(hi) <= r.right) {
          fmt::format_to(std::back_inserter(whiskers), "M{} {}V{}", Num(to), Num(mid - cap), Num(mid + cap));
        }
      }
      if (!rects.empty()) svg.Add("<g class=\"series\" fill=\"{}\">{}</g>\n", PaletteColour(bars.colour), rects);
    }
    if (!whiskers.empty()) {
      svg.Add("<path class=\"error\" d=\"{}\" fill=\"none\" stroke=\"#000\" stroke-width=\"1.2\"/>\n", whiskers);
    }
    DrawReferenceLines(svg, chart.lines, r, xs, nullptr, labels);
  } else {
    DrawNoData(svg, r);
  }
  for (std::size_t i = 0; i < chart.categories.size() && has_rows; ++i) {
    svg.Add("<text class=\"category{}\" x=\"{}\" y=\"{}\" text-anchor=\"end\" fill=\"#000\"{}>{}</text>\n",
            highlighted(i) ? " highlight" : "", Num(r.left - 8.0),
            Num(r.top + row * (static_cast<double>(i) + 0.5) + 4.0), highlighted(i) ? " font-weight=\"bold\"" : "",
            EscapeXml(chart.categories[i]));
  }
  DrawLabels(svg, labels, r);
  DrawAxisLabels(svg, r, chart.value.label, "");
  DrawLegend(svg, legend, legend_places);
  return svg.Finish();
}

std::string RenderHistogram(const HistogramChart& chart) {
  const double width = ValidSize(chart.width, 640.0, 200.0), height = ValidSize(chart.height, 360.0, 160.0);
  Svg svg(chart.title, width, height);
  const Rect r{kMarginLeft, kTitleBand + kLegendGap, width - kMarginRight, height - kMarginBottom};

  const int log_x = LogBase(chart.x);
  const bool bins_valid = std::isfinite(chart.lower) && std::isfinite(chart.bin_width) && chart.bin_width > 0.0;
  const auto edge = [&](std::size_t i) { return chart.lower + chart.bin_width * static_cast<double>(i); };
  const auto drawable = [&](std::size_t i) {
    return bins_valid && std::isfinite(chart.counts[i]) && chart.counts[i] >= 0.0 &&
           !std::isnan(Transform(log_x, edge(i))) && !std::isnan(Transform(log_x, edge(i + 1)));
  };
  Extent ex, ey;
  bool has_data = false;
  ey.Add(0.0);
  for (std::size_t i = 0; i < chart.counts.size(); ++i) {
    if (!drawable(i)) continue;
    ex.Add(Transform(log_x, edge(i)));
    ex.Add(Transform(log_x, edge(i + 1)));
    ey.Add(chart.counts[i]);
    has_data = true;
  }
  for (const ReferenceLine& line : chart.lines) {
    if (line.direction == ReferenceLine::Direction::kVertical) {
      ex.Add(Transform(log_x, line.at));
    } else {
      ey.Add(Transform(kLinear, line.at));
    }
  }
  Scale xs{log_x, 0.0, 1.0, r.left, r.right}, ys{kLinear, 0.0, 1.0, r.bottom, r.top};
  std::tie(xs.lo, xs.hi) = Ends(chart.x, ex);
  Axis count_axis;
  count_axis.min = 0.0;  // all-zero counts widen upwards only
  std::tie(ys.lo, ys.hi) = Ends(count_axis, ey);

  if (has_data) {
    DrawXTicks(svg, xs, AxisTicks(xs, MaxTicks(r.Width(), kPixelsPerXTick)), r);
    DrawYTicks(svg, ys, AxisTicks(ys, MaxTicks(r.Height(), kPixelsPerYTick)), r);
    std::string path;
    bool separated = true;  // a white line between bars, unless they are too narrow for it
    for (std::size_t i = 0; i < chart.counts.size(); ++i) {
      if (!drawable(i) || chart.counts[i] == 0.0) continue;
      const double x0 = std::clamp(xs(edge(i)), r.left, r.right), x1 = std::clamp(xs(edge(i + 1)), r.left, r.right);
      const double y = std::clamp(ys(chart.counts[i]), r.top, r.bottom);
      if (x1 - x0 < 6.0) separated = false;
      fmt::format_to(std::back_inserter(path), "M{} {}V{}H{}V{}Z", Num(x0), Num(r.bottom), Num(y), Num(x1),
                     Num(r.bottom));
    }
    if (!path.empty()) {
      svg.Add("<path class=\"series\" d=\"{}\" fill=\"{}\"{}/>\n", path, PaletteColour(chart.colour),
              separated ? " stroke=\"#fff\" stroke-width=\"1\"" : "");
    }
  }
  DrawFrame(svg, r);
  std::vector<Label> labels;
  DrawReferenceLines(svg, chart.lines, r, xs, &ys, labels);
  if (!has_data) DrawNoData(svg, r);
  DrawLabels(svg, labels, r);
  DrawAxisLabels(svg, r, chart.x.label, chart.count_label);
  return svg.Finish();
}

}  // namespace ringtol::jobs::svg
