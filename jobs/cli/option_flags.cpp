#include "jobs/cli/option_flags.h"

#include <fmt/format.h>

#include "jobs/inputs/input_error.h"

namespace ringtol::jobs {

void FailOption(const InvalidOption& invalid, std::span<const OptionName> flags) {
  const OptionName& flag = NameOfOption(flags, invalid);
  // A flag in the field's own units shows the value as it was typed; another, as derived.
  const double value = invalid.value / flag.to_si;
  throw InputError(fmt::format("{}: {}: out of range; allowed: {}", flag.name,
                               flag.to_si == kSameUnit ? ShowNumber(value) : ShowDerived(value),
                               Allowed(invalid, flag.to_si)));
}

}  // namespace ringtol::jobs
