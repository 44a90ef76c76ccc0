#include "solvers/linear_series.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "solvers/path_kernels.h"

namespace ringtol {
namespace {

using solvers::internal::FoldFor;
using solvers::internal::PaddedAngles;
using solvers::internal::SeriesFold;
using solvers::internal::SumSeries;

// Step counts of every residue modulo four: the smallest that folds, and a few hundred to
// a few thousand (across the phasors' 512-angle anchors and 64-angle blocks), as the
// default campaign's path tolerance picks them.
const std::vector<int> kFoldedSteps = {32,  400, 1024, 3200,   // 4m
                                       17,  401, 1025, 3201,   // 4m + 1
                                       34,  402, 1026, 3202,   // 4m + 2
                                       19,  403, 1027, 3203};  // 4m + 3

// The integer rates fold; the bore's terms and a roller's lobes (rates R / r_b, rarely an
// integer) beside them: rates of both parities, zero, negative, and not integers.
const std::vector<double> kRates = {0.0, 1.0, 2.0, 3.0, 4.0, 7.0, 12.0, 31.0, -5.0, 2.37, 9.81, 14.5};

TEST(SumSeries, FoldsTheIntegerRatesForEveryStepCountWithALaneGroupInTheFold) {
  for (const int steps : kFoldedSteps) {
    EXPECT_EQ(FoldFor(steps), steps % 2 == 0 ? SeriesFold::kQuarter : SeriesFold::kHalf) << steps << " steps";
  }
  // One angle fewer than a lane group in the folded part: every angle is summed.
  const int lanes = static_cast<int>(solvers::path_kernels::kLanes);
  EXPECT_EQ(FoldFor(4 * lanes - 2), SeriesFold::kNone);
  EXPECT_EQ(FoldFor(2 * lanes - 1), SeriesFold::kNone);
}

// Whatever the fold, every angle of every series is its closed form, each term from libm in
// long double and summed in long double.
TEST(SumSeries, EveryAngleEqualsTheTermByTermSumInLongDouble) {
  // Relative to a series' scale sum_p |cosine| + |sine|: each phasor is exact to ~1e-13 of
  // a term (a recurrence restarted from libm every 512 angles), and the fold's extra sum of
  // even and odd parts adds an ulp; ten times that.
  constexpr double kRelativeRoundOff = 1e-12;
  constexpr Eigen::Index kSeries = 3;
  const auto terms = static_cast<Eigen::Index>(kRates.size());
  std::mt19937_64 draws(41);
  std::uniform_real_distribution<double> coefficient(-1.0, 1.0);
  Eigen::MatrixXd cosine(kSeries, terms), sine(kSeries, terms);
  for (Eigen::Index s = 0; s < kSeries; ++s) {
    for (Eigen::Index p = 0; p < terms; ++p) {
      cosine(s, p) = coefficient(draws);
      sine(s, p) = coefficient(draws);
    }
  }
  // A series that only some terms reach, as a contact's sees only the bore's and its roller's.
  cosine.row(2).head(3).setZero();
  sine.row(2).head(3).setZero();
  const auto& kernels = solvers::path_kernels::KernelsFor(solvers::path_kernels::Isa::kBest);
  for (const int steps : kFoldedSteps) {
    std::vector<double> series;
    SumSeries(cosine, sine, kRates, steps, kernels, series);
    const std::size_t padded = PaddedAngles(steps);
    ASSERT_EQ(series.size(), static_cast<std::size_t>(kSeries) * padded);
    for (Eigen::Index s = 0; s < kSeries; ++s) {
      const double scale = cosine.row(s).cwiseAbs().sum() + sine.row(s).cwiseAbs().sum();
      for (int k = 0; k <= steps; ++k) {
        const long double psi = 2.0L * std::numbers::pi_v<long double> * k / steps;
        long double sum = 0.0L;
        for (Eigen::Index p = 0; p < terms; ++p) {
          const long double phase = static_cast<long double>(kRates[static_cast<std::size_t>(p)]) * psi;
          sum += cosine(s, p) * std::cos(phase) + sine(s, p) * std::sin(phase);
        }
        const double value = series[static_cast<std::size_t>(s) * padded + static_cast<std::size_t>(k)];
        ASSERT_NEAR(value, static_cast<double>(sum), kRelativeRoundOff * scale)
            << steps << " steps, series " << s << ", angle " << k;
      }
    }
  }
}

}  // namespace
}  // namespace ringtol
