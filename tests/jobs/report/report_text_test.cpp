// How the summary and the reports write numbers and name error motion
// (jobs/report/report_text.h): to what the numbers mean, and in one place.
#include "jobs/report/report_text.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "jobs/campaign/sample_record.h"

namespace ringtol::jobs {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

// Four significant digits, never finer than a nanometre, never in exponent notation.
TEST(ReportText, LengthsAreMicrometresToFourDigitsAndNoFinerThanANanometre) {
  EXPECT_EQ(Micrometres(13.866), "13.87 µm");
  EXPECT_EQ(Micrometres(184.0), "184 µm");
  EXPECT_EQ(Micrometres(1234.56), "1235 µm");
  EXPECT_EQ(Micrometres(123456.0), "123456 µm");
  EXPECT_EQ(Micrometres(0.0123456), "0.012 µm");
  EXPECT_EQ(Micrometres(0.0015), "0.002 µm");
  EXPECT_EQ(Micrometres(0.0003119), "< 0.001 µm");  // the fundamental: a third of a nanometre
  EXPECT_EQ(Micrometres(4e-6), "< 0.001 µm");       // a replay tolerance of 4 pm
  EXPECT_EQ(Micrometres(0.0), "0 µm");
}

// One sample in n moves a yield by 100/n points: the decimals show it, and no more.
TEST(ReportText, YieldsAreWrittenToTheResolutionOfTheirSampleCount) {
  EXPECT_EQ(YieldPercent(17.0 / 34.0, 34), "50.0 %");
  EXPECT_EQ(YieldPercent(999.0 / 1000.0, 1000), "99.9 %");
  EXPECT_EQ(YieldPercent(2047.0 / 2048.0, 2048), "99.95 %");
  EXPECT_EQ(YieldPercent(999999.0 / 1000000.0, 1000000), "99.9999 %");  // not "100 %"
  analysis::ProportionEstimate yield = analysis::EstimateProportion(2048, 2048);
  EXPECT_EQ(YieldWithInterval(yield), "100.00 % [99.82, 100.00 %]");
}

// A level or a share as people say it: four significant digits, no trailing zeros.
TEST(ReportText, PercentagesAreWrittenToFourSignificantDigits) {
  EXPECT_EQ(Percent(0.25), "25 %");
  EXPECT_EQ(Percent(0.999), "99.9 %");
  EXPECT_EQ(Percent(0.99999), "100 %");
  EXPECT_EQ(Percent(0.001234), "0.1234 %");
}

TEST(ReportText, DecimalsNeverWriteANegativeZero) {
  EXPECT_EQ(Decimals(-0.0004, 3), "0.000");
  EXPECT_EQ(Decimals(-0.0006, 3), "-0.001");
  EXPECT_EQ(Decimals(0.8271, 3), "0.827");
  EXPECT_EQ(CapabilityIndex(1.3342), "1.33");
  EXPECT_EQ(CapabilityIndex(0.005922), "0.01");
}

// Every error motion value is a column a campaign stores, and is read back from it; the
// conditions name the standard, the direction, the fundamental, the filter and the
// revolutions.
TEST(ReportText, ErrorMotionValuesAreTheStoredColumnsAndSayHowTheyWereRead) {
  for (const ErrorMotionValue value : kErrorMotionValues) {
    const char* column = ErrorMotionColumn(value);
    EXPECT_NE(std::find_if(kOutputNames.begin(), kOutputNames.end(),
                           [&](const char* name) { return std::string(name) == column; }),
              kOutputNames.end())
        << column;
    EXPECT_EQ(ErrorMotionOf(column), value);
    EXPECT_THAT(ErrorMotionName(value), HasSubstr(std::string(ErrorMotionWord(value)) + " error motion"));
  }
  EXPECT_FALSE(ErrorMotionOf("runout_mm").has_value());
  const std::string life = ErrorMotionConditions({.filter = {50.0}});
  for (const char* said : {"ISO 230-7", "sensor", "fundamental removed", "Gaussian filter at 50 UPR (ISO 16610-21)",
                           "every revolution"}) {
    EXPECT_THAT(life, HasSubstr(said)) << said;
  }
  EXPECT_THAT(ErrorMotionConditions({.filter = {0.0}, .revolutions = 16}),
              AllOf(HasSubstr("unfiltered"), HasSubstr("over 16 revolutions")));
}

}  // namespace
}  // namespace ringtol::jobs
