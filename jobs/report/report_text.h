// How the summary and the reports write what a designer reads: numbers to what they mean,
// and the name and the reading of an error motion value. One place for each, so that the
// terminal, the pages and their JSON cannot say it differently.
//
// Error motion (docs/model.md §9) is named by ErrorMotionName and read as
// ErrorMotionConditions says; every error-motion number the summary or a report shows
// carries them, so that what the reading is (its filter and its revolutions) is stated in
// one function.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "analysis/order_statistics.h"
#include "engine/error_motion.h"

namespace ringtol::jobs {

// A length [µm] to what a campaign's numbers mean, with its unit: four significant digits,
// never finer than 1 nm (a replay agrees to picometres, the sampling budget is a micrometre,
// a roundness tester resolves some nanometres), never in exponent notation: "13.87 µm",
// "0.012 µm"; "< 0.001 µm" for a nonzero value of magnitude below 0.0005 µm, "0 µm" for
// zero.
std::string Micrometres(double value_um);

// `value` to `decimals` places (>= 0), with no negative zero: -0.0004 to 3 places is
// "0.000", a sign that would say nothing.
std::string Decimals(double value, int decimals);
// A capability index (Cp, Cpk) to two decimals, as quality engineers quote them: at the
// sample counts of a campaign its interval is some hundredths wide. "1.33".
std::string CapabilityIndex(double value);

// A fraction as a percentage to four significant digits: 0.25 -> "25 %", 0.999 -> "99.9 %".
std::string Percent(double fraction);
// A fraction of `trials` as a percentage to the resolution its count gives (1 / trials):
// one decimal up to 1,000 trials, two up to 10,000, and so on: "99.95 %" of 2,048.
std::string YieldPercent(double fraction, std::int64_t trials);
// "99.95 % [99.73, 99.99 %]": the estimate and its interval, to the same resolution.
std::string YieldWithInterval(const analysis::ProportionEstimate& yield);

// The terminal summaries' value column: their labels are padded to it ("samples           "),
// and a line that continues a label's list starts with this.
inline constexpr const char* kSummaryIndent = "                  ";

// One line for a measured population (jobs/report/population_view.h): its parts and how
// they are drawn, the class compared with and how many parts lie within it (those outside
// named), and the order whose measured median is largest (of those the class draws, if any)
// against the class's median there:
// "ring population: 20 measured parts, resampled; against precise, the tightest class every
// part meets at 604 mm: 20 of 20 within RONt 100 µm; order 3 median 15.78 µm against the
// class's 6.53 µm".
struct PopulationView;
std::string PopulationLine(const PopulationView& view);

// ISO 230-7's three values of a radial error motion (numbered in kErrorMotionValues order).
enum class ErrorMotionValue { kTotal, kSynchronous, kAsynchronous };
inline constexpr ErrorMotionValue kErrorMotionValues[] = {ErrorMotionValue::kTotal, ErrorMotionValue::kSynchronous,
                                                          ErrorMotionValue::kAsynchronous};

// Which value an output column holds: error_motion_total_mm is kTotal; none for the others.
std::optional<ErrorMotionValue> ErrorMotionOf(std::string_view output);
// The column of a value: "error_motion_asynchronous_mm".
const char* ErrorMotionColumn(ErrorMotionValue value);
// "total", "synchronous", "asynchronous".
std::string_view ErrorMotionWord(ErrorMotionValue value);
// "asynchronous error motion".
std::string ErrorMotionName(ErrorMotionValue value);

// How an error motion was read.
struct ErrorMotionReading {
  engine::ErrorMotionFilter filter;  // the base scene's
  // 0: over every revolution of the stage's life (a results file's columns); otherwise
  // over this many successive revolutions (the report's replay for the polar plot).
  int revolutions = 0;
};
// "ISO 230-7, in the sensor's direction, fundamental removed, Gaussian filter at 50 UPR
// (ISO 16610-21), over every revolution of the life".
std::string ErrorMotionConditions(const ErrorMotionReading& reading);
// "Gaussian filter at 50 UPR (ISO 16610-21)" or "unfiltered".
std::string ErrorMotionFilterName(const engine::ErrorMotionFilter& filter);

}  // namespace ringtol::jobs
