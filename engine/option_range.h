// The values an option accepts, stated once beside the option's field as a Range, and what
// an options struct's IsValid reports about a field outside it (Ceres'
// Solver::Options::IsValid is the model):
//
//   struct PoolOptions {
//     double chunk_seconds = 0.5;  // [s] the adaptive chunks' target wall time
//     static constexpr Range kChunkSecondsRange = Above(0.0);
//     ...
//     bool IsValid(InvalidOption* invalid = nullptr) const;
//   };
//
// IsValid names the field by its member's name; a caller names it in its own terms: an
// input file's reader by its key, with the range in the key's units, the command line by
// its flag (jobs/inputs/toml_fields.h: Describe words a Range, Allowed an InvalidOption's).
// The same Range states a key's allowed values in the readers' field lists, so the docs'
// input reference, the reader and the check are one statement. NaN lies in no range.
#pragma once

#include <limits>
#include <string>
#include <string_view>
#include <type_traits>

namespace ringtol {

// An interval of allowed values; each bound inclusive unless open.
struct Range {
  double lower = -std::numeric_limits<double>::infinity();
  bool lower_open = false;
  double upper = std::numeric_limits<double>::infinity();
  bool upper_open = false;

  constexpr bool Contains(double value) const {
    const bool above = lower_open ? value > lower : value >= lower;
    const bool below = upper_open ? value < upper : value <= upper;
    return above && below;
  }
};
constexpr Range AnyFinite() { return {}; }
constexpr Range AtLeast(double lower) { return {lower, false}; }                 // [lower, inf)
constexpr Range Above(double lower) { return {lower, true}; }                    // (lower, inf)
constexpr Range Between(double lower, double upper) { return {lower, false, upper, false}; }  // [lower, upper]
constexpr Range Inside(double lower, double upper) { return {lower, true, upper, true}; }     // (lower, upper)

// A field of an options struct outside its Range: what IsValid reports.
struct InvalidOption {
  std::string field;      // the member's name as declared: "chunk_seconds", "simulation.steps"
  double value = 0.0;     // what it holds, in its units
  Range range;            // what it accepts, in its units
  bool integer = false;   // an integer field: the integers in `range`
};

// IsValid's step for one field: true when `value` lies in `range`; otherwise false, with
// the field described in *invalid (when not null).
template <typename T>
bool CheckOption(std::string_view field, T value, const Range& range, InvalidOption* invalid) {
  if (range.Contains(static_cast<double>(value))) return true;
  if (invalid != nullptr) *invalid = {std::string(field), static_cast<double>(value), range, std::is_integral_v<T>};
  return false;
}

// IsValid's step for a nested options struct: `options.IsValid`, its field named
// "<field>.<its field>".
template <typename Options>
bool CheckOptions(std::string_view field, const Options& options, InvalidOption* invalid) {
  if (options.IsValid(invalid)) return true;
  if (invalid != nullptr) invalid->field = std::string(field) + "." + invalid->field;
  return false;
}

}  // namespace ringtol
