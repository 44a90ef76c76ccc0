#include "jobs/report/svg_chart.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/support/text_files.h"

namespace ringtol::jobs::svg {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::Not;

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Coordinates are written rounded to 0.01 px (error <= 0.005 each); an expected position
// built from the frame's left (or bottom) and width (or height) and compared with a
// written point carries three such errors.
constexpr double kPixel = 0.015;

struct Point {
  double x = 0.0, y = 0.0;
};

struct Frame {
  double left = 0.0, top = 0.0, right = 0.0, bottom = 0.0;
};

// Parses every document with Python's XML parser (one process for all of them) and checks
// that no non-finite number leaked into it.
void ExpectValidSvg(const std::vector<std::string>& documents) {
  const std::string test = ::testing::UnitTest::GetInstance()->current_test_info()->name();
  std::string command =
      "/usr/bin/python3 -c 'import sys, xml.dom.minidom\nfor f in sys.argv[1:]: "
      "xml.dom.minidom.parse(f)'";
  for (std::size_t i = 0; i < documents.size(); ++i) {
    std::string lower = documents[i];
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
    EXPECT_THAT(lower, Not(HasSubstr("nan"))) << documents[i];
    EXPECT_THAT(lower, Not(HasSubstr("inf"))) << documents[i];
    EXPECT_EQ(documents[i].rfind("<svg ", 0), 0u);
    const std::filesystem::path file =
        std::filesystem::path(::testing::TempDir()) / ("svg_chart_" + test + std::to_string(i) + ".svg");
    std::ofstream(file, std::ios::binary) << documents[i];
    command += " " + file.string();
  }
  const std::filesystem::path log = std::filesystem::path(::testing::TempDir()) / ("svg_chart_" + test + ".log");
  command += " > " + log.string() + " 2>&1";
  EXPECT_EQ(std::system(command.c_str()), 0) << testing::ReadText(log);
}

// The opening tags that start with `start` (e.g. "<polyline"), in order.
std::vector<std::string> Tags(const std::string& svg, std::string_view start) {
  std::vector<std::string> tags;
  for (std::size_t at = svg.find(start); at != std::string::npos; at = svg.find(start, at + 1)) {
    tags.push_back(svg.substr(at, svg.find('>', at) - at + 1));
  }
  return tags;
}

std::string Attribute(const std::string& tag, std::string_view name) {
  const std::string key = " " + std::string(name) + "=\"";
  const std::size_t at = tag.find(key);
  if (at == std::string::npos) {
    ADD_FAILURE() << "no " << name << " in " << tag;
    return "";
  }
  const std::size_t begin = at + key.size();
  return tag.substr(begin, tag.find('"', begin) - begin);
}

double NumberAttribute(const std::string& tag, std::string_view name) { return std::stod(Attribute(tag, name)); }

// The tokens of SVG text: decimal numbers (-?[0-9]+(.[0-9]+)?) and, with `commands`, the
// path commands M H V L Z. A hand scanner: GCC 12 with sanitizers warns inside std::regex.
std::vector<std::string> Tokens(const std::string& text, bool commands) {
  std::vector<std::string> tokens;
  const auto digit = [&](std::size_t i) { return i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])); };
  for (std::size_t i = 0; i < text.size();) {
    if (commands && std::string_view("MHVLZ").find(text[i]) != std::string_view::npos) {
      tokens.emplace_back(1, text[i++]);
      continue;
    }
    const std::size_t start = i;
    if (text[i] == '-' && digit(i + 1)) ++i;
    if (!digit(i)) {
      i = start + 1;
      continue;
    }
    while (digit(i)) ++i;
    if (i < text.size() && text[i] == '.' && digit(i + 1)) {
      ++i;
      while (digit(i)) ++i;
    }
    tokens.push_back(text.substr(start, i - start));
  }
  return tokens;
}

std::vector<double> Numbers(const std::string& text) {
  std::vector<double> numbers;
  for (const std::string& token : Tokens(text, false)) numbers.push_back(std::stod(token));
  return numbers;
}

// The x and the y coordinates of a path of absolute M, H, V, L and Z commands.
struct PathCoordinates {
  std::vector<double> x, y;
};

PathCoordinates CoordinatesOf(const std::string& d) {
  PathCoordinates coordinates;
  char command = 'M';
  bool next_is_x = true;  // within M and L pairs
  for (const std::string& token : Tokens(d, true)) {
    if (std::isalpha(static_cast<unsigned char>(token[0]))) {
      command = token[0];
      next_is_x = true;
      continue;
    }
    const double value = std::stod(token);
    const bool is_x = command == 'H' || ((command == 'M' || command == 'L') && next_is_x);
    (is_x ? coordinates.x : coordinates.y).push_back(value);
    next_is_x = !next_is_x;
  }
  return coordinates;
}

std::vector<Point> PointsOf(const std::string& tag) {
  const std::vector<double> numbers = Numbers(Attribute(tag, "points"));
  std::vector<Point> points;
  for (std::size_t i = 0; i + 1 < numbers.size(); i += 2) points.push_back({numbers[i], numbers[i + 1]});
  return points;
}

Frame FrameOf(const std::string& svg) {
  const std::vector<std::string> frames = Tags(svg, "<rect class=\"frame\"");
  if (frames.size() != 1) {
    ADD_FAILURE() << frames.size() << " frames";
    return {};
  }
  const double x = NumberAttribute(frames[0], "x"), y = NumberAttribute(frames[0], "y");
  return {x, y, x + NumberAttribute(frames[0], "width"), y + NumberAttribute(frames[0], "height")};
}

std::size_t Count(const std::string& text, std::string_view what) {
  std::size_t count = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++count;
  return count;
}

