// ISO 230-7 error motion values against signals whose values are known exactly.
#include "engine/error_motion.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace ringtol::engine {
namespace {

constexpr int kSteps = 360;
constexpr double kTight = 1e-15;  // [m] round-off of micrometre signals

double Psi(int j) { return 2.0 * std::numbers::pi * j / kSteps; }

// An eccentric artefact alone: a pure once-per-revolution sinusoid is centring, not error
// motion, so every value is zero and the fundamental is its amplitude.
TEST(ErrorMotion, APureFundamentalIsCentringNotErrorMotion) {
  std::vector<double> motion;
  for (int j = 0; j < kSteps; ++j) motion.push_back(5e-6 + 3e-6 * std::cos(Psi(j) - 0.4));
  const ErrorMotion e = MeasureErrorMotion(motion, kSteps);
  EXPECT_NEAR(e.fundamental, 3e-6, kTight);
  EXPECT_NEAR(e.total, 0.0, 1e-14);
  EXPECT_NEAR(e.synchronous, 0.0, 1e-14);
  EXPECT_EQ(e.asynchronous, 0.0);
}

// A third harmonic repeats every revolution: synchronous, its max - min twice the
// amplitude; the fundamental riding on it is removed.
TEST(ErrorMotion, ARepeatingHarmonicIsSynchronous) {
  std::vector<double> motion;
  for (int k = 0; k < 4; ++k) {
    for (int j = 0; j < kSteps; ++j) motion.push_back(2e-6 * std::sin(3.0 * Psi(j)) + 7e-6 * std::sin(Psi(j)));
  }
  const ErrorMotion e = MeasureErrorMotion(motion, kSteps);
  EXPECT_NEAR(e.synchronous, 4e-6, 1e-13);
  EXPECT_NEAR(e.total, 4e-6, 1e-13);
  EXPECT_NEAR(e.asynchronous, 0.0, 1e-20);
  EXPECT_NEAR(e.fundamental, 7e-6, 1e-13);
}

// A term at a non-integer rate (a roller's lobe) shifts phase every revolution: over
// revolutions at phases 0 and pi it spans a band of twice its amplitude at every angle
// where it is at its peak, and averages away.
TEST(ErrorMotion, ATermThatDriftsIsAsynchronous) {
  std::vector<double> motion;
  const double amplitude = 1e-6;
  for (int k = 0; k < 2; ++k) {
    for (int j = 0; j < kSteps; ++j) {
      motion.push_back(amplitude * std::cos(12.0 * Psi(j) + std::numbers::pi * k) + 2e-6 * std::cos(2.0 * Psi(j)));
    }
  }
  const ErrorMotion e = MeasureErrorMotion(motion, kSteps);
  EXPECT_NEAR(e.asynchronous, 2.0 * amplitude, 1e-13);
  EXPECT_NEAR(e.synchronous, 4e-6, 1e-13);  // the order-2 term alone
  // The band rides on the synchronous part: total is at most their sum.
  EXPECT_LE(e.total, e.synchronous + e.asynchronous + 1e-13);
  EXPECT_GE(e.total, std::max(e.synchronous, e.asynchronous) - 1e-13);
}

// One revolution's total equals its synchronous value, and a revolution repeated changes
// nothing: the values are properties of the motion, not of how many times it was read.
TEST(ErrorMotion, RepeatingARevolutionChangesNothing) {
  std::vector<double> once;
  for (int j = 0; j < kSteps; ++j) once.push_back(1e-6 * std::cos(5.0 * Psi(j) + 0.3) + 0.5e-6 * std::sin(9.0 * Psi(j)));
  std::vector<double> thrice;
  for (int k = 0; k < 3; ++k) thrice.insert(thrice.end(), once.begin(), once.end());
  const ErrorMotion a = MeasureErrorMotion(once, kSteps);
  const ErrorMotion b = MeasureErrorMotion(thrice, kSteps);
  EXPECT_NEAR(a.total, a.synchronous, kTight);
  EXPECT_NEAR(b.total, a.total, kTight);
  EXPECT_NEAR(b.synchronous, a.synchronous, kTight);
  EXPECT_EQ(a.asynchronous, 0.0);
  EXPECT_NEAR(b.asynchronous, 0.0, kTight);
}

TEST(ErrorMotion, RefusesPartialRevolutions) {
  const std::vector<double> motion(kSteps + 1, 0.0);
  EXPECT_THROW(MeasureErrorMotion(motion, kSteps), std::invalid_argument);
  EXPECT_THROW(MeasureErrorMotion(std::vector<double>{}, kSteps), std::invalid_argument);
  EXPECT_THROW(MeasureErrorMotion(std::vector<double>(2, 0.0), 2), std::invalid_argument);
}

// A term that drifts through the revolutions at a fractional rate, as a roller's lobe does,
// comes out of the filter scaled by ISO 16610-21's transmission at that rate, in every
// revolution read: the record's own ends, beyond the margins, do not reach them.
TEST(FilterErrorMotion, PassesADriftingTermByTheGaussianTransmissionAtItsRate) {
  constexpr double kAmplitude = 1e-6;  // [m]
  constexpr double kRate = 7.3;        // undulations per revolution
  constexpr int kRead = 8;
  const ErrorMotionFilter filter{5.0};
  const int margin = filter.MarginRevolutions();
  ASSERT_GE(margin, 1);
  std::vector<double> motion;
  for (int k = -margin; k < kRead + margin; ++k) {
    for (int j = 0; j < kSteps; ++j) motion.push_back(kAmplitude * std::cos(kRate * (2.0 * std::numbers::pi * k + Psi(j))));
  }
  const std::vector<double> filtered = FilterErrorMotion(motion, kSteps, filter);
  ASSERT_EQ(filtered.size(), static_cast<std::size_t>(kRead * kSteps));
  // exp(-pi (alpha 7.3 / 5)^2), alpha^2 = ln 2 / pi: exp(-ln 2 (7.3 / 5)^2).
  const double transmission = std::exp(-std::numbers::ln2 * (kRate / 5.0) * (kRate / 5.0));
  EXPECT_NEAR(filter.Transmission(kRate), transmission, 1e-15);
  double worst = 0.0;
  for (int k = 0; k < kRead; ++k) {
    for (int j = 0; j < kSteps; ++j) {
      const double expected = transmission * kAmplitude * std::cos(kRate * (2.0 * std::numbers::pi * k + Psi(j)));
      worst = std::max(worst, std::abs(filtered[static_cast<std::size_t>(k * kSteps + j)] - expected));
    }
  }
  EXPECT_LT(worst, 1e-12 * kAmplitude);
}

TEST(FilterErrorMotion, UnfilteredIsTheMotionAsItIs) {
  const ErrorMotionFilter unfiltered{0.0};
  EXPECT_EQ(unfiltered.MarginRevolutions(), 0);
  EXPECT_EQ(unfiltered.Transmission(1000.0), 1.0);
  std::vector<double> motion(2 * kSteps);
  for (int j = 0; j < 2 * kSteps; ++j) motion[static_cast<std::size_t>(j)] = 1e-6 * std::sin(13.7 * Psi(j));
  EXPECT_EQ(FilterErrorMotion(motion, kSteps, unfiltered), motion);
}

TEST(FilterErrorMotion, RefusesARecordWithNoRevolutionBesideItsMargins) {
  const ErrorMotionFilter filter{50.0};
  const auto margins = static_cast<std::size_t>(2 * filter.MarginRevolutions());
  EXPECT_THROW(FilterErrorMotion(std::vector<double>(margins * kSteps, 0.0), kSteps, filter), std::invalid_argument);
  EXPECT_NO_THROW(FilterErrorMotion(std::vector<double>((margins + 1) * kSteps, 0.0), kSteps, filter));
}

}  // namespace
}  // namespace ringtol::engine
