// Options that validate themselves (engine/option_range.h), as their tests check them:
// defaults valid, and each field set outside its range refused under its own name.
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include "engine/option_range.h"

namespace ringtol::testing {

// One field set outside its range, and the name IsValid must give it.
template <typename Options>
struct Spoiled {
  std::string field;
  std::function<void(Options&)> spoil;
};

template <typename Options>
void ExpectEachRefusedByName(const std::vector<Spoiled<Options>>& cases) {
  EXPECT_TRUE(Options{}.IsValid());
  for (const Spoiled<Options>& c : cases) {
    Options options;
    c.spoil(options);
    InvalidOption invalid;
    EXPECT_FALSE(options.IsValid()) << c.field;
    EXPECT_FALSE(options.IsValid(&invalid)) << c.field;
    EXPECT_EQ(invalid.field, c.field);
    EXPECT_FALSE(invalid.range.Contains(invalid.value)) << c.field << " = " << invalid.value;
  }
}

}  // namespace ringtol::testing