// The points of the chart's only polyline: none, and a test failure, when it has
// another number of polylines.
std::vector<Point> OnlyPolylinePoints(const std::string& svg) {
  const std::vector<std::string> lines = Tags(svg, "<polyline");
  EXPECT_EQ(lines.size(), 1u) << "polylines in the chart";
  return lines.size() == 1 ? PointsOf(lines[0]) : std::vector<Point>{};
}

void ExpectInside(Point p, const Frame& f) {
  EXPECT_GE(p.x, f.left - kPixel);
  EXPECT_LE(p.x, f.right + kPixel);
  EXPECT_GE(p.y, f.top - kPixel);
  EXPECT_LE(p.y, f.bottom + kPixel);
}

TEST(SvgTicks, NiceTicksOfKnownRangesAreExactDecimals) {
  EXPECT_THAT(NiceTicks(0.0, 0.3).values, ElementsAre(0.0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3));
  const Ticks tenths = NiceTicks(0.0, 0.3, 4);
  EXPECT_THAT(tenths.values, ElementsAre(0.0, 0.1, 0.2, 0.3));  // exact: 0.3 is not 3 x 0.1
  EXPECT_THAT(tenths.labels, ElementsAre("0", "0.1", "0.2", "0.3"));
  EXPECT_THAT(NiceTicks(-0.02, 0.87).labels, ElementsAre("0", "0.2", "0.4", "0.6", "0.8"));
  EXPECT_THAT(NiceTicks(0.0, 1.0).labels, ElementsAre("0", "0.2", "0.4", "0.6", "0.8", "1"));
  EXPECT_THAT(NiceTicks(0.0, 100.0).labels, ElementsAre("0", "20", "40", "60", "80", "100"));
  EXPECT_THAT(NiceTicks(-3.7, 12.2).labels, ElementsAre("-2", "0", "2", "4", "6", "8", "10", "12"));
  EXPECT_THAT(NiceTicks(-0.013, 0.012).labels, ElementsAre("-0.01", "-0.005", "0", "0.005", "0.01"));
  EXPECT_THAT(NiceTicks(1e-6, 3e-6).labels, ElementsAre("1e-06", "1.5e-06", "2e-06", "2.5e-06", "3e-06"));
  EXPECT_THAT(NiceTicks(0.0, 3e7).labels, ElementsAre("0", "5e+06", "1e+07", "1.5e+07", "2e+07", "2.5e+07", "3e+07"));
  EXPECT_THAT(NiceTicks(0.0, 0.3, 3).labels, ElementsAre("0", "0.2"));
  EXPECT_TRUE(NiceTicks(1.0, 1.0).values.empty());
  EXPECT_TRUE(NiceTicks(0.0, kInf).values.empty());
  EXPECT_TRUE(NiceTicks(kNaN, 1.0).values.empty());
}

TEST(SvgTicks, NiceTicksKeepBetweenTwoAndEightEvenlySpacedTicksInsideTheRange) {
  for (int e = -8; e <= 8; ++e) {
    for (double lo : {-7.3, -1.0, 0.0, 0.4, 2.9}) {
      for (double span : {1.0, 1.1, 1.5, 2.2, 3.0, 4.9, 7.1, 9.99}) {
        const double scale = std::pow(10.0, e);
        const double a = lo * scale, b = (lo + span) * scale;
        const Ticks ticks = NiceTicks(a, b);
        ASSERT_GE(ticks.values.size(), 2u) << a << " " << b;
        ASSERT_LE(ticks.values.size(), 8u) << a << " " << b;
        ASSERT_EQ(ticks.labels.size(), ticks.values.size());
        // A tick within 1e-9 steps of an end counts as inside; steps agree to rounding.
        const double step = ticks.values[1] - ticks.values[0];
        EXPECT_GE(ticks.values.front(), a - 1e-9 * step);
        EXPECT_LE(ticks.values.back(), b + 1e-9 * step);
        for (std::size_t i = 1; i < ticks.values.size(); ++i) {
          EXPECT_NEAR(ticks.values[i] - ticks.values[i - 1], step, 1e-9 * step);
        }
      }
    }
  }
}

TEST(SvgTicks, Log2TicksAreCompactPowersOfTwo) {
  EXPECT_THAT(Log2Ticks(64.0, 1 << 20).labels, ElementsAre("64", "256", "1k", "4k", "16k", "64k", "256k", "1M"));
  EXPECT_THAT(Log2Ticks(0.5, 4.0).labels, ElementsAre("0.5", "1", "2", "4"));
  EXPECT_THAT(Log2Ticks(0.5, 4.0).values, ElementsAre(0.5, 1.0, 2.0, 4.0));
  // 2^10 .. 2^29 are 20 powers: every third keeps 7.
  EXPECT_THAT(Log2Ticks(1000.0, 1e9).labels, ElementsAre("1k", "8k", "64k", "512k", "4M", "32M", "256M"));
  EXPECT_TRUE(Log2Ticks(0.0, 4.0).values.empty());
}

TEST(SvgEscape, EscapesMarkupAndDropsControlCharacters) {
  EXPECT_EQ(EscapeXml("a<b & c>\"d\" 'e'\x01\tµ"), "a&lt;b &amp; c&gt;&quot;d&quot; &apos;e&apos;\tµ");
}

