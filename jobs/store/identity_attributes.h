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

// Whether every file has the attribute.
enum class Presence {
  kAlways,
  // Files written before it lack it: their identity keeps the field's default. An empty
  // text is not written, so that a file of a job without it looks like those files.
  kSince,
};

// A field kept as one of a few words (a choice, an enumeration). `word` names the
// identity's value as the file keeps it, `shown` as the job file writes it (the resume's
// message), `set` gives the identity the value a word names (false: no value has it) and
// `words` lists them for the message that refuses another.
template <typename Identity>
struct WordMember {
  std::string (*word)(const Identity&);
  std::string (*shown)(const Identity&);
  bool (*set)(Identity&, std::string_view);
  std::string (*words)();
};

// One identity attribute: its name in the file and the member of `Identity` it holds, a
// text (a variable-length string), an unsigned or signed 64-bit count, a float64 or a
// word. `key` is the job file's key a resume's message names, where it is not `name`.
template <typename Identity>
struct IdentityAttribute {
  using Member = std::variant<std::string Identity::*, std::uint64_t Identity::*, std::int64_t Identity::*,
                              double Identity::*, WordMember<Identity>>;
  const char* name;
  Member member;
  Comparison comparison = Comparison::kWord;
  Presence presence = Presence::kAlways;
  const char* key = nullptr;
};

template <typename Identity>
void WriteIdentityAttributes(const Where& where, hid_t file, const Identity& identity,
                             std::span<const IdentityAttribute<std::type_identity_t<Identity>>> attributes) {
  for (const IdentityAttribute<Identity>& attribute : attributes) {
    std::visit(
        [&](const auto& member) {
          using M = std::remove_cvref_t<decltype(member)>;
          if constexpr (std::is_same_v<M, WordMember<Identity>>) {
            WriteStringAttribute(where, file, attribute.name, member.word(identity));
          } else if constexpr (std::is_same_v<M, std::string Identity::*>) {
            if (attribute.presence == Presence::kSince && (identity.*member).empty()) return;
            WriteStringAttribute(where, file, attribute.name, identity.*member);
          } else {
            const NumberTypes types = TypesOf<std::remove_cvref_t<decltype(identity.*member)>>();
            WriteAttribute(where, file, attribute.name, types.file, types.native, &(identity.*member));
          }
        },
        attribute.member);
  }
}

// InputError (`where.input`) naming the first attribute that is missing (unless
// Presence::kSince) or not of its kind, and the `format` ("ringtol campaign") the file is
// then not a complete one of.
template <typename Identity>
void ReadIdentityAttributes(const Where& where, hid_t file, Identity& identity,
                            std::span<const IdentityAttribute<std::type_identity_t<Identity>>> attributes,
                            std::string_view format) {
  for (const IdentityAttribute<Identity>& attribute : attributes) {
    std::visit(
        [&](const auto& member) {
          using M = std::remove_cvref_t<decltype(member)>;
          const auto missing = [&] {
            if (attribute.presence == Presence::kAlways) {
              Fail(where, fmt::format("is not a complete {} file: attribute {} is missing", format, attribute.name));
            }
          };
          if constexpr (std::is_same_v<M, WordMember<Identity>>) {
            const std::optional<std::string> word = ReadStringAttribute(where, file, attribute.name);
            if (!word) return missing();
            if (!member.set(identity, *word)) {
              Fail(where, fmt::format("attribute {} = \"{}\" is not one of {}", attribute.name, *word, member.words()));
            }
          } else {
            using T = std::remove_cvref_t<decltype(identity.*member)>;
            std::optional<T> value;
            if constexpr (std::is_same_v<T, std::string>) {
              value = ReadStringAttribute(where, file, attribute.name);
            } else {
              value = ReadNumberAttribute<T>(where, file, attribute.name);
            }
            if (!value) return missing();
            identity.*member = *std::move(value);
          }
        },
        attribute.member);
  }
}

// The first attribute, in the table's order, in which `now` differs from the file.
template <typename Identity>
std::optional<std::string> IdentityAttributeDifference(
    const Identity& file, const Identity& now,
    std::span<const IdentityAttribute<std::type_identity_t<Identity>>> attributes) {
  for (const IdentityAttribute<Identity>& attribute : attributes) {
    if (attribute.comparison == Comparison::kNever) continue;
    const std::string_view field = attribute.key != nullptr ? attribute.key : attribute.name;
    std::optional<std::string> difference = std::visit(
        [&](const auto& member) -> std::optional<std::string> {
          using M = std::remove_cvref_t<decltype(member)>;
          if constexpr (std::is_same_v<M, WordMember<Identity>>) {
            if (member.word(file) == member.word(now)) return std::nullopt;
            return WordDifference(field, member.shown(file), member.shown(now));
          } else if constexpr (std::is_same_v<M, std::string Identity::*>) {
            if (attribute.comparison == Comparison::kText) return TextDifference(field, file.*member, now.*member);
            return WordDifference(field, file.*member, now.*member);
          } else {
            if (file.*member == now.*member) return std::nullopt;
            return fmt::format("{} differs ({} in the file, {} now)", field, file.*member, now.*member);
          }
        },
        attribute.member);
    if (difference) return difference;
  }
  return std::nullopt;
}

}  // namespace ringtol::jobs::hdf5
