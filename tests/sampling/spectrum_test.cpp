#include "sampling/spectrum.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

#include "sampling/assembly_sampler.h"
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
// The coarse grid's upper bound exceeds the exact measure by its Taylor remainder, sum n^3 |a|
// (h/2)^3 / 3 at h = pi / top (about 12 % of RONt for the ring's n^-1 spectrum at Rayleigh-mean
// amplitudes), plus the quadratic's reach past the extreme: medians measured 1.17 (ring, 2..50)
// and 1.24 (rollers, VDsp 2..8).
constexpr double kCoarseMedianWidth = 1.3;

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

// MeasureForm as first written: the grid summed one term at a time, then the same polish. The
// measure now sums four terms per pass; it must still compute these bits.
double TermByTermMeasure(FormMeasure measure, const std::vector<engine::Harmonic>& harmonics) {
  struct Term {
    int order;
    double amplitude, phase;
  };
  std::vector<Term> terms;
  int top = 0;
  for (const engine::Harmonic& h : harmonics) {
    if (h.amplitude == 0.0) continue;
    if (measure == FormMeasure::kRoundness && h.order >= 2) terms.push_back({h.order, h.amplitude, h.phase});
    if (measure == FormMeasure::kTwoPointVariation && h.order % 2 == 0)
      terms.push_back({h.order, 2.0 * h.amplitude, h.phase});
    if (!terms.empty()) top = std::max(top, terms.back().order);
  }
  if (terms.empty()) return 0.0;
  auto evaluate = [&](double theta) {
    double f = 0.0, df = 0.0, ddf = 0.0;
    for (const Term& t : terms) {
      const double a = t.order * theta + t.phase;
      const double c = std::cos(a), sn = std::sin(a);
      const double n = t.order;
      f += t.amplitude * c;
      df -= n * t.amplitude * sn;
      ddf -= n * n * t.amplitude * c;
    }
    return std::array<double, 3>{f, df, ddf};
  };
  const int points = std::max(64, 8 * top);
  const double spacing = 2.0 * kPi / points;
  auto polish = [&](double theta, double sign) {
    std::array<double, 3> v = evaluate(theta);
    double best = v[0];
    for (int iteration = 0; iteration < 8; ++iteration) {
      if (sign * v[2] >= 0.0) break;
      const double step = std::clamp(-v[1] / v[2], -spacing, spacing);
      theta += step;
      v = evaluate(theta);
      if (sign * v[0] > sign * best) best = v[0];
      if (std::abs(step) < 1e-13) break;
    }
    return best;
  };
  std::vector<double> f(static_cast<std::size_t>(points), 0.0);
  for (const Term& t : terms) {
    std::complex<double> z = std::polar(t.amplitude, t.phase);
    const std::complex<double> step = std::polar(1.0, t.order * spacing);
    for (double& value : f) {
      value += z.real();
      z *= step;
    }
  }
  double curvature = 0.0;
  for (const Term& t : terms) curvature += static_cast<double>(t.order) * t.order * t.amplitude;
  const double margin = curvature * spacing * spacing / 8.0;
  const auto [low, high] = std::minmax_element(f.begin(), f.end());
  double max = *high, min = *low;
  const std::size_t n = f.size();
  for (std::size_t m = 0; m < n; ++m) {
    const double before = f[(m + n - 1) % n], here = f[m], after = f[(m + 1) % n];
    const double theta = spacing * static_cast<double>(m);
    if (here >= before && here >= after && here >= *high - margin) max = std::max(max, polish(theta, +1.0));
    if (here <= before && here <= after && here <= *low + margin) min = std::min(min, polish(theta, -1.0));
  }
  return max - min;
}