TEST(SvgChart, EscapesEveryTextAndIsAWellFormedDocumentWithViewBoxAndTitle) {
  const std::string nasty = "a<b & c>\"d\"";
  Chart chart;
  chart.title = nasty + " title";
  chart.x.label = nasty + " x";
  chart.y.label = nasty + " y";
  chart.series.push_back({.name = nasty + " series", .x = {1.0, 2.0}, .y = {3.0, 4.0}});
  chart.lines.push_back({ReferenceLine::Direction::kVertical, 1.5, nasty + " line"});
  BarChart bars;
  bars.title = nasty;
  bars.categories = {nasty, "spring"};
  bars.series.push_back({.name = nasty, .value = {0.1, 0.2}});
  bars.highlighted = {true, false};
  bars.highlight_label = nasty;
  HistogramChart histogram;
  histogram.title = nasty;
  histogram.count_label = nasty;
  histogram.counts = {1.0, 2.0};
  histogram.lines.push_back({ReferenceLine::Direction::kVertical, 1.0, nasty});
  const std::vector<std::string> svgs = {RenderChart(chart), RenderBarChart(bars), RenderHistogram(histogram)};
  for (const std::string& svg : svgs) {
    EXPECT_THAT(svg, Not(HasSubstr("a<b")));
    EXPECT_THAT(svg, HasSubstr("a&lt;b &amp; c&gt;&quot;d&quot;"));
    EXPECT_THAT(svg, HasSubstr("<title>a&lt;b &amp; c&gt;&quot;d&quot;"));
    EXPECT_THAT(svg, HasSubstr(" viewBox=\"0 0 640 "));
    EXPECT_THAT(svg, HasSubstr("font-family=\"DejaVu Sans, Arial, sans-serif\""));
    EXPECT_THAT(svg, Not(HasSubstr("<script")));
    EXPECT_THAT(svg, Not(HasSubstr("href")));
  }
  EXPECT_EQ(Count(svgs[0], "a&lt;b &amp; c&gt;&quot;d&quot; line"), 2u);  // the label and its halo
  ExpectValidSvg(svgs);
}

TEST(SvgChart, MapsDataCoordinatesLinearlyOntoTheFrame) {
  Chart chart;
  chart.x = {.label = "x", .min = 0.0, .max = 10.0};
  chart.y = {.label = "y", .min = 0.0, .max = 100.0};
  chart.series.push_back({.x = {2.0, 8.0}, .y = {25.0, 75.0}});
  const std::string svg = RenderChart(chart);
  const Frame f = FrameOf(svg);
  const std::vector<Point> points = OnlyPolylinePoints(svg);
  ASSERT_EQ(points.size(), 2u);
  const double width = f.right - f.left, height = f.bottom - f.top;
  EXPECT_NEAR(points[0].x, f.left + 0.2 * width, kPixel);
  EXPECT_NEAR(points[0].y, f.bottom - 0.25 * height, kPixel);
  EXPECT_NEAR(points[1].x, f.left + 0.8 * width, kPixel);
  EXPECT_NEAR(points[1].y, f.bottom - 0.75 * height, kPixel);
  ExpectValidSvg({svg});
}

TEST(SvgChart, PointMarkersKeepTheirShapeCentredOnThePointAndInTheLegend) {
  Chart chart;
  chart.x = {.label = "cost", .min = 0.0, .max = 10.0};
  chart.y = {.label = "yield", .min = 0.0, .max = 1.0};
  chart.series.push_back({.name = "square", .x = {5.0}, .y = {0.5}, .style = Series::Style::kPoints,
                          .marker = Series::Marker::kSquare});
  chart.series.push_back({.name = "triangle", .x = {2.0}, .y = {0.5}, .style = Series::Style::kPoints,
                          .marker = Series::Marker::kTriangle});
  chart.series.push_back({.name = "diamond", .x = {8.0}, .y = {0.5}, .style = Series::Style::kPoints,
                          .marker = Series::Marker::kDiamond});
  const std::string svg = RenderChart(chart);
  const Frame f = FrameOf(svg);
  // The square's rectangle is centred on the point: the middle of the frame.
  const std::vector<std::string> rects = Tags(svg, "<rect x");
  const double middle_x = 0.5 * (f.left + f.right), middle_y = 0.5 * (f.top + f.bottom);
  const auto centred = std::count_if(rects.begin(), rects.end(), [&](const std::string& r) {
    return std::abs(NumberAttribute(r, "x") + 0.5 * NumberAttribute(r, "width") - middle_x) < kPixel &&
           std::abs(NumberAttribute(r, "y") + 0.5 * NumberAttribute(r, "height") - middle_y) < kPixel;
  });
  EXPECT_EQ(centred, 1);
  // The triangle (three corners) and the diamond (four) as closed paths, in the plot and in
  // the legend: two of each, and no circle anywhere.
  const std::vector<std::string> paths = Tags(svg, "<path d=\"M");
  const auto closed = [&](std::size_t corners) {
    return std::count_if(paths.begin(), paths.end(), [&](const std::string& p) {
      const std::string d = Attribute(p, "d");
      return d.back() == 'Z' && static_cast<std::size_t>(std::count(d.begin(), d.end(), 'L')) + 1 == corners;
    });
  };
  EXPECT_EQ(closed(3), 2);
  EXPECT_EQ(closed(4), 2);
  EXPECT_THAT(svg, Not(HasSubstr("<circle")));
  ExpectValidSvg({svg});
}

TEST(SvgChart, Log2AxisPlacesEachDoublingOneStepFurther) {
  Chart chart;
  chart.x = {.label = "samples", .log2 = true, .min = 64.0, .max = 1024.0};
  chart.y = {.label = "estimate", .min = 0.0, .max = 1.0};
  chart.series.push_back({.x = {64.0, 128.0, 1024.0}, .y = {0.5, 0.5, 0.5}, .style = Series::Style::kPoints});
  const std::string svg = RenderChart(chart);
  const Frame f = FrameOf(svg);
  const std::vector<std::string> circles = Tags(svg, "<circle cx");
  ASSERT_EQ(circles.size(), 3u);
  EXPECT_NEAR(NumberAttribute(circles[0], "cx"), f.left, kPixel);
  EXPECT_NEAR(NumberAttribute(circles[1], "cx"), f.left + 0.25 * (f.right - f.left), kPixel);  // 1 of 4 octaves
  EXPECT_NEAR(NumberAttribute(circles[2], "cx"), f.right, kPixel);
  for (const char* label : {">64<", ">128<", ">256<", ">512<", ">1k<"}) EXPECT_THAT(svg, HasSubstr(label));
  ExpectValidSvg({svg});
}

