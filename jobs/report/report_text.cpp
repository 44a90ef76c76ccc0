#include "jobs/report/report_text.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include <fmt/format.h>

#include "jobs/campaign/sample_record.h"

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

std::string ErrorMotionConditions(const ErrorMotionReading& reading) {
  return fmt::format("ISO 230-7, in the sensor's direction, fundamental removed, {}, over {}",
                     ErrorMotionFilterName(reading.filter),
                     reading.revolutions > 0 ? fmt::format("{} revolutions", reading.revolutions)
                                             : std::string("every revolution of the life"));
}

}  // namespace ringtol::jobs
