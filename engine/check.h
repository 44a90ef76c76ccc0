// Invariant checks that stay on in every build (Drake's DRAKE_THROW_UNLESS is the model):
//
//   RINGTOL_CHECK(column < specs_.size(), column, specs_.size());
//
// throws std::logic_error when the condition is false, with the condition's text, the
// function, file and line, and each value after it as "name = value"
// ("column = 7, specs_.size() = 5"), so that the message says what was wrong and not
// only where. A failed check is ringtol's bug or a caller's misuse of an API, never a
// user's input (that is an InputError at the file's or command line's boundary,
// jobs/inputs/input_error.h) nor a numerical outcome (a solvers::Status): docs/architecture.md,
// "Failure". The values are formatted only when the check fails.
//
// Values print with operator<<, enums as their number, strings quoted, floating-point
// numbers as the shortest text that reads back as the same number; a type without
// operator<< prints as "?". The names are the values' own text, split at the commas
// between them (outside brackets and quotes).
#pragma once

#include <charconv>
#include <concepts>
#include <sstream>
#include <string>
#include <string_view>
#include <type_traits>

namespace ringtol::internal {

// Appends `value` as RINGTOL_CHECK shows it.
template <typename T>
void ShowCheckedValue(std::ostringstream& out, const T& value) {
  if constexpr (std::is_same_v<T, bool>) {
    out << (value ? "true" : "false");
  } else if constexpr (std::is_enum_v<T>) {
    out << static_cast<long long>(static_cast<std::underlying_type_t<T>>(value));
  } else if constexpr (std::is_floating_point_v<T>) {
    char text[32];
    const auto end = std::to_chars(text, text + sizeof text, value).ptr;
    out << std::string_view(text, static_cast<std::size_t>(end - text));
  } else if constexpr (std::is_convertible_v<const T&, std::string_view>) {
    out << '"' << std::string_view(value) << '"';
  } else if constexpr (requires { out << value; }) {
    out << value;
  } else {
    out << '?';
  }
}

// The text of RINGTOL_CHECK's values, "a, b.size()", cut into the name of each.
std::string_view NextCheckedName(std::string_view& names);

[[noreturn]] void ThrowCheckFailure(const char* condition, const char* function, const char* file, int line,
                                    const std::string& values);

// Throws std::logic_error for a failed RINGTOL_CHECK.
template <typename... Values>
[[noreturn]] void FailCheck(const char* condition, const char* function, const char* file, int line,
                            std::string_view names, const Values&... values) {
  std::ostringstream shown;
  if constexpr (sizeof...(Values) > 0) {
    const char* separator = "";
    ((shown << separator << NextCheckedName(names) << " = ", ShowCheckedValue(shown, values), separator = ", "), ...);
  }
  ThrowCheckFailure(condition, function, file, line, shown.str());
}

}  // namespace ringtol::internal

// Throws std::logic_error unless `condition` holds (see above); the values after it are
// evaluated only when it does not.
#define RINGTOL_CHECK(condition, ...)                                                                   \
  do {                                                                                                  \
    if (!(condition)) {                                                                                 \
      ::ringtol::internal::FailCheck(#condition, __func__, __FILE__, __LINE__, #__VA_ARGS__ __VA_OPT__(, ) \
                                         __VA_ARGS__);                                                  \
    }                                                                                                   \
  } while (false)
