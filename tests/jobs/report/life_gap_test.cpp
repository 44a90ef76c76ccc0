// How much of the life's value one revolution misses (jobs/report/campaign_summary.h), from
// paired values whose answer is known, and where the summary and the report's answer say it.
#include "jobs/report/campaign_summary.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "jobs/report/campaign_report.h"
#include "jobs/report/report_html.h"

namespace ringtol::jobs {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// 100 samples of 1 .. 100 um whose life values lie 5 % above, in shuffled order, and one
// pair with a NaN (a sample without a life value) that is left out.
struct Pairs {
  std::vector<double> one, life;
};
Pairs FivePercentAbove() {
  Pairs pairs;
  for (int i = 0; i < 100; ++i) {
    const double value = 1e-3 * static_cast<double>((37 * i) % 100 + 1);
    pairs.one.push_back(value);
    pairs.life.push_back(1.05 * value);
  }
  pairs.one.push_back(0.5);
  pairs.life.push_back(kNaN);
  return pairs;
}

TEST(LifeGap, QuantilesAndTheMedianExcessOfValuesFivePercentAbove) {
  const Pairs pairs = FivePercentAbove();
  const std::optional<LifeGap> gap = CompareLife("D_trajectory", pairs.one, pairs.life);
  ASSERT_TRUE(gap.has_value());
  EXPECT_EQ(gap->count, 100);
  // Every life value is its own one-revolution value times 1.05, so are the order
  // statistics the quantiles are read from: equal up to one rounding.
  EXPECT_NEAR(gap->life_q50, 1.05 * gap->one_q50, 1e-15);
  EXPECT_NEAR(gap->life_q99, 1.05 * gap->one_q99, 1e-15);
  EXPECT_NEAR(gap->one_q50, 0.050, 0.0015);  // the middle of 1 .. 100 um
  EXPECT_NEAR(gap->one_q99, 0.099, 0.0015);
  EXPECT_NEAR(gap->median_excess, 0.05, 1e-12);

  const std::string sentence = LifeGapSentence(*gap);
  EXPECT_THAT(sentence, HasSubstr("Over the stage's life, D_trajectory q99 is "));
  EXPECT_THAT(sentence, HasSubstr(" mm over one revolution (+5.0 %) and q50 "));
  EXPECT_THAT(sentence, HasSubstr("the median sample's life value lies 5.0 % above its own one-revolution value."));
}

TEST(LifeGap, NoneWithoutAFinitePair) {
  const std::vector<double> one = {0.1, 0.2}, life = {kNaN, kNaN};
  EXPECT_FALSE(CompareLife("runout", one, life).has_value());
}

TEST(LifeGap, OnlyPairsWhoseTwoColumnsAreThere) {
  const Pairs pairs = FivePercentAbove();
  std::map<std::string, std::vector<double>, std::less<>> values = {{"d_trajectory_mm", pairs.one},
                                                                    {"life_d_trajectory_mm", pairs.life},
                                                                    {"runout_mm", pairs.one}};
  const std::vector<LifeGap> gaps = LifeGaps(values);
  ASSERT_EQ(gaps.size(), 1u);  // runout has no life column here
  EXPECT_EQ(gaps[0].label, "D_trajectory");
  EXPECT_TRUE(IsLifeColumn("life_runout_mm"));
  EXPECT_FALSE(IsLifeColumn("swing_mm"));
}

TEST(LifeGap, TheTerminalSummaryStatesItOnlyWhereTheColumnsAre) {
  CampaignSummary summary;
  std::ostringstream without;
  PrintSummary(without, summary);
  EXPECT_THAT(without.str(), Not(HasSubstr("Over the stage's life")));
  EXPECT_FALSE(SummaryJson(summary).contains("life"));

  const Pairs pairs = FivePercentAbove();
  summary.life_gaps.push_back(*CompareLife("runout", pairs.one, pairs.life));
  std::ostringstream with;
  PrintSummary(with, summary);
  EXPECT_THAT(with.str(), HasSubstr("life              Over the stage's life, runout q99 is "));
  EXPECT_EQ(SummaryJson(summary)["life"]["runout"]["count"], 100);
}

TEST(LifeGap, TheReportsAnswerStatesItOnlyWhereTheColumnsAre) {
  CampaignReport report;
  EXPECT_THAT(ReportHtml(report), Not(HasSubstr("Over the stage")));
  EXPECT_FALSE(ReportJson(report).contains("life"));
  const Pairs pairs = FivePercentAbove();
  report.life_gaps.push_back(*CompareLife("D_trajectory", pairs.one, pairs.life));
  const std::string page = ReportHtml(report);
  const std::size_t answer = page.find("id=\"answer\"");
  const std::size_t sentence = page.find("Over the stage&apos;s life, D_trajectory");
  ASSERT_NE(sentence, std::string::npos);
  EXPECT_GT(sentence, answer);  // in the answer's block, before it closes
  EXPECT_LT(sentence, page.find("</div>", answer));
  EXPECT_EQ(ReportJson(report)["life"]["D_trajectory"]["count"], 100);
}

// What a campaign without the life says in place of its numbers names the outputs it
// left out: every life output of the outputs table, each by its name.
TEST(LifeNotComputed, NamesEveryLifeOutputOfTheTable) {
  const std::string text = LifeNotComputed();
  for (std::size_t k = 0; k < kOutputCount; ++k) {
    if (IsLifeOutput(k)) {
      EXPECT_THAT(text, HasSubstr(kOutputNames[k]));
    }
  }
  EXPECT_THAT(text, HasSubstr("[outputs] life = false"));
}

}  // namespace
}  // namespace ringtol::jobs
