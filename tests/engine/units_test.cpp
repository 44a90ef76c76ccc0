#include "engine/units.h"

#include <gtest/gtest.h>

#include <limits>
#include <numbers>

namespace ringtol::units {
namespace {

// A length read from a file in millimetres and shown back in a message reads as written:
// InMillimetres divides by the factor the reader multiplied by.
TEST(Units, MillimetresReadFromAFileAreShownAsWritten) {
  for (const double mm : {302.0, 0.14, 5.0, 1e-5, 2.5, 800.0}) {
    EXPECT_EQ(InMillimetres(mm * kMetresPerMillimetre), mm) << mm;
  }
  EXPECT_EQ(ShowMillimetres(0.302), "302");
  EXPECT_EQ(ShowMillimetres(0.14e-3), "0.14");
  EXPECT_EQ(ShowMillimetres(1e-8), "1e-05");
  EXPECT_EQ(ShowMillimetres(std::numeric_limits<double>::infinity()), "inf");
}

TEST(Units, ATurnAMicrometreAndAPercentConvertExactly) {
  EXPECT_EQ(kRadiansPerRevolution, 2.0 * std::numbers::pi);
  EXPECT_EQ(InDegrees(kRadiansPerRevolution), 360.0);
  EXPECT_EQ(InMicrometres(0.25e-6), 0.25);
  EXPECT_EQ(kFractionPerPercent * 50.0, 0.5);
}

}  // namespace
}  // namespace ringtol::units
