// The name a mistyped word most likely meant, for "did you mean" in messages about an
// unknown command.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace ringtol::jobs {

// The optimal string alignment distance between a and b: the fewest insertions, deletions,
// substitutions and swaps of two neighbouring characters (bytes) that turn a into b, no
// substring edited twice ("campagin" is 1 from "campaign").
std::size_t EditDistance(std::string_view a, std::string_view b);

// The name of `names` nearest to `word`, when it is near enough to be a typo: at most 2
// edits, and fewer than half the word's length (so "x" suggests nothing); the first of
// equally near names. Empty when none is.
std::optional<std::string> NearestName(std::string_view word, std::span<const std::string> names);

}  // namespace ringtol::jobs