// Shapes that span what the catalogue and the sampler draw: the ring's 2..50 at n^-1 (every
// ring class), rollers' 2..8 (every roller class), a flat spectrum, a steep one, a table with
// gaps, a lone high order, and a cutoff well above the default.
std::vector<SpectrumShape> VariedShapes() {
  return {{2, 50, 1.0, {}}, {2, 8, 1.0, {}},   {2, 16, 0.0, {}},          {2, 30, 2.5, {}},
          {2, 6, 1.0, {0.0, 1.0, 0.0, 0.3, 0.0}}, {24, 24, 1.0, {}}, {3, 120, 0.5, {}}};
}

TEST(MeasureForm, ComputesTheTermByTermGridsBitsOnRandomProfiles) {
  for (const SpectrumShape& shape : VariedShapes()) {
    const auto orders = static_cast<std::size_t>(shape.order_count());
    for (std::uint64_t draw = 0; draw < 300; ++draw) {
      const auto u = Draws(23, draw, orders, 0), v = Draws(23, draw, orders, 1);
      const std::vector<engine::Harmonic> hs = DrawHarmonics(shape, 1e-5, u, v);
      for (const FormMeasure measure : {FormMeasure::kRoundness, FormMeasure::kTwoPointVariation}) {
        const double reference = TermByTermMeasure(measure, hs);
        ASSERT_EQ(MeasureForm(measure, hs), reference) << shape.min_order << ".." << shape.max_order << " " << draw;
      }
    }
  }
}

TEST(BoundForm, BoundsTheComputedMeasureOnRandomProfiles) {
  // Rigorous bounds, so no tolerance: lower <= MeasureForm <= upper exactly, and the coarse
  // grid's are inside the amplitudes'.
  for (const SpectrumShape& shape : VariedShapes()) {
    const auto orders = static_cast<std::size_t>(shape.order_count());
    for (std::uint64_t draw = 0; draw < 1000; ++draw) {
      const auto u = Draws(29, draw, orders, 0), v = Draws(29, draw, orders, 1);
      const std::vector<engine::Harmonic> hs = DrawHarmonics(shape, 3e-6, u, v);
      for (const FormMeasure measure : {FormMeasure::kRoundness, FormMeasure::kTwoPointVariation}) {
        const double exact = MeasureForm(measure, hs);
        const FormBounds amplitudes = BoundForm(measure, hs, FormBoundLevel::kAmplitudes);
        const FormBounds coarse = BoundForm(measure, hs, FormBoundLevel::kCoarseGrid);
        ASSERT_LE(amplitudes.lower, exact) << draw;
        ASSERT_GE(amplitudes.upper, exact) << draw;
        ASSERT_LE(coarse.lower, exact) << draw;
        ASSERT_GE(coarse.upper, exact) << draw;
        EXPECT_GE(coarse.lower, amplitudes.lower);
        EXPECT_LE(coarse.upper, amplitudes.upper);
      }
    }
  }
}

TEST(BoundForm, CoarseGridIsCloseOnTheCataloguesSpectra) {
  // Useful, not only sound: on the ring's and the rollers' default spectra the coarse upper
  // bound is within kCoarseMedianWidth of the exact measure for the median draw.
  const std::vector<std::pair<SpectrumShape, FormMeasure>> spectra = {
      {{2, 50, 1.0, {}}, FormMeasure::kRoundness}, {{2, 8, 1.0, {}}, FormMeasure::kTwoPointVariation}};
  for (const auto& [shape, measure] : spectra) {
    const auto orders = static_cast<std::size_t>(shape.order_count());
    std::vector<double> ratio;
    for (std::uint64_t draw = 0; draw < 1001; ++draw) {
      const auto u = Draws(41, draw, orders, 0), v = Draws(41, draw, orders, 1);
      const std::vector<engine::Harmonic> hs = DrawHarmonics(shape, 3e-6, u, v);
      ratio.push_back(BoundForm(measure, hs, FormBoundLevel::kCoarseGrid).upper / MeasureForm(measure, hs));
    }
    std::nth_element(ratio.begin(), ratio.begin() + 500, ratio.end());
    EXPECT_LT(ratio[500], kCoarseMedianWidth) << FormMeasureName(measure);
  }
}

