#include "jobs/cli/nearest_name.h"

#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace ringtol::jobs {
namespace {

TEST(EditDistance, CountsInsertionsDeletionsSubstitutionsAndSwaps) {
  EXPECT_EQ(EditDistance("campaign", "campaign"), 0u);
  EXPECT_EQ(EditDistance("campagin", "campaign"), 1u);  // g and i swapped
  EXPECT_EQ(EditDistance("simulte", "simulate"), 1u);
  EXPECT_EQ(EditDistance("kitten", "sitting"), 3u);
  EXPECT_EQ(EditDistance("", "fit"), 3u);
  EXPECT_EQ(EditDistance("fit", ""), 3u);
  // Optimal string alignment edits no substring twice: "ca" -> "ac" -> "abc" is not 2.
  EXPECT_EQ(EditDistance("ca", "abc"), 3u);
  EXPECT_EQ(EditDistance("abc", "ca"), EditDistance("ca", "abc"));
}

TEST(NearestName, SuggestsOnlyANameATypoAway) {
  const std::vector<std::string> commands = {"simulate", "sweep", "sample", "fit", "campaign", "report"};
  EXPECT_EQ(NearestName("campagin", commands), std::optional<std::string>("campaign"));
  EXPECT_EQ(NearestName("reprot", commands), std::optional<std::string>("report"));
  EXPECT_EQ(NearestName("fti", commands), std::optional<std::string>("fit"));
  EXPECT_EQ(NearestName("xyz", commands), std::nullopt);
  EXPECT_EQ(NearestName("s", commands), std::nullopt);  // one letter is no word to correct
  EXPECT_EQ(NearestName("bench", commands), std::nullopt);
}

}  // namespace
}  // namespace ringtol::jobs