TEST(SvgChart, StepHoldsEachValueUntilTheNextPoint) {
  Chart chart;
  chart.x = {.min = 0.0, .max = 2.0};
  chart.y = {.min = 0.0, .max = 1.0};
  chart.series.push_back({.x = {0.0, 1.0, 2.0}, .y = {0.0, 0.5, 1.0}, .style = Series::Style::kStep});
  const std::string svg = RenderChart(chart);
  const Frame f = FrameOf(svg);
  const std::vector<Point> p = OnlyPolylinePoints(svg);
  ASSERT_EQ(p.size(), 5u);
  const double mid_x = 0.5 * (f.left + f.right), mid_y = 0.5 * (f.top + f.bottom);
  const std::vector<Point> expected = {
      {f.left, f.bottom}, {mid_x, f.bottom}, {mid_x, mid_y}, {f.right, mid_y}, {f.right, f.top}};
  for (std::size_t i = 0; i < p.size(); ++i) {
    EXPECT_NEAR(p[i].x, expected[i].x, kPixel) << i;
    EXPECT_NEAR(p[i].y, expected[i].y, kPixel) << i;
  }
}

TEST(SvgChart, NonFiniteValuesAreGapsAndNeverWritten) {
  Chart chart;
  chart.series.push_back(
      {.name = "with gaps", .x = {1.0, 2.0, 3.0, kInf, 5.0, 6.0}, .y = {1.0, 2.0, kNaN, 4.0, 5.0, 6.0}});
  chart.series.push_back({.x = {1.0, 2.0}, .y = {-kInf, kNaN}, .style = Series::Style::kPoints});
  chart.lines.push_back({ReferenceLine::Direction::kHorizontal, kNaN, "nowhere"});
  const std::string svg = RenderChart(chart);
  EXPECT_EQ(Tags(svg, "<polyline").size(), 2u);  // (1,1)-(2,2) and (5,5)-(6,6)
  EXPECT_EQ(Tags(svg, "<circle cx").size(), 0u);
  EXPECT_THAT(svg, Not(HasSubstr("no data")));
  ExpectValidSvg({svg});
}

TEST(SvgChart, EqualAspectDrawsACircleAsWideAsItIsTall) {
  // The circle touches (1 ± 3, -2) and (1, -2 ± 3); a wide second series makes the x range
  // the longer one, so y is the axis that the equal aspect widens.
  constexpr double kCx = 1.0, kCy = -2.0, kR = 3.0;
  Chart chart;
  chart.title = "ring centre";
  chart.x.label = "x [µm]";
  chart.y.label = "y [µm]";
  chart.equal_aspect = true;
  chart.series.push_back(
      {.name = "touch points", .x = {kCx - kR, kCx + kR, kCx, kCx}, .y = {kCy, kCy, kCy + kR, kCy - kR}});
  chart.series.push_back({.name = "wide", .x = {-20.0, 20.0}, .y = {0.0, 0.0}, .colour = 1, .dashed = true});
  chart.circle = Circle{kCx, kCy, kR, "minimum enclosing circle"};
  const std::string svg = RenderChart(chart);
  const std::vector<std::string> circles = Tags(svg, "<circle class=\"circle\"");
  ASSERT_EQ(circles.size(), 1u);
  const std::vector<std::string> lines = Tags(svg, "<polyline");
  ASSERT_EQ(lines.size(), 2u);
  const std::vector<Point> p = PointsOf(lines[0]);
  ASSERT_EQ(p.size(), 4u);
  const double r = NumberAttribute(circles[0], "r");
  EXPECT_GT(r, 10.0);
  EXPECT_NEAR(p[1].x - p[0].x, 2.0 * r, 2.0 * kPixel);
  EXPECT_NEAR(p[2].y - p[3].y, -2.0 * r, 2.0 * kPixel);  // y grows upwards, pixels downwards
  EXPECT_NEAR(NumberAttribute(circles[0], "cx"), p[2].x, kPixel);
  EXPECT_NEAR(NumberAttribute(circles[0], "cy"), p[0].y, kPixel);
  EXPECT_THAT(Attribute(circles[0], "stroke-dasharray"), Not(::testing::IsEmpty()));
  EXPECT_THAT(svg, HasSubstr(">minimum enclosing circle<"));
  ExpectValidSvg({svg});
}

TEST(SvgChart, InfiniteBandBoundsAreClippedToThePlotArea) {
  Chart chart;
  chart.title = "S1 of ring shape";
  chart.x = {.label = "samples", .log2 = true};
  chart.y = {.label = "S1"};
  chart.series.push_back({.name = "estimate",
                          .x = {64.0, 128.0, 256.0, 512.0},
                          .y = {1.0, 1.2, 1.1, 1.05},
                          .style = Series::Style::kPoints,
                          .band_lower = {-kInf, 0.8, 0.9, 1.0},
                          .band_upper = {kInf, kInf, 1.4, 1.1}});
  chart.lines.push_back({ReferenceLine::Direction::kHorizontal, 1.0, "reference"});
  const std::string svg = RenderChart(chart);
  const Frame f = FrameOf(svg);
  const std::vector<std::string> bands = Tags(svg, "<polygon");
  ASSERT_EQ(bands.size(), 1u);
  const std::vector<Point> band = PointsOf(bands[0]);
  ASSERT_GE(band.size(), 3u);
  bool touches_top = false, touches_bottom = false;
  for (const Point& p : band) {
    ExpectInside(p, f);
    touches_top = touches_top || std::abs(p.y - f.top) <= kPixel;
    touches_bottom = touches_bottom || std::abs(p.y - f.bottom) <= kPixel;
  }
  EXPECT_TRUE(touches_top);
  EXPECT_TRUE(touches_bottom);
  EXPECT_EQ(Tags(svg, "<path class=\"reference\"").size(), 1u);
  ExpectValidSvg({svg});
}