TEST(FormWithin, DecidesAsTheExactMeasureAtAndAroundEveryLimit) {
  // Limits at the measure itself and one ulp either side are where a bound's round-off would
  // show; limits at 0.9 and 1.1 times it are where the coarse grid alone must not decide wrong.
  for (const SpectrumShape& shape : VariedShapes()) {
    const auto orders = static_cast<std::size_t>(shape.order_count());
    for (std::uint64_t draw = 0; draw < 300; ++draw) {
      const auto u = Draws(31, draw, orders, 0), v = Draws(31, draw, orders, 1);
      const std::vector<engine::Harmonic> hs = DrawHarmonics(shape, 2e-5, u, v);
      for (const FormMeasure measure : {FormMeasure::kRoundness, FormMeasure::kTwoPointVariation}) {
        const double exact = MeasureForm(measure, hs);
        for (const double limit : {exact, std::nextafter(exact, 0.0), std::nextafter(exact, 1.0), 0.9 * exact,
                                   1.1 * exact, 0.0})
          ASSERT_EQ(FormWithin(measure, hs, limit), exact <= limit) << draw << " limit " << limit;
      }
    }
  }
}

TEST(FormWithin, AcceptsAndRejectsTheCataloguesPartsAsTheExactMeasure) {
  // Parts drawn at their class's calibrated scale from the loosest and the tightest classes
  // (ring ISO2768-L, RONt 0.5 mm, and IT5/2 at 250-315 mm, 11.5 um; rollers Normal at
  // D 6-18 mm, VDsp 10 um, and class 2, 2.5 um), at Cp 0.1 and 1, so that 76 % and 0.27 % of
  // parts are out of tolerance.
  struct Class {
    SpectrumShape shape;
    FormMeasure measure;
    double tolerance;
  };
  const std::vector<Class> classes = {{{2, 50, 1.0, {}}, FormMeasure::kRoundness, 500e-6},
                                      {{2, 50, 1.0, {}}, FormMeasure::kRoundness, 11.5e-6},
                                      {{2, 8, 1.0, {}}, FormMeasure::kTwoPointVariation, 10e-6},
                                      {{2, 8, 1.0, {}}, FormMeasure::kTwoPointVariation, 2.5e-6}};
  CalibrationOptions calibration;
  calibration.min_draws = 4096;
  for (const Class& c : classes) {
    for (const double cp : {0.1, 1.0}) {
      const double coverage = std::erf(3.0 * cp / std::numbers::sqrt2);
      const double scale = CalibrateSpectrum(c.shape, c.measure, c.tolerance, coverage, calibration).scale;
      const auto orders = static_cast<std::size_t>(c.shape.order_count());
      int rejected = 0;
      for (std::uint64_t draw = 0; draw < 4000; ++draw) {
        const auto u = Draws(37, draw, orders, 0), v = Draws(37, draw, orders, 1);
        const std::vector<engine::Harmonic> hs = DrawHarmonics(c.shape, scale, u, v);
        const bool exact = MeasureForm(c.measure, hs) <= c.tolerance;
        ASSERT_EQ(FormWithin(c.measure, hs, c.tolerance), exact) << c.tolerance << " Cp " << cp << " " << draw;
        rejected += !exact;
      }
      if (cp == 0.1) {
        EXPECT_GT(rejected, 1000);  // the limit is crossed often, not only in principle
      }
    }
  }
}

