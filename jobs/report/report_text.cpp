#include "jobs/report/report_text.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "jobs/campaign/sample_record.h"
#include "jobs/report/population_view.h"

namespace ringtol::jobs {
namespace {

// The finest a reported length resolves [µm]: 1 nm.
constexpr double kResolutionUm = 1e-3;
constexpr int kResolutionDecimals = 3;  // of kResolutionUm
constexpr int kSignificantDigits = 4;

}  // namespace

std::string Micrometres(double value_um) {
  if (!std::isfinite(value_um)) return "unbounded";
  if (value_um == 0.0) return "0 µm";
  if (std::abs(value_um) < 0.5 * kResolutionUm) return "< 0.001 µm";
  // Decimals for four significant digits, at most the resolution's and at least none.
  const int magnitude = static_cast<int>(std::floor(std::log10(std::abs(value_um))));
  const int decimals = std::clamp(kSignificantDigits - 1 - magnitude, 0, kResolutionDecimals);
  std::string text = fmt::format("{:.{}f}", value_um, decimals);
  if (text.find('.') != std::string::npos) {
    text.erase(text.find_last_not_of('0') + 1);
    if (text.back() == '.') text.pop_back();
  }
  return text + " µm";
}

std::string Decimals(double value, int decimals) {
  std::string text = fmt::format("{:.{}f}", value, std::max(0, decimals));
  if (text.front() == '-' && text.find_first_not_of("-0.") == std::string::npos) text.erase(0, 1);
  return text;
}

std::string CapabilityIndex(double value) {
  constexpr int kCapabilityDecimals = 2;
  return std::isfinite(value) ? Decimals(value, kCapabilityDecimals) : "unbounded";
}

namespace {

int YieldDecimals(std::int64_t trials) {
  // 100 / trials percentage points a sample: decimals enough to tell one sample apart.
  const double step = 100.0 / static_cast<double>(std::max<std::int64_t>(1, trials));
  return std::max(1, static_cast<int>(std::ceil(-std::log10(step))));
}

}  // namespace

std::string Percent(double fraction) { return fmt::format("{:.4g} %", 100.0 * fraction); }

std::string YieldPercent(double fraction, std::int64_t trials) {
  return fmt::format("{:.{}f} %", 100.0 * fraction, YieldDecimals(trials));
}

std::string YieldWithInterval(const analysis::ProportionEstimate& yield) {
  const int decimals = YieldDecimals(yield.trials);
  return fmt::format("{:.{}f} % [{:.{}f}, {:.{}f} %]", 100.0 * yield.value, decimals, 100.0 * yield.interval.lower,
                     decimals, 100.0 * yield.interval.upper, decimals);
}

namespace {

// Each value's column and word, in kErrorMotionValues order.
struct ErrorMotionNames {
  const char* column;
  const char* word;
};
constexpr ErrorMotionNames kErrorMotionNames[] = {{"error_motion_total_mm", "total"},
                                                  {"error_motion_synchronous_mm", "synchronous"},
                                                  {"error_motion_asynchronous_mm", "asynchronous"}};
static_assert(std::size(kErrorMotionNames) == std::size(kErrorMotionValues));
static_assert([] {
  for (const ErrorMotionNames& names : kErrorMotionNames) {
    const std::size_t output = OutputIndex(names.column);
    if (output == kOutputCount || !IsLifeOutput(output) || !IsErrorMotionOutput(names.column)) return false;
  }
  return true;
}(), "each column is an error-motion life output of the outputs table");

const ErrorMotionNames& NamesOf(ErrorMotionValue value) { return kErrorMotionNames[static_cast<std::size_t>(value)]; }

}  // namespace

std::optional<ErrorMotionValue> ErrorMotionOf(std::string_view output) {
  for (const ErrorMotionValue value : kErrorMotionValues) {
    if (output == NamesOf(value).column) return value;
  }
  return std::nullopt;
}

const char* ErrorMotionColumn(ErrorMotionValue value) { return NamesOf(value).column; }

std::string_view ErrorMotionWord(ErrorMotionValue value) { return NamesOf(value).word; }

std::string ErrorMotionName(ErrorMotionValue value) { return fmt::format("{} error motion", ErrorMotionWord(value)); }

std::string ErrorMotionFilterName(const engine::ErrorMotionFilter& filter) {
  return filter.filtered() ? fmt::format("Gaussian filter at {:g} UPR (ISO 16610-21)", filter.cutoff_upr)
                           : std::string("unfiltered");
}

namespace {

// Parts named in a line before the rest are counted: a line stays a line.
constexpr std::size_t kPartsNamed = 5;

std::string PartsOutside(const PopulationView& view) {
  std::vector<std::string> names;
  for (const MeasuredPartView& part : view.parts) {
    if (!part.within_class) names.push_back(part.name);
  }
  if (names.empty()) return "";
  const std::size_t more = names.size() > kPartsNamed ? names.size() - kPartsNamed : 0;
  names.resize(names.size() - more);
  return fmt::format(" (outside: {}{})", fmt::join(names, ", "), more > 0 ? fmt::format(" and {} more", more) : "");
}

std::string ClassWords(const PopulationView& view) {
  std::string words = view.class_name;
  if (view.mode == sampling::ToleranceMode::kInspected) words += " (inspected)";
  if (!view.class_chosen) return words;
  const std::string at = fmt::format("{:g} mm", view.diameter_mm);
  return PartsWithinClass(view) == static_cast<std::int64_t>(view.parts.size())
             ? fmt::format("{}, the tightest class every part meets at {}", words, at)
             : fmt::format("{}, the loosest class at {} (none holds every part)", words, at);
}

}  // namespace

std::string PopulationLine(const PopulationView& view) {
  std::string draw;
  if (view.draw == sampling::PopulationDraw::kModel) {
    draw = "drawn from a law fitted to them";
  } else {
    draw = view.ring ? "resampled" : "resampled without replacement";
  }
  std::string line = fmt::format("{} population: {} measured parts, {}", view.ring ? "ring" : "roller",
                                 view.parts.size(), draw);
  if (view.class_name.empty()) {
    return line + fmt::format("; not compared with a class: {}", view.class_problem.value_or(""));
  }
  line += fmt::format("; against {}: {} of {} within {} {}{}", ClassWords(view), PartsWithinClass(view),
                      view.parts.size(), view.ring ? "RONt" : "VDsp", Micrometres(view.class_limit_um),
                      PartsOutside(view));
  // The parts' dominant order among those the class draws: a kept order 1 is mostly the
  // tester's centring, which no ring class draws.
  const auto largest = std::max_element(view.orders.begin(), view.orders.end(), [](const auto& a, const auto& b) {
    return std::pair(a.class_median_um.has_value(), a.measured_median_um) <
           std::pair(b.class_median_um.has_value(), b.measured_median_um);
  });
  if (largest == view.orders.end()) return line;
  line += fmt::format("; order {} median {} against ", largest->order, Micrometres(largest->measured_median_um));
  line += largest->class_median_um ? fmt::format("the class's {}", Micrometres(*largest->class_median_um))
                                   : std::string("nothing the class draws");
  if (view.class_problem) line += fmt::format(" ({})", *view.class_problem);
  return line;
}

std::string ErrorMotionConditions(const ErrorMotionReading& reading) {
  return fmt::format("ISO 230-7, in the sensor's direction, fundamental removed, {}, over {}",
                     ErrorMotionFilterName(reading.filter),
                     reading.revolutions > 0 ? fmt::format("{} revolutions", reading.revolutions)
                                             : std::string("every revolution of the life"));
}

}  // namespace ringtol::jobs
