#include "engine/check.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace ringtol {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;

enum class Colour { kRed = 3 };

// The line of the check below, for the message's "file:line".
constexpr int kCheckLine = __LINE__ + 3;
void CheckColumn(std::size_t column, const std::vector<double>& columns) {
  const std::string name = "status";
  RINGTOL_CHECK(column < columns.size(), column, columns.size(), name, Colour::kRed, 0.1, std::max(1, 2));
}

std::string MessageOf(std::size_t column, const std::vector<double>& columns) {
  try {
    CheckColumn(column, columns);
  } catch (const std::logic_error& e) {
    return e.what();
  }
  return "";
}

TEST(RingtolCheck, PassesSilentlyWhenTheConditionHolds) {
  EXPECT_NO_THROW(CheckColumn(1, {1.0, 2.0}));
}

TEST(RingtolCheck, ThrowsALogicErrorWithTheConditionWhereItFailedAndEveryValue) {
  EXPECT_THROW(CheckColumn(7, {1.0, 2.0}), std::logic_error);
  EXPECT_THAT(MessageOf(7, {1.0, 2.0}),
              AllOf(HasSubstr("check_test.cpp:" + std::to_string(kCheckLine) + ": "), HasSubstr("CheckColumn"),
                    HasSubstr("column < columns.size()"),
                    HasSubstr("column = 7, columns.size() = 2, name = \"status\", Colour::kRed = 3, 0.1 = 0.1, "
                              "std::max(1, 2) = 2")));
}

TEST(RingtolCheck, WithoutValuesStatesTheConditionAlone) {
  const auto check = [](bool ready) { RINGTOL_CHECK(ready); };
  try {
    check(false);
    FAIL() << "no exception";
  } catch (const std::logic_error& e) {
    EXPECT_THAT(e.what(), AllOf(HasSubstr("check failed: ready"), Not(HasSubstr(" = "))));
  }
}

TEST(RingtolCheck, EvaluatesItsValuesOnlyWhenItFails) {
  int evaluated = 0;
  const auto count = [&evaluated] { return ++evaluated; };
  RINGTOL_CHECK(evaluated == 0, count());
  EXPECT_EQ(evaluated, 0);
}

}  // namespace
}  // namespace ringtol