TEST(CalibrateSpectrum, SelectionByBoundsEqualsSortingEveryExactMeasure) {
  // The quantile and its interval are order statistics: selected by bounds or by sorting all
  // exact measures, they are the same draws' values, so the same bits.
  auto same = [](const SpectrumCalibration& a, const SpectrumCalibration& b) {
    return a.scale == b.scale && a.unit_quantile == b.unit_quantile && a.unit_quantile_low == b.unit_quantile_low &&
           a.unit_quantile_high == b.unit_quantile_high && a.draws == b.draws;
  };
  CalibrationOptions bounded, exact;
  bounded.min_draws = exact.min_draws = 4096;
  exact.exact_every_draw = true;
  // Coverages of Cp 0.1, 0.55 and 0.86 at 4096 draws (Cp 1.33 needs half a million draws: too
  // slow to measure every one here); the 118-order shape is left to the bound tests.
  for (const SpectrumShape& shape : VariedShapes()) {
    if (shape.max_order > 50) continue;
    for (const FormMeasure measure : {FormMeasure::kRoundness, FormMeasure::kTwoPointVariation}) {
      bool even = false;
      for (int n = shape.min_order; n <= shape.max_order; ++n) even = even || (n % 2 == 0 && shape.RelativeScale(n) > 0);
      if (measure == FormMeasure::kTwoPointVariation && !even) continue;
      for (const double coverage : {0.236, 0.9, 0.99}) {
        const SpectrumCalibration a = CalibrateSpectrum(shape, measure, 1e-5, coverage, bounded);
        const SpectrumCalibration b = CalibrateSpectrum(shape, measure, 1e-5, coverage, exact);
        EXPECT_TRUE(same(a, b)) << shape.min_order << ".." << shape.max_order << " " << FormMeasureName(measure)
                                << " p " << coverage << ": " << a.unit_quantile << " vs " << b.unit_quantile;
      }
    }
  }
  // And at the campaign's own size and coverage (Cp 1, 16384 draws) for the ring's spectrum.
  const SpectrumShape ring{2, 50, 1.0, {}};
  CalibrationOptions full_exact;
  full_exact.exact_every_draw = true;
  EXPECT_TRUE(same(CalibrateSpectrum(ring, FormMeasure::kRoundness, 200e-6, 0.9973),
                   CalibrateSpectrum(ring, FormMeasure::kRoundness, 200e-6, 0.9973, full_exact)));
}

// A tabulated calibration is the Monte Carlo's own, bit for bit, at any tolerance: every
// row drawn again.
TEST(CalibrateSpectrum, EveryTabulatedCalibrationIsTheMonteCarlosBitForBit) {
  CalibrationOptions drawn;
  drawn.tabulated = false;
  ASSERT_FALSE(TabulatedCalibrations().empty());
  for (const TabulatedCalibration& row : TabulatedCalibrations()) {
    for (const double tolerance : {1.0, 200e-6, 10e-6}) {
      const SpectrumCalibration a = CalibrateSpectrum(row.shape, row.measure, tolerance, row.coverage);
      const SpectrumCalibration b = CalibrateSpectrum(row.shape, row.measure, tolerance, row.coverage, drawn);
      SCOPED_TRACE(::testing::Message() << row.shape.min_order << ".." << row.shape.max_order << " "
                                        << FormMeasureName(row.measure) << " t " << tolerance);
      EXPECT_EQ(a.scale, b.scale);
      EXPECT_EQ(a.unit_quantile, b.unit_quantile);
      EXPECT_EQ(a.unit_quantile_low, b.unit_quantile_low);
      EXPECT_EQ(a.unit_quantile_high, b.unit_quantile_high);
      EXPECT_EQ(a.draws, b.draws);
    }
  }
}

// The table's rows are what a campaign file draws unless it says otherwise: the default
// spectra at the default capability.
TEST(CalibrateSpectrum, TheDefaultSpectraAtTheDefaultCapabilityAreTabulated) {
  const auto tabulated = [](const SpectrumShape& shape, FormMeasure measure) {
    const std::span<const TabulatedCalibration> rows = TabulatedCalibrations();
    return std::any_of(rows.begin(), rows.end(), [&](const TabulatedCalibration& row) {
      return row.shape == shape && row.measure == measure && row.coverage == Capability{}.Coverage();
    });
  };
  EXPECT_TRUE(tabulated(RingFormTolerance{}.spectrum, FormMeasure::kRoundness));
  EXPECT_TRUE(tabulated(RollerShapeTolerance{}.form, FormMeasure::kTwoPointVariation));
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
