// FitFourierSeries against profiles built here from the definition
//   value(theta) = mean + sum_n C_n cos(n theta + phi_n):
// noise-free samples must give the coefficients back to round-off, noisy ones within
// their standard errors, and bad sample sets must be refused with messages that say why.
#include "sampling/profile_fit.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace ringtol::sampling {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr double kEps = std::numeric_limits<double>::epsilon();

// A ring of 100 mm radius with micrometre form errors, as a roundness tester sees it.
constexpr double kRadius = 0.1;  // [m]
const std::vector<engine::Harmonic> kFormError = {
    {1, 5e-6, 1.0}, {2, 8e-6, 0.3}, {3, 3e-6, -1.2}, {5, 1.5e-6, 2.9}};
constexpr int kFitOrder = 6;  // above every order of kFormError: orders 4 and 6 must come out zero

double ProfileValue(double theta, const std::vector<engine::Harmonic>& harmonics) {
  double value = kRadius;
  for (const engine::Harmonic& h : harmonics) value += h.amplitude * std::cos(h.order * theta + h.phase);
  return value;
}

// a_n and b_n of r = ... + sum_n (a_n cos n theta - b_n sin n theta) for `harmonics` [m], as
// PolarProfile sums harmonics of equal order.
double CosCoefficient(const std::vector<engine::Harmonic>& harmonics, int n) {
  return engine::PolarProfile(1.0, 0.0, harmonics).cos_coefficient(n);
}
double SinCoefficient(const std::vector<engine::Harmonic>& harmonics, int n) {
  return engine::PolarProfile(1.0, 0.0, harmonics).sin_coefficient(n);
}

std::vector<ProfileSample> Sample(const std::vector<double>& angles, const std::vector<engine::Harmonic>& harmonics) {
  std::vector<ProfileSample> samples;
  for (const double theta : angles) samples.push_back({theta, ProfileValue(theta, harmonics)});
  return samples;
}

std::vector<double> EvenAngles(int count) {
  std::vector<double> angles;
  for (int i = 0; i < count; ++i) angles.push_back(2.0 * kPi * i / count);
  return angles;
}

// Noise-free data are the true values rounded to eps |value| <= eps kRadius; a backward-
// stable least-squares solve amplifies that by at most the condition number, and the SVD
// adds rounding of the same size per unknown it combines: unknowns x eps x cond x kRadius.
double RoundOffTolerance(const FourierFit& fit) {
  return static_cast<double>(2 * kFitOrder + 1) * kEps * fit.condition_number * kRadius;
}

void ExpectCoefficients(const FourierFit& fit, const std::vector<engine::Harmonic>& truth, double tolerance) {
  EXPECT_NEAR(fit.mean, kRadius, tolerance);
  ASSERT_EQ(fit.harmonics.size(), static_cast<std::size_t>(kFitOrder));
  for (const engine::Harmonic& h : fit.harmonics) {
    SCOPED_TRACE("order " + std::to_string(h.order));
    EXPECT_NEAR(h.amplitude * std::cos(h.phase), CosCoefficient(truth, h.order), tolerance);
    EXPECT_NEAR(h.amplitude * std::sin(h.phase), SinCoefficient(truth, h.order), tolerance);
  }
}

