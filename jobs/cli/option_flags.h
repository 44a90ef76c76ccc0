// The command line's side of options that validate themselves (engine/option_range.h): a
// command checks the options its flags set with their IsValid, and names the field it
// reports by its flag.
#pragma once

#include <span>

#include "engine/option_range.h"
#include "jobs/inputs/toml_fields.h"

namespace ringtol::jobs {

// Throws InputError "<flag>: <value>: out of range; allowed: <range>" naming the flag that
// `flags` gives the field IsValid reports, its value and range in the flag's units.
[[noreturn]] void FailOption(const InvalidOption& invalid, std::span<const OptionName> flags);

// Returns when `options` are valid; else FailOption.
template <typename Options>
void RequireValid(const Options& options, std::span<const OptionName> flags) {
  if (InvalidOption invalid; !options.IsValid(&invalid)) FailOption(invalid, flags);
}

}  // namespace ringtol::jobs