TEST(SvgChart, LinesBeyondFixedAxesAreClippedAtTheFrame) {
  Chart chart;
  chart.x = {.min = 0.0, .max = 1.0};
  chart.y = {.min = 0.0, .max = 1.0};
  chart.series.push_back({.x = {-1.0, 0.5, 2.0}, .y = {0.5, 0.5, 3.5}});
  const std::string svg = RenderChart(chart);
  const Frame f = FrameOf(svg);
  const std::vector<Point> p = OnlyPolylinePoints(svg);
  ASSERT_EQ(p.size(), 3u);
  for (const Point& point : p) ExpectInside(point, f);
  EXPECT_NEAR(p.front().x, f.left, kPixel);
  EXPECT_NEAR(p.back().y, f.top, kPixel);  // y = 0.5 + 2 (x - 0.5) leaves through the top at x = 0.75
  EXPECT_NEAR(p.back().x, f.left + 0.75 * (f.right - f.left), kPixel);
}

TEST(SvgChart, AStepLineOfManySamplesIsThinnedToItsPixelColumns) {
  constexpr int kSamples = 200'000;
  Series cdf{.name = "empirical CDF", .style = Series::Style::kStep};
  for (int i = 0; i < kSamples; ++i) {
    const double u = (i + 0.5) / kSamples;
    cdf.x.push_back(u * u * 10.0);
    cdf.y.push_back((i + 1.0) / kSamples);
  }
  Chart chart;
  chart.y = {.label = "fraction", .min = 0.0, .max = 1.0};
  chart.series.push_back(std::move(cdf));
  chart.lines.push_back({ReferenceLine::Direction::kVertical, 9.0, "spec"});
  chart.lines.push_back({ReferenceLine::Direction::kHorizontal, 0.99, "99 %"});
  const std::string svg = RenderChart(chart);
  // The M4 reduction keeps at most 4 points per half-pixel column.
  const Frame f = FrameOf(svg);
  std::size_t points = 0;
  for (const std::string& line : Tags(svg, "<polyline")) points += PointsOf(line).size();
  EXPECT_GT(points, 0u);
  EXPECT_LE(static_cast<double>(points), 4.0 * 2.0 * (f.right - f.left + 1.0));
  EXPECT_LT(svg.size(), 100'000u);
  ExpectValidSvg({svg});
}

TEST(SvgChart, AFixedTickStepPutsTicksAtItsMultiples) {
  Chart chart;
  chart.x = {.label = "ring angle [deg]", .min = 0.0, .max = 360.0, .step = 90.0};
  chart.series.push_back({.x = {0.0, 180.0, 360.0}, .y = {0.0, 1.0, 0.0}});
  const std::string svg = RenderChart(chart);
  for (const char* label : {">0<", ">90<", ">180<", ">270<", ">360<"}) EXPECT_THAT(svg, HasSubstr(label)) << label;
  EXPECT_THAT(svg, Not(HasSubstr(">50<")));
  // A step that would crowd the axis gives way to nice numbers.
  chart.x.step = 1.0;
  EXPECT_THAT(RenderChart(chart), Not(HasSubstr(">17<")));
  ExpectValidSvg({svg});
}

TEST(SvgDecimate, AShortCurveComesBackWhole) {
  const std::vector<double> x = {0.0, 1.0, 2.0}, y = {3.0, 4.0, 5.0};
  EXPECT_THAT(DecimateCurve(x, y, 3), ElementsAre(0u, 1u, 2u));
}

// A centre path that winds fifty times around a slowly drifting circle, with a fast ripple:
// 200,001 points, every one distinct. The kept ones are few, ascending, and hold the ends,
// each axis's extremes, and the point farthest from a given centre.
TEST(SvgDecimate, ALongPathKeepsItsEndsAndEveryExtreme) {
  constexpr std::size_t kPoints = 200'001, kKept = 2000;
  std::vector<double> x(kPoints), y(kPoints);
  for (std::size_t i = 0; i < kPoints; ++i) {
    const double t = 2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(kPoints - 1);
    x[i] = (100.0 + std::sin(7.0 * t)) * std::cos(50.0 * t) + 3.0 * t;
    y[i] = (100.0 + std::cos(331.0 * t)) * std::sin(50.0 * t) - 2.0 * t;
  }
  const std::array<double, 2> centre = {10.0, -5.0};
  const std::vector<std::size_t> kept = DecimateCurve(x, y, kKept, centre);
  EXPECT_LE(kept.size(), kKept);
  constexpr std::size_t kRuns = kKept / 7;  // seven kept at most per run
  EXPECT_GE(kept.size(), 2 * kRuns) << "every run keeps its first and last point";
  EXPECT_TRUE(std::is_sorted(kept.begin(), kept.end()));
  EXPECT_EQ(std::adjacent_find(kept.begin(), kept.end()), kept.end()) << "no index twice";
  const auto has = [&](std::size_t i) { return std::binary_search(kept.begin(), kept.end(), i); };
  EXPECT_TRUE(has(0));
  EXPECT_TRUE(has(kPoints - 1));
  const auto at = [](const std::vector<double>& v, auto it) { return static_cast<std::size_t>(it - v.begin()); };
  EXPECT_TRUE(has(at(x, std::min_element(x.begin(), x.end()))));
  EXPECT_TRUE(has(at(x, std::max_element(x.begin(), x.end()))));
  EXPECT_TRUE(has(at(y, std::min_element(y.begin(), y.end()))));
  EXPECT_TRUE(has(at(y, std::max_element(y.begin(), y.end()))));
  std::size_t farthest = 0;
  for (std::size_t i = 0; i < kPoints; ++i) {
    if (std::hypot(x[i] - centre[0], y[i] - centre[1]) > std::hypot(x[farthest] - centre[0], y[farthest] - centre[1]))
      farthest = i;
  }
  EXPECT_TRUE(has(farthest));
}

TEST(SvgDecimate, ANonFinitePointIsNeverAnExtreme) {
  std::vector<double> x(100), y(100);
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = static_cast<double>(i);
    y[i] = std::sin(0.1 * static_cast<double>(i));
  }
  x[40] = kNaN;
  y[41] = kInf;  // infinite is an extreme like any other value: only NaN is not
  const std::vector<std::size_t> kept = DecimateCurve(x, y, 7);
  EXPECT_LE(kept.size(), 7u);
  EXPECT_FALSE(std::binary_search(kept.begin(), kept.end(), std::size_t{40}));
  EXPECT_TRUE(std::binary_search(kept.begin(), kept.end(), std::size_t{41}));
}