std::string ErrorFor(const std::vector<ProfileSample>& samples, int max_order) {
  try {
    FitFourierSeries(samples, max_order);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  ADD_FAILURE() << "FitFourierSeries accepted the samples";
  return "";
}

// Standard normal deviates from Box-Muller on a splitmix64 stream: the same numbers with
// every standard library, which std::normal_distribution does not promise.
class GaussianNoise {
 public:
  explicit GaussianNoise(std::uint64_t seed) : state_(seed) {}

  double operator()() {
    const double radius = std::sqrt(-2.0 * std::log(Uniform()));
    return radius * std::cos(2.0 * kPi * Uniform());
  }

 private:
  double Uniform() {  // in (0, 1): never 0, whose log is -inf
    state_ += 0x9e3779b97f4a7c15ULL;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return (static_cast<double>(z >> 11) + 0.5) * 0x1.0p-53;
  }

  std::uint64_t state_;
};

// The noisy experiment shared by the statistical tests: M evenly spaced readings with
// independent Gaussian noise of standard deviation kNoise.
constexpr int kNoisyPoints = 720;  // M, a reading every half degree
constexpr double kNoise = 1e-6;    // [m] sigma
constexpr std::uint64_t kNoiseSeed = 20240601;

const FourierFit& NoisyFit() {
  static const FourierFit fit = [] {
    GaussianNoise noise(kNoiseSeed);
    std::vector<ProfileSample> samples = Sample(EvenAngles(kNoisyPoints), kFormError);
    for (ProfileSample& sample : samples) sample.value += kNoise * noise();
    return FitFourierSeries(samples, kFitOrder);
  }();
  return fit;
}

// For M evenly spaced angles and M > 2N the sampled cosines and sines are orthogonal:
// sum_i cos n theta_i cos m theta_i = (M/2) delta_nm, likewise for sines, cross sums 0.
// So A^T A = diag(M, M/2, ..., M/2), the condition number of A is sqrt(2), and the
// covariance sigma^2 (A^T A)^-1 makes a_0, a_n, b_n uncorrelated with standard errors
// sigma / sqrt(M) and sigma sqrt(2 / M).
const double kMeanStandardError = kNoise / std::sqrt(double{kNoisyPoints});
const double kCoefficientStandardError = kNoise * std::sqrt(2.0 / kNoisyPoints);

TEST(FitFourierSeries, RecoversKnownCoefficientsExactlyFromEvenNoiseFreeSamples) {
  constexpr int kPoints = 360;
  const FourierFit fit = FitFourierSeries(Sample(EvenAngles(kPoints), kFormError), kFitOrder);
  ExpectCoefficients(fit, kFormError, RoundOffTolerance(fit));
  for (int n = 1; n <= kFitOrder; ++n) EXPECT_EQ(fit.harmonics[static_cast<std::size_t>(n - 1)].order, n);
  EXPECT_LE(fit.residual_max, RoundOffTolerance(fit));
  EXPECT_LE(fit.residual_rms, fit.residual_max);
  EXPECT_EQ(fit.points, kPoints);

  // The Gram matrix is M/2 (1, 2, 1, ..., 1) up to the rounding of sums of M products of
  // terms <= 1: M eps relative; a factor 10 more for the SVD.
  const double kConditionTolerance = 10.0 * kPoints * kEps;
  EXPECT_NEAR(fit.condition_number, std::sqrt(2.0), kConditionTolerance);
  // Each angle 2 pi i / M is rounded to eps x 2 pi, so each gap to twice that.
  const double kGapTolerance = 2.0 * kEps * 2.0 * kPi;
  EXPECT_NEAR(fit.largest_gap, 2.0 * kPi / kPoints, kGapTolerance);
}

TEST(FitFourierSeries, RecoversExactlyFromUnevenSamplesWithA60DegreeGap) {
  // From 30 to 330 degrees, crowded towards 30: no reading in the 60 degrees about 0.
  constexpr int kPoints = 100;
  std::vector<double> angles;
  for (int i = 0; i < kPoints; ++i) angles.push_back((30.0 + 300.0 * std::pow(i / (kPoints - 1.0), 1.3)) * kDeg);
  const FourierFit fit = FitFourierSeries(Sample(angles, kFormError), kFitOrder);
  ExpectCoefficients(fit, kFormError, RoundOffTolerance(fit));
  // 30 and 330 degrees are each rounded to eps x 2 pi.
  const double kGapTolerance = 2.0 * kEps * 2.0 * kPi;
  EXPECT_NEAR(fit.largest_gap, 60.0 * kDeg, kGapTolerance);
}

TEST(FitFourierSeries, AcceptsAnglesBeyondOneTurnAndRepeatedAngles) {
  // Every angle twice, shifted by whole turns from -3 to +4: the same outline.
  constexpr int kDistinct = 40;
  std::vector<double> angles;
  const std::vector<double> even = EvenAngles(kDistinct);
  for (std::size_t i = 0; i < even.size(); ++i) {
    const double turns = static_cast<double>(i % 8) - 3.0;
    angles.push_back(even[i] + turns * 2.0 * kPi);
    angles.push_back(even[i] - turns * 2.0 * kPi);
  }
  const FourierFit fit = FitFourierSeries(Sample(angles, kFormError), kFitOrder);
  // Wrapping by fmod is exact; what differs from the one-turn fit is the 2.4e-16 rad by
  // which the double 2 pi misses 2 pi, per turn: <= 4 x 2.4e-16 rad x sum_n n C_n < 1e-19 m,
  // far inside the round-off tolerance.
  ExpectCoefficients(fit, kFormError, RoundOffTolerance(fit));
  EXPECT_EQ(fit.points, 2 * kDistinct);
  // Wrapping rounds each angle to eps x 8 turns.
  const double kGapTolerance = 2.0 * kEps * 8.0 * 2.0 * kPi;
  EXPECT_NEAR(fit.largest_gap, 2.0 * kPi / kDistinct, kGapTolerance);
}

TEST(FitFourierSeries, ReportsPhasesInTheCosineWithPhaseConventionOfPolarProfile) {
  constexpr double kAmplitude = 2e-6;  // [m]
  // 0.7 as given; -4 is outside (-pi, pi] and must come back as -4 + 2 pi.
  for (const auto& [phase, expected] : {std::pair{0.7, 0.7}, std::pair{-4.0, -4.0 + 2.0 * kPi}}) {
    SCOPED_TRACE("phase " + std::to_string(phase));
    const FourierFit fit = FitFourierSeries(Sample(EvenAngles(64), {{3, kAmplitude, phase}}), kFitOrder);
    const double tolerance = RoundOffTolerance(fit);
    EXPECT_NEAR(fit.harmonics[2].amplitude, kAmplitude, tolerance);
    // A coefficient error e turns the phase by at most e / C.
    EXPECT_NEAR(fit.harmonics[2].phase, expected, tolerance / kAmplitude);
    for (const engine::Harmonic& h : fit.harmonics) {
      if (h.order != 3) {
        EXPECT_LE(h.amplitude, tolerance) << "order " << h.order;
      }
    }
  }
}

// Statistical: seed kNoiseSeed, significance 1e-3 for the whole test. The 2 N + 1 = 13
// coefficients are checked at k = 4.5 standard errors each: P(|Z| > 4.5) = 6.8e-6, and
// 13 x 6.8e-6 = 8.8e-5 < 1e-3 (Bonferroni).
TEST(FitFourierSeries, RecoversCoefficientsWithinTheirStandardErrorsUnderNoise) {
  constexpr double kStandardErrors = 4.5;
  const FourierFit& fit = NoisyFit();
  EXPECT_NEAR(fit.mean, kRadius, kStandardErrors * kMeanStandardError);
  for (const engine::Harmonic& h : fit.harmonics) {
    SCOPED_TRACE("order " + std::to_string(h.order));
    EXPECT_NEAR(h.amplitude * std::cos(h.phase), CosCoefficient(kFormError, h.order),
                kStandardErrors * kCoefficientStandardError);
    EXPECT_NEAR(h.amplitude * std::sin(h.phase), SinCoefficient(kFormError, h.order),
                kStandardErrors * kCoefficientStandardError);
  }
}

// Statistical: seed kNoiseSeed, significance 1e-3. Every reported standard error is
// s sqrt(2 / M), s^2 = SS_res / nu, nu = M - 13 = 707 (with equal, uncorrelated variances
// of a_n and b_n the delta method gives back their common value). nu s^2 / sigma^2 is
// chi-square with nu degrees of freedom, so s / sigma = 1 +- 1 / sqrt(2 nu) to first
// order; all orders share s, so this is one check, at z = 3.29 (two-sided 1e-3).
TEST(FitFourierSeries, ReportsAmplitudeStandardErrorsThatMatchTheAnalyticOnes) {
  const FourierFit& fit = NoisyFit();
  const double degrees_of_freedom = kNoisyPoints - (2 * kFitOrder + 1);
  const double kRelativeTolerance = 3.29 / std::sqrt(2.0 * degrees_of_freedom);
  ASSERT_EQ(fit.amplitude_standard_errors.size(), static_cast<std::size_t>(kFitOrder));
  for (const double standard_error : fit.amplitude_standard_errors) {
    EXPECT_NEAR(standard_error / kCoefficientStandardError, 1.0, kRelativeTolerance);
  }
}

TEST(FitFourierSeries, ReportsRSquaredOfOneWithoutNoiseAndBetweenZeroAndOneWithIt) {
  const FourierFit clean = FitFourierSeries(Sample(EvenAngles(360), kFormError), kFitOrder);
  // 1 - R^2 = SS_res / SS_tot <= (residual_max / smallest amplitude)^2 < 1e-19: below
  // the spacing of doubles next to 1.
  EXPECT_NEAR(clean.r_squared, 1.0, kEps);
  const FourierFit& noisy = NoisyFit();
  EXPECT_GT(noisy.r_squared, 0.0);
  EXPECT_LT(noisy.r_squared, 1.0);
  // A perfect circle: SS_tot = 0, where R^2 is 1 by definition.
  EXPECT_EQ(FitFourierSeries(Sample(EvenAngles(36), {}), kFitOrder).r_squared, 1.0);
}

TEST(FitFourierSeries, ReportsNanStandardErrorsWhenPointsEqualUnknowns) {
  const FourierFit fit = FitFourierSeries(Sample(EvenAngles(2 * kFitOrder + 1), kFormError), kFitOrder);
  ExpectCoefficients(fit, kFormError, RoundOffTolerance(fit));
  for (const double standard_error : fit.amplitude_standard_errors) EXPECT_TRUE(std::isnan(standard_error));
}

TEST(FitFourierSeries, RejectsTooFewDistinctAnglesNamingTheCounts) {
  // 40 samples, but at 20 distinct angles: repeats add no equations.
  std::vector<double> angles = EvenAngles(20);
  angles.insert(angles.end(), angles.begin(), angles.end());
  EXPECT_THAT(ErrorFor(Sample(angles, kFormError), 10),
              AllOf(HasSubstr("orders up to 10"), HasSubstr("2*10+1 = 21 points at distinct angles"),
                    HasSubstr("got 20")));
  EXPECT_THAT(ErrorFor({}, 1), HasSubstr("got 0"));
}

// A long export at many orders is refused before its matrix is allocated, saying what fits
// instead: here 100,000 points at orders up to 1,000 would take 3.2 GB.
TEST(FitFourierSeries, RefusesAMatrixTooLargeSayingWhatFits) {
  const std::string message = ErrorFor(Sample(EvenAngles(100000), kFormError), 1000);
  EXPECT_THAT(message, AllOf(HasSubstr("orders up to 1000 to 100000 points"), HasSubstr("100000 x 2001"),
                             HasSubstr("3.2 GB"), HasSubstr("orders up to 319 at these points"),
                             HasSubstr("every 4th point")));
}

TEST(FitFourierSeries, RejectsAGapTooWideForTheOrdersNamingTheGap) {
  // 50 readings within 20 degrees: enough points for order 10, but not enough outline.
  std::vector<double> angles;
  for (int i = 0; i < 50; ++i) angles.push_back(20.0 * kDeg * i / 49.0);
  EXPECT_THAT(ErrorFor(Sample(angles, kFormError), 10),
              AllOf(HasSubstr("orders up to 10"), HasSubstr("rank-deficient"), HasSubstr("gap of 340.0 degrees"),
                    HasSubstr("fit fewer orders (up to 3 ")));
}

TEST(FitFourierSeries, RejectsNonFiniteSamplesAndOrdersBelowOne) {
  std::vector<ProfileSample> samples = Sample(EvenAngles(36), kFormError);
  EXPECT_THAT(ErrorFor(samples, 0), HasSubstr("max_order = 0"));
  samples[7].value = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT(ErrorFor(samples, 2), AllOf(HasSubstr("sample 7"), HasSubstr("nan")));
  samples[7].value = kRadius;
  samples[9].angle = std::numeric_limits<double>::infinity();
  EXPECT_THAT(ErrorFor(samples, 2), AllOf(HasSubstr("sample 9"), HasSubstr("inf")));
}

}  // namespace
}  // namespace ringtol::sampling
