// Sizes of a validation run that its command line may raise: a test states its CI size and
// the variable that runs it longer (see the test's header for the command).
#pragma once

#include <cstdint>
#include <cstdlib>
#include <string>

namespace ringtol::testing {

// Under AddressSanitizer every solve is ~20 times slower: validations run fewer draws.
#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif

// The integer in environment variable `name`, or `fallback` when it is not set.
inline std::int64_t LongerRun(const char* name, std::int64_t fallback) {
  const char* value = std::getenv(name);
  return value != nullptr ? std::stoll(value) : fallback;
}

}  // namespace ringtol::testing