TEST(SvgBarChart, HighlightedCategoriesGetTheHighlightStyle) {
  BarChart chart;
  chart.title = "indices by harmonic order";
  chart.categories = {"2", "3", "4", "5", "6"};
  chart.highlighted = {false, true, false, false, true};
  chart.highlight_label = "multiple of the roller count";
  chart.series.push_back({.name = "S1", .value = {0.1, 0.5, 0.0, 0.02, 0.3}});
  chart.series.push_back({.name = "ST", .value = {0.12, 0.55, 0.01, 0.03, 0.33}, .colour = 1});
  const std::string svg = RenderBarChart(chart);
  EXPECT_EQ(Tags(svg, "<rect class=\"highlight\"").size(), 2u);
  const std::vector<std::string> labels = Tags(svg, "<text class=\"category");
  ASSERT_EQ(labels.size(), 5u);
  for (std::size_t i = 0; i < labels.size(); ++i) {
    EXPECT_EQ(labels[i].find("font-weight=\"bold\"") != std::string::npos, static_cast<bool>(chart.highlighted[i]))
        << labels[i];
  }
  EXPECT_THAT(svg, HasSubstr(">multiple of the roller count<"));
  EXPECT_EQ(Tags(svg, "<rect x").size(), 10u + 3u);  // two bars per category, three legend swatches
  ExpectValidSvg({svg});
}

TEST(SvgBarChart, AxisIncludesNegativeValuesAndErrorBarsStayInside) {
  BarChart chart;
  chart.categories = {"ring shape", "roller shape", "roller position", "spring"};
  chart.value.label = "Sobol' index";
  chart.series.push_back({.name = "S1",
                          .value = {0.6, -0.02, 0.1, kNaN},
                          .lower = {0.5, -0.08, 0.05, kNaN},
                          .upper = {0.7, 0.04, 0.15, kNaN}});
  chart.series.push_back({.name = "ST",
                          .value = {0.7, 0.01, 0.2, 0.0},
                          .lower = {0.6, -kInf, 0.1, 0.0},
                          .upper = {kInf, 0.05, 0.3, 0.01},
                          .colour = 1});
  const std::string svg = RenderBarChart(chart);
  const Frame f = FrameOf(svg);
  const std::vector<std::string> errors = Tags(svg, "<path class=\"error\"");
  ASSERT_EQ(errors.size(), 1u);
  const PathCoordinates whiskers = CoordinatesOf(Attribute(errors[0], "d"));
  ASSERT_FALSE(whiskers.x.empty());
  for (const double x : whiskers.x) {
    EXPECT_GE(x, f.left - kPixel);
    EXPECT_LE(x, f.right + kPixel);
  }
  // The unbounded sides of ST's first and second error bars reach the frame.
  EXPECT_NEAR(*std::max_element(whiskers.x.begin(), whiskers.x.end()), f.right, kPixel);
  EXPECT_NEAR(*std::min_element(whiskers.x.begin(), whiskers.x.end()), f.left, kPixel);
  // The negative S1 bar ends where the positive ones start (at 0), and starts inside the frame.
  const std::vector<std::string> s1 = Tags(svg.substr(svg.find("<g class=\"series\"")), "<rect x");
  ASSERT_GE(s1.size(), 3u);
  EXPECT_NEAR(NumberAttribute(s1[1], "x") + NumberAttribute(s1[1], "width"), NumberAttribute(s1[0], "x"), kPixel);
  EXPECT_GT(NumberAttribute(s1[1], "width"), 0.0);
  EXPECT_GT(NumberAttribute(s1[1], "x"), f.left);
  EXPECT_THAT(svg, HasSubstr(">0<"));
  ExpectValidSvg({svg});
}

TEST(SvgHistogram, DrawsBinsAndALabelledSpecLine) {
  HistogramChart chart;
  chart.title = "runout";
  chart.x.label = "runout [µm]";
  chart.lower = 0.0;
  chart.bin_width = 0.5;
  chart.counts = {1.0, 3.0, 5.0, 2.0, 0.0, 1.0};
  chart.lines.push_back({ReferenceLine::Direction::kVertical, 4.0, "spec ≤ 4 µm"});
  const std::string svg = RenderHistogram(chart);
  const Frame f = FrameOf(svg);
  const std::vector<std::string> bars = Tags(svg, "<path class=\"series\"");
  ASSERT_EQ(bars.size(), 1u);
  EXPECT_EQ(Count(Attribute(bars[0], "d"), "Z"), 5u);  // the empty bin is not drawn
  const PathCoordinates corners = CoordinatesOf(Attribute(bars[0], "d"));
  EXPECT_NEAR(*std::min_element(corners.x.begin(), corners.x.end()), f.left, kPixel);  // 0 stays the axis end
  EXPECT_NEAR(*std::max_element(corners.y.begin(), corners.y.end()), f.bottom, kPixel);
  EXPECT_EQ(Tags(svg, "<path class=\"reference\"").size(), 1u);
  EXPECT_THAT(svg, HasSubstr(">spec ≤ 4 µm<"));
  ExpectValidSvg({svg});
}

