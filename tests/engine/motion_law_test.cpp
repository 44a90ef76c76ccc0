#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "engine/motion_law.h"

namespace ringtol {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kPi = std::numbers::pi;
// Angles and times here are O(10) evaluated from a handful of products: a few ulps.
constexpr double kRounding = 1e-12;

TEST(MotionLaw, ArticleLawRestsThenTurnsAtItsRate) {
  const engine::MotionLaw law = engine::ArticleLaw(0.5, 270.0 * kDeg, 3.0);
  EXPECT_EQ(law.Angle(0.25), 0.0);
  EXPECT_EQ(law.Rate(0.25), 0.0);
  EXPECT_EQ(law.Rate(0.5), 270.0 * kDeg);  // right-continuous at the step
  EXPECT_NEAR(law.Angle(1.5), 270.0 * kDeg, kRounding);
  EXPECT_NEAR(law.Angle(10.0), 9.5 * 270.0 * kDeg, kRounding);  // keeps turning after its listed turns
  EXPECT_DOUBLE_EQ(law.RotationStart(), 0.5);
  EXPECT_NEAR(law.Duration(), 0.5 + 3.0 * 360.0 / 270.0, kRounding);
}

// Closed forms of the trapezoid: 45 deg in 1/3 s at 810 deg/s^2, 810 deg in 3 s, 45 deg
// down: 900 deg in total at t = settle + 11/3 s, then at rest.
TEST(MotionLaw, TestBenchTrapezoidMatchesItsClosedForm) {
  const engine::MotionLaw law = engine::TestBenchLaw(0.5);
  const double a = 810.0 * kDeg;
  EXPECT_NEAR(law.Angle(0.5 + 0.2), 0.5 * a * 0.2 * 0.2, kRounding);
  EXPECT_NEAR(law.Rate(0.5 + 0.2), a * 0.2, kRounding);
  EXPECT_EQ(law.Acceleration(0.6), a);
  EXPECT_NEAR(law.Angle(0.5 + 1.0 / 3.0), 45.0 * kDeg, kRounding);
  EXPECT_NEAR(law.Angle(0.5 + 1.0 / 3.0 + 1.5), 45.0 * kDeg + 1.5 * 270.0 * kDeg, kRounding);
  EXPECT_EQ(law.Acceleration(0.5 + 1.0 / 3.0 + 3.1), -a);
  EXPECT_NEAR(law.Angle(0.5 + 11.0 / 3.0), 900.0 * kDeg, kRounding);
  EXPECT_NEAR(law.Rate(0.5 + 11.0 / 3.0), 0.0, kRounding);
  EXPECT_NEAR(law.Angle(20.0), 900.0 * kDeg, kRounding);
  ASSERT_EQ(law.Breakpoints().size(), 4u);
  EXPECT_NEAR(law.Breakpoints()[3], 0.5 + 11.0 / 3.0, kRounding);
}

TEST(MotionLaw, TimeAtAngleInvertsTheAngle) {
  const engine::MotionLaw law = engine::TestBenchLaw(0.5);
  for (const double t : {0.6, 0.8, 0.84, 1.0, 2.5, 3.9, 4.1}) {
    EXPECT_NEAR(law.TimeAtAngle(law.Angle(t)), t, 1e-9) << t;
  }
  // The ring never gets past 900 degrees.
  EXPECT_EQ(law.TimeAtAngle(901.0 * kDeg), std::numeric_limits<double>::infinity());
  // At rest from the start: psi = 0 is reached at once.
  EXPECT_EQ(law.TimeAtAngle(0.0), 0.0);
}

// A reversal: turn at 1 rad/s for 2 s, then decelerate at 1 rad/s^2 for 4 s. The angle
// 2 + t' - t'^2/2 rises to 2.5 at t' = 1 and falls back to 0 at t' = 1 + sqrt(5).
TEST(MotionLaw, ReversalsPassTheSameAngleTwice) {
  const engine::MotionLaw law({{.duration = 2.0, .acceleration = 0.0, .start_rate = 1.0},
                                {.duration = 4.0, .acceleration = -1.0, .start_rate = std::nullopt}});
  EXPECT_NEAR(law.TimeAtAngle(2.25), 2.0 + 1.0 - std::sqrt(0.5), kRounding);
  EXPECT_NEAR(law.TimeAtAngle(2.25, 3.0), 2.0 + 1.0 + std::sqrt(0.5), kRounding);
  EXPECT_NEAR(law.TimeAtAngle(2.5), 3.0, 1e-7);  // a double root: sqrt(eps) conditioning
  EXPECT_NEAR(law.TimeAtAngle(0.0, 1.0), 2.0 + 1.0 + std::sqrt(5.0), kRounding);
  EXPECT_NEAR(law.Rate(6.0), -3.0, kRounding);
  EXPECT_NEAR(law.Angle(7.0), 2.0 + 4.0 - 8.0 - 3.0, kRounding);  // turning back for good
  EXPECT_EQ(law.TimeAtAngle(3.0), std::numeric_limits<double>::infinity());
  EXPECT_EQ(law.RotationStart(), 0.0);
}

TEST(MotionLaw, BadSegmentsAreRejectedByIndex) {
  EXPECT_THROW(engine::MotionLaw({}), std::invalid_argument);
  try {
    engine::MotionLaw({{.duration = 1.0, .acceleration = 0.0, .start_rate = std::nullopt}, {.duration = -1.0, .acceleration = 0.0, .start_rate = std::nullopt}});
    FAIL() << "a negative duration was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("segment 1"), std::string::npos) << e.what();
  }
  EXPECT_THROW(engine::MotionLaw({{.duration = 1.0, .acceleration = std::nan(""), .start_rate = std::nullopt}}), std::invalid_argument);
  EXPECT_THROW(engine::MotionLaw({{.duration = 1.0, .start_rate = std::numeric_limits<double>::infinity()}}),
               std::invalid_argument);
  EXPECT_THROW(engine::MotionLaw({{.duration = 1.0, .start_rate = std::nan("")}}), std::invalid_argument);
}

TEST(MotionLaw, EqualLawsCompareEqual) {
  EXPECT_EQ(engine::TestBenchLaw(0.5), engine::TestBenchLaw(0.5));
  EXPECT_FALSE(engine::TestBenchLaw(0.5) == engine::TestBenchLaw(0.4));
}

TEST(MotionLaw, ALawThatNeverTurnsHasNoRotationStart) {
  const engine::MotionLaw still(std::vector<engine::MotionSegment>{{.duration = 1.0, .acceleration = 0.0, .start_rate = std::nullopt}});
  EXPECT_EQ(still.RotationStart(), std::numeric_limits<double>::infinity());
  EXPECT_EQ(still.TimeAtAngle(0.1), std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace ringtol
