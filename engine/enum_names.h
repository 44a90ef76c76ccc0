// An enum's stable names, listed once in a table from which both directions are derived:
// the name a file or a message shows, and the value a file's text reads as. Every enum
// that appears in input or output files has such a table beside its declaration, so that
// what is written and what reads back cannot drift apart.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace ringtol {

template <typename Enum>
struct NamedValue {
  Enum value;
  std::string_view name;
};

template <typename Enum, std::size_t N>
using NameTable = std::array<NamedValue<Enum>, N>;

// The name of `value`; "?" for a value the table does not list (a broken invariant
// elsewhere, never a file's fault).
template <typename Enum, std::size_t N>
constexpr std::string_view NameOf(const NameTable<Enum, N>& table, Enum value) {
  for (const NamedValue<Enum>& entry : table) {
    if (entry.value == value) return entry.name;
  }
  return "?";
}

// The value named `name`; empty when none is.
template <typename Enum, std::size_t N>
constexpr std::optional<Enum> ValueNamed(const NameTable<Enum, N>& table, std::string_view name) {
  for (const NamedValue<Enum>& entry : table) {
    if (entry.name == name) return entry.value;
  }
  return std::nullopt;
}

// The allowed values, for messages: `"a", "b", "c"` (or `a, b, c` with quote = "").
template <typename Enum, std::size_t N>
std::string NameList(const NameTable<Enum, N>& table, std::string_view quote = "\"") {
  std::string list;
  for (const NamedValue<Enum>& entry : table) {
    if (!list.empty()) list += ", ";
    list.append(quote).append(entry.name).append(quote);
  }
  return list;
}

}  // namespace ringtol
