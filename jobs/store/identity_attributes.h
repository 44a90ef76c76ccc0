// A results file's identity attributes: the root attributes that say which job wrote it.
// They are written when the file is created, read by every reader, and compared by a
// resume, which refuses a file whose identity differs from the run's. Each store lists
// its own once, as a table of IdentityAttribute, so that the three can never disagree
// about a field (jobs/store/campaign_store.cpp, allocation_store.cpp).
#pragma once

#include <hdf5.h>

#include <fmt/format.h>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>

#include "jobs/store/hdf5_file.h"

namespace ringtol::jobs::hdf5 {

// How a resume compares an identity attribute with the run's.
enum class Comparison {
  kWord,   // as a value: "design differs ('sobol' in the file, 'lhs' now)", "seed differs (7 in the file, 8 now)"
  kText,   // a job file's text, by its first differing line (TextDifference)
  kNever,  // where the job file was: a resume may name it by another path
};

// One identity attribute: its name in the file and the member of `Identity` it holds, a
// text (a variable-length string), an unsigned or signed 64-bit count, or a float64.
template <typename Identity>
struct IdentityAttribute {
  using Member = std::variant<std::string Identity::*, std::uint64_t Identity::*, std::int64_t Identity::*,
                              double Identity::*>;
  const char* name;
  Member member;
  Comparison comparison = Comparison::kWord;
};

template <typename Identity>
void WriteIdentityAttributes(const Where& where, hid_t file, const Identity& identity,
                             std::span<const IdentityAttribute<std::type_identity_t<Identity>>> attributes) {
  for (const IdentityAttribute<Identity>& attribute : attributes) {
    std::visit(
        [&](auto member) {
          using T = std::remove_cvref_t<decltype(identity.*member)>;
          if constexpr (std::is_same_v<T, std::string>) {
            WriteStringAttribute(where, file, attribute.name, identity.*member);
          } else {
            const NumberTypes types = TypesOf<T>();
            WriteAttribute(where, file, attribute.name, types.file, types.native, &(identity.*member));
          }
        },
        attribute.member);
  }
}

// InputError (`where.input`) naming the first attribute that is missing or not of its
// kind, and the `format` ("ringtol campaign") the file is then not a complete one of.
template <typename Identity>
void ReadIdentityAttributes(const Where& where, hid_t file, Identity& identity,
                            std::span<const IdentityAttribute<std::type_identity_t<Identity>>> attributes, std::string_view format) {
  for (const IdentityAttribute<Identity>& attribute : attributes) {
    std::visit(
        [&](auto member) {
          using T = std::remove_cvref_t<decltype(identity.*member)>;
          std::optional<T> value;
          if constexpr (std::is_same_v<T, std::string>) {
            value = ReadStringAttribute(where, file, attribute.name);
          } else {
            value = ReadNumberAttribute<T>(where, file, attribute.name);
          }
          if (!value) {
            Fail(where, fmt::format("is not a complete {} file: attribute {} is missing", format, attribute.name));
          }
          identity.*member = *std::move(value);
        },
        attribute.member);
  }
}

// The first attribute, in the table's order, in which `now` differs from the file.
template <typename Identity>
std::optional<std::string> IdentityAttributeDifference(const Identity& file, const Identity& now,
                                                       std::span<const IdentityAttribute<std::type_identity_t<Identity>>> attributes) {
  for (const IdentityAttribute<Identity>& attribute : attributes) {
    if (attribute.comparison == Comparison::kNever) continue;
    std::optional<std::string> difference = std::visit(
        [&](auto member) -> std::optional<std::string> {
          if constexpr (std::is_same_v<std::remove_cvref_t<decltype(file.*member)>, std::string>) {
            if (attribute.comparison == Comparison::kText) return TextDifference(attribute.name, file.*member, now.*member);
            return WordDifference(attribute.name, file.*member, now.*member);
          } else {
            if (file.*member == now.*member) return std::nullopt;
            return fmt::format("{} differs ({} in the file, {} now)", attribute.name, file.*member, now.*member);
          }
        },
        attribute.member);
    if (difference) return difference;
  }
  return std::nullopt;
}

}  // namespace ringtol::jobs::hdf5