// A label's box, estimated as a renderer would lay it out: 0.6 em a glyph (DejaVu Sans's
// average advance, the widest of the fonts the charts name) at the charts' 12 px, from
// 0.8 em above its baseline (capitals and digits reach 0.73 em) to 0.2 em below it
// (descenders reach 0.24 em; a label's digits and most letters have none).
struct Box {
  double left = 0.0, top = 0.0, right = 0.0, bottom = 0.0;
};
constexpr double kFontPx = 12.0;

Box LabelBox(const std::string& svg, const std::string& label) {
  // The black copy; a white halo of the same text is drawn under it.
  const std::size_t at = svg.find("fill=\"#000\">" + EscapeXml(label) + "</text>");
  if (at == std::string::npos) {
    ADD_FAILURE() << "no label " << label;
    return {};
  }
  const std::size_t open = svg.rfind("<text", at);
  const std::string tag = svg.substr(open, svg.find('>', open) - open + 1);
  std::size_t glyphs = 0;
  for (const char c : label) glyphs += (static_cast<unsigned char>(c) & 0xC0) != 0x80;
  const double width = 0.6 * kFontPx * static_cast<double>(glyphs);
  const double x = NumberAttribute(tag, "x"), y = NumberAttribute(tag, "y");
  const bool end = Attribute(tag, "text-anchor") == "end";
  return {end ? x - width : x, y - 0.8 * kFontPx, end ? x : x + width, y + 0.2 * kFontPx};
}

bool Overlap(const Box& a, const Box& b) {
  return a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom;
}

void ExpectApartAndInside(const std::string& svg, const std::vector<std::string>& labels) {
  const Frame f = FrameOf(svg);
  std::vector<Box> boxes;
  for (const std::string& label : labels) {
    boxes.push_back(LabelBox(svg, label));
    const Box& b = boxes.back();
    EXPECT_GE(b.left, f.left - kPixel) << label;
    EXPECT_LE(b.right, f.right + kPixel) << label;
    EXPECT_GE(b.top, f.top - kPixel) << label;
    EXPECT_LE(b.bottom, f.bottom + kPixel) << label;
  }
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    for (std::size_t j = i + 1; j < boxes.size(); ++j) {
      EXPECT_FALSE(Overlap(boxes[i], boxes[j])) << labels[i] << " overprints " << labels[j];
    }
  }
}

// An empirical CDF whose spec limit lies where the 99 % level is labelled, at the right
// end: neither label is drawn over the other.
TEST(SvgChart, TheSpecLabelIsNotDrawnOverTheNinetyNinePercentLabel) {
  Chart chart;
  chart.title = "Empirical CDF of asynchronous error motion [mm]";
  chart.y.min = 0.0;
  chart.y.max = 1.0;
  Series cdf{.name = "empirical CDF", .style = Series::Style::kStep};
  for (int i = 0; i <= 100; ++i) {
    cdf.x.push_back(0.00405 * i / 100.0);
    cdf.y.push_back(i / 100.0);
  }
  chart.series.push_back(std::move(cdf));
  chart.lines = {{ReferenceLine::Direction::kVertical, 0.004, "spec 0.004"},
                 {ReferenceLine::Direction::kHorizontal, 0.99, "99 %"}};
  const std::string svg = RenderChart(chart);
  ExpectApartAndInside(svg, {"spec 0.004", "99 %"});
  ExpectValidSvg({svg});
}

// Vertical markers closer than their labels' width stack at different heights; one far
// from both keeps the top row.
TEST(SvgChart, LabelsOfNearbyVerticalMarkersStackAndAFarOneKeepsTheTop) {
  Chart chart;
  chart.title = "spec and q99 nearly coincide";
  chart.series.push_back({.name = "data", .x = {0.0, 0.005}, .y = {0.0, 1.0}});
  chart.lines = {{ReferenceLine::Direction::kVertical, 0.0040, "spec 0.004"},
                 {ReferenceLine::Direction::kVertical, 0.00402, "q99 0.00402"},
                 {ReferenceLine::Direction::kVertical, 0.0041, "q99.9 0.0041"},
                 {ReferenceLine::Direction::kVertical, 0.00415, "max 0.00415"},
                 {ReferenceLine::Direction::kVertical, 0.0005, "q50 0.0005"}};
  const std::vector<std::string> labels = {"spec 0.004", "q99 0.00402", "q99.9 0.0041", "max 0.00415", "q50 0.0005"};
  const std::string svg = RenderChart(chart);
  ExpectApartAndInside(svg, labels);
  EXPECT_EQ(LabelBox(svg, "q50 0.0005").top, LabelBox(svg, "spec 0.004").top);
  ExpectValidSvg({svg});

  HistogramChart histogram;
  histogram.title = "the same on a histogram";
  histogram.lower = 0.0;
  histogram.bin_width = 0.001;
  histogram.counts = {3.0, 5.0, 2.0, 1.0, 1.0};
  histogram.lines = chart.lines;
  const std::string bars = RenderHistogram(histogram);
  ExpectApartAndInside(bars, labels);
  ExpectValidSvg({bars});
}

