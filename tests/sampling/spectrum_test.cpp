#include "sampling/spectrum.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "sampling/random.h"
#include "tests/support/statistics.h"

namespace ringtol::sampling {
namespace {

using ::testing::HasSubstr;

constexpr double kPi = std::numbers::pi;
constexpr double kEps = std::numeric_limits<double>::epsilon();
// Newton polishes the extreme to where f' = 0 to round-off: the value error is then second order in
// the angle error, far below a few eps times the sum of amplitudes.
constexpr double kPolishedTolerance = 64.0 * kEps;

std::vector<double> Draws(std::uint64_t seed, std::uint64_t draw, std::size_t count, std::uint64_t offset) {
  std::vector<double> u(count);
  for (std::size_t k = 0; k < count; ++k) u[k] = RandomUnit(seed, RandomStream::kMonteCarlo, draw, 2 * k + offset, 0);
  return u;
}

// max - min of f over a dense grid, and a bound on how far below the true extremes the grid can be:
// |f - f(grid)| <= max|f''| h^2 / 8 at a smooth extreme, h the spacing.
struct DenseRange {
  double range;
  double bound;
};
DenseRange BruteForce(const std::vector<engine::Harmonic>& hs, bool two_point) {
  constexpr int kPoints = 100000;
  double lo = 1e300, hi = -1e300, curvature = 0.0;
  for (const auto& h : hs) curvature += h.order * h.order * h.amplitude * 2.0;
  for (int m = 0; m < kPoints; ++m) {
    const double t = 2.0 * kPi * m / kPoints;
    double f = 0.0;
    for (const auto& h : hs) {
      if (h.order < 2) continue;
      f += h.amplitude * std::cos(h.order * t + h.phase);
      if (two_point) f += h.amplitude * std::cos(h.order * (t + kPi) + h.phase);
    }
    lo = std::min(lo, f);
    hi = std::max(hi, f);
  }
  const double h = 2.0 * kPi / kPoints;
  return {hi - lo, 2.0 * curvature * h * h / 8.0};
}

TEST(MeasureForm, OneHarmonicHasTheTextbookValues) {
  // docs/tolerances.md §7.3: r = R + A cos(n theta): RONt = 2A; VDsp = 4A for even n, 0 for odd.
  constexpr double kA = 7e-6;
  for (int n = 2; n <= 12; ++n) {
    const std::vector<engine::Harmonic> h{{n, kA, 0.3 * n}};
    EXPECT_NEAR(MeasureForm(FormMeasure::kRoundness, h), 2.0 * kA, kPolishedTolerance * kA) << n;
    EXPECT_NEAR(MeasureForm(FormMeasure::kTwoPointVariation, h), n % 2 == 0 ? 4.0 * kA : 0.0, kPolishedTolerance * kA)
        << n;
  }
  // The least-squares circle absorbs eccentricity: order 1 has no roundness.
  const std::vector<engine::Harmonic> eccentric{{1, kA, 0.0}};
  EXPECT_EQ(MeasureForm(FormMeasure::kRoundness, eccentric), 0.0);
}

TEST(MeasureForm, AgreesWithADenseGridOnRandomProfiles) {
  SpectrumShape shape{2, 40, 0.5, {}};
  for (std::uint64_t draw = 0; draw < 12; ++draw) {
    const auto u = Draws(17, draw, 39, 0), v = Draws(17, draw, 39, 1);
    const std::vector<engine::Harmonic> hs = DrawHarmonics(shape, 1e-5, u, v);
    for (const bool two_point : {false, true}) {
      const DenseRange dense = BruteForce(hs, two_point);
      const double measured = MeasureForm(two_point ? FormMeasure::kTwoPointVariation : FormMeasure::kRoundness, hs);
      // The grid can only miss the extremes from inside.
      EXPECT_GE(measured, dense.range - kPolishedTolerance * 1e-4) << draw;
      EXPECT_LE(measured, dense.range + dense.bound) << draw;
    }
  }
}

TEST(DrawHarmonics, AmplitudesAreRayleighAndPhasesUniform) {
  // C_n / (c s_n) ~ Rayleigh(1): F(x) = 1 - exp(-x^2/2); phi ~ U(-pi, pi). Kolmogorov- Smirnov on 4
  // orders x 2 quantities, overall significance 1e-3.
  constexpr double kAlpha = 1e-3 / 8.0;
  constexpr int kDraws = 5000;
  constexpr double kScale = 2e-6;
  const SpectrumShape shape{2, 30, 1.5, {}};
  for (const int n : {2, 3, 10, 30}) {
    std::vector<double> amplitude, phase;
    for (int i = 0; i < kDraws; ++i) {
      const auto u = Draws(5, static_cast<std::uint64_t>(i), 29, 0), v = Draws(5, static_cast<std::uint64_t>(i), 29, 1);
      const engine::Harmonic h = DrawHarmonics(shape, kScale, u, v)[static_cast<std::size_t>(n - 2)];
      ASSERT_EQ(h.order, n);
      amplitude.push_back(h.amplitude / (kScale * std::pow(n, -1.5)));
      phase.push_back(h.phase);
    }
    const double da = testing::KolmogorovSmirnovStatistic(amplitude, [](double x) { return 1 - std::exp(-x * x / 2); });
    const double dp = testing::KolmogorovSmirnovStatistic(phase, [](double x) { return (x + kPi) / (2 * kPi); });
    EXPECT_GT(testing::KolmogorovSmirnovPValue(da, amplitude.size()), kAlpha) << "order " << n;
    EXPECT_GT(testing::KolmogorovSmirnovPValue(dp, phase.size()), kAlpha) << "order " << n;
  }
}

TEST(MeasureForm, PeakToValleyOfOneDrawnOrderHasItsExactDistribution) {
  // One order n drawn at scale c: C ~ Rayleigh(c n^-a), so RONt = 2C and, for even n,
  // VDsp = 4C; for odd n VDsp = 0. Kolmogorov-Smirnov against those laws, significance 1e-3
  // split over 3 tests.
  constexpr double kAlpha = 1e-3 / 3.0;
  const auto rayleigh = [](double x) { return 1 - std::exp(-x * x / 2); };
  constexpr int kDraws = 4000;
  constexpr double kScale = 3e-6;
  for (const int n : {4, 7}) {
    const SpectrumShape shape{n, n, 1.0, {}};
    const double sigma = kScale / n;
    std::vector<double> roundness, two_point;
    for (int i = 0; i < kDraws; ++i) {
      const auto u = Draws(9, static_cast<std::uint64_t>(i), 1, 0), v = Draws(9, static_cast<std::uint64_t>(i), 1, 1);
      const auto hs = DrawHarmonics(shape, kScale, u, v);
      roundness.push_back(MeasureForm(FormMeasure::kRoundness, hs) / (2 * sigma));
      two_point.push_back(MeasureForm(FormMeasure::kTwoPointVariation, hs));
    }
    const double d = testing::KolmogorovSmirnovStatistic(roundness, rayleigh);
    EXPECT_GT(testing::KolmogorovSmirnovPValue(d, roundness.size()), kAlpha) << "order " << n;
    if (n % 2 == 1) {
      EXPECT_EQ(*std::max_element(two_point.begin(), two_point.end()), 0.0);
    } else {
      for (double& x : two_point) x /= 4 * sigma;
      const double d2 = testing::KolmogorovSmirnovStatistic(two_point, rayleigh);
      EXPECT_GT(testing::KolmogorovSmirnovPValue(d2, two_point.size()), kAlpha) << "order " << n;
    }
  }
}

TEST(CalibrateSpectrum, CalibratedPartsMeetTheirToleranceAtTheStatedCoverage) {
  // Fresh draws at the calibrated scale: the fraction inside differs from p by the calibration's
  // own sampling error (the coverage of an order statistic has variance p(1-p)/K) plus the check's
  // (p(1-p)/M), independent: z = (f - p) / sqrt(p(1-p)(1/K + 1/M)). Significance 1e-3 over 4 cases.
  const double z_max = testing::TwoSidedNormalQuantile(1e-3 / 4.0);
  constexpr double kTolerance = 50e-6;
  constexpr int kChecks = 20000;
  const SpectrumShape shape{2, 16, 1.0, {}};
  for (const FormMeasure measure : {FormMeasure::kRoundness, FormMeasure::kTwoPointVariation}) {
    for (const double p : {0.9973, 0.9}) {
      const SpectrumCalibration c = CalibrateSpectrum(shape, measure, kTolerance, p);
      EXPECT_GE(c.draws, 16384);
      EXPECT_LE(c.unit_quantile_low, c.unit_quantile);
      EXPECT_GE(c.unit_quantile_high, c.unit_quantile);
      int inside = 0;
      for (int i = 0; i < kChecks; ++i) {
        const auto u = Draws(77, static_cast<std::uint64_t>(i), 15, 0),
                   v = Draws(77, static_cast<std::uint64_t>(i), 15, 1);
        inside += MeasureForm(measure, DrawHarmonics(shape, c.scale, u, v)) <= kTolerance;
      }
      const double f = static_cast<double>(inside) / kChecks;
      const double sd = std::sqrt(p * (1 - p) * (1.0 / c.draws + 1.0 / kChecks));
      EXPECT_LT(std::abs(f - p) / sd, z_max) << FormMeasureName(measure) << " p " << p << " f " << f;
    }
  }
}

TEST(CalibrateSpectrum, RoundnessOfOneOrderIsTwiceItsAmplitude) {
  // With a single order, RONt = 2C and C is Rayleigh(c): P(2C <= t) = p gives c = (t/2) / sqrt(-2
  // ln(1-p)); the Monte Carlo quantile must find it within its own 95 % interval, widened by the 1
  // % the interval's ranks may round.
  constexpr double kTolerance = 10e-6;
  constexpr double kP = 0.99;
  const SpectrumCalibration c = CalibrateSpectrum({3, 3, 1.0, {}}, FormMeasure::kRoundness, kTolerance, kP);
  const double exact_unit_quantile = 2.0 * std::pow(3.0, -1.0) * std::sqrt(-2.0 * std::log1p(-kP));
  EXPECT_GE(exact_unit_quantile, c.unit_quantile_low * 0.99);
  EXPECT_LE(exact_unit_quantile, c.unit_quantile_high * 1.01);
}

TEST(CalibrateSpectrum, RefusesWhatItCannotCalibrate) {
  try {
    CalibrateSpectrum({3, 3, 1.0, {}}, FormMeasure::kTwoPointVariation, 1e-5, 0.99);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("cannot see odd orders"));
  }
  EXPECT_THROW(CalibrateSpectrum({2, 1, 1.0, {}}, FormMeasure::kRoundness, 1e-5, 0.99), std::invalid_argument);
  EXPECT_THROW(CalibrateSpectrum({0, 4, 1.0, {}}, FormMeasure::kRoundness, 1e-5, 0.99), std::invalid_argument);
  EXPECT_THROW(CalibrateSpectrum({2, 4, -1.0, {}}, FormMeasure::kRoundness, 1e-5, 0.99), std::invalid_argument);
  EXPECT_THROW(CalibrateSpectrum({2, 4, 1.0, {1, 2}}, FormMeasure::kRoundness, 1e-5, 0.99), std::invalid_argument);
  EXPECT_THROW(CalibrateSpectrum({2, 4, 1.0, {}}, FormMeasure::kRoundness, 0.0, 0.99), std::invalid_argument);
  try {
    CalibrateSpectrum({2, 4, 1.0, {}}, FormMeasure::kRoundness, 1e-5, 0.9999999);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("calibration draws"));
  }
}

}  // namespace
}  // namespace ringtol::sampling