TEST(SvgPolar, TheDivisionIsTheFinestNiceStepThatKeepsEveryValueWithinTheRings) {
  EXPECT_EQ(PolarDivision(-3.0, 7.0), 2.0);  // 7 / 4 = 1.75
  EXPECT_EQ(PolarDivision(-12.0, 3.0), 5.0);  // 12 / 4 = 3
  EXPECT_EQ(PolarDivision(0.0, 4.0), 1.0);    // exactly four divisions out
  EXPECT_EQ(PolarDivision(-0.3, 0.3), 0.1);   // 0.075
  EXPECT_EQ(PolarDivision(0.0, 0.0), 1.0);
  EXPECT_EQ(PolarDivision(kNaN, 1.0), 1.0);
}

// A deviation v is drawn kPolarBaseDivisions + v / units_per_division divisions from the
// centre, at its angle counter-clockwise from +x; beyond the rings it stays on the
// outermost one, and a NaN point is left out.
TEST(SvgPolar, DeviationsAreDrawnTheirDivisionsOutFromTheBaseCircle) {
  PolarChart chart;
  chart.title = "error motion";
  chart.unit = "µm";
  chart.units_per_division = 0.5;
  chart.curves.push_back(
      {.name = "average", .angle_deg = {0.0, 90.0, 180.0, 270.0, 300.0}, .value = {0.0, 0.5, -1.0, 100.0, kNaN}});
  chart.circles.push_back({.value = 1.0, .name = "outer"});
  chart.bands.push_back({.name = "revolutions", .angle_deg = {0.0, 120.0, 240.0}, .lower = {-1.0, -1.0, -1.0},
                         .upper = {1.0, 1.0, 1.0}});
  const std::string svg = RenderPolarChart(chart);
  const std::vector<std::string> base = Tags(svg, "<circle class=\"base\"");
  ASSERT_EQ(base.size(), 1u);
  const double cx = NumberAttribute(base[0], "cx"), cy = NumberAttribute(base[0], "cy");
  const double division = NumberAttribute(base[0], "r") / kPolarBaseDivisions;
  const std::vector<std::string> curves = Tags(svg, "<path class=\"series\"");
  ASSERT_EQ(curves.size(), 1u);
  const PathCoordinates p = CoordinatesOf(Attribute(curves[0], "d"));
  ASSERT_EQ(p.x.size(), 4u);
  ASSERT_EQ(p.y.size(), 4u);
  EXPECT_NEAR(p.x[0] - cx, kPolarBaseDivisions * division, kPixel);
  EXPECT_NEAR(p.y[0], cy, kPixel);
  EXPECT_NEAR(cy - p.y[1], (kPolarBaseDivisions + 1) * division, kPixel);  // y grows upwards, pixels downwards
  EXPECT_NEAR(cx - p.x[2], (kPolarBaseDivisions - 2) * division, kPixel);
  EXPECT_NEAR(p.y[3] - cy, (kPolarBaseDivisions + kPolarDivisionsOut) * division, kPixel);
  const std::vector<std::string> circles = Tags(svg, "<circle class=\"circle\"");
  ASSERT_EQ(circles.size(), 1u);
  EXPECT_NEAR(NumberAttribute(circles[0], "r"), (kPolarBaseDivisions + 2) * division, kPixel);
  const std::vector<std::string> bands = Tags(svg, "<path class=\"band\"");
  ASSERT_EQ(bands.size(), 1u);
  EXPECT_EQ(Attribute(bands[0], "fill-rule"), "evenodd");
  EXPECT_THAT(svg, HasSubstr("0.5 µm per division"));
  EXPECT_THAT(svg, HasSubstr(">revolutions<"));
  ExpectValidSvg({svg});
}

TEST(SvgEmpty, EmptyAndDegenerateInputsGiveValidChartsThatSayNoData) {
  // Named rather than temporaries: GCC 12 at -O3 misreads a temporary's strings as
  // maybe-uninitialized.
  const Chart no_chart;
  const BarChart no_bars;
  const HistogramChart no_histogram;
  Chart all_nan;
  all_nan.series.push_back({.x = {kNaN, 1.0}, .y = {1.0, kInf}});
  BarChart categories_only;
  categories_only.categories = {"ring shape"};
  HistogramChart no_width;
  no_width.counts = {1.0, 2.0};
  no_width.bin_width = 0.0;
  Chart tiny;
  tiny.width = 0.0;
  tiny.height = kNaN;
  const std::vector<std::string> empty = {
      RenderChart(no_chart), RenderBarChart(no_bars),         RenderHistogram(no_histogram),
      RenderChart(all_nan),  RenderBarChart(categories_only), RenderHistogram(no_width),
      RenderChart(tiny)};
  for (const std::string& svg : empty) EXPECT_THAT(svg, HasSubstr(">no data<")) << svg;

  Chart one_point;
  one_point.series.push_back({.x = {3.0}, .y = {5.0}, .style = Series::Style::kPoints});
  Chart flat;
  flat.x.log2 = true;
  flat.series.push_back({.x = {64.0, 64.0}, .y = {0.0, 0.0}});
  HistogramChart zeros;
  zeros.counts = {0.0, 0.0};
  BarChart all_zero;
  all_zero.categories = {"spring"};
  all_zero.series.push_back({.value = {0.0}});
  const std::vector<std::string> degenerate = {RenderChart(one_point), RenderChart(flat), RenderHistogram(zeros),
                                               RenderBarChart(all_zero)};
  for (const std::string& svg : degenerate) EXPECT_THAT(svg, Not(HasSubstr(">no data<"))) << svg;
  EXPECT_EQ(Tags(degenerate[0], "<circle cx").size(), 1u);

  std::vector<std::string> all = empty;
  all.insert(all.end(), degenerate.begin(), degenerate.end());
  ExpectValidSvg(all);
}

}  // namespace
}  // namespace ringtol::jobs::svg
