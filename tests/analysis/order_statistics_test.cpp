#include "analysis/order_statistics.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <limits>
#include <random>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace ringtol::analysis {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// ---------------------------------------------------------------------------------------
// Independent reference for the Binomial(n, p) law: every term exp(log n! - log k! -
// log (n-k)! + k log p + (n-k) log(1-p)) from a table of lgamma, summed in plain double.
// Nothing here goes through Boost.

// ln k! for k = 0..max.
std::vector<double> LogFactorials(std::int64_t max) {
  std::vector<double> table(static_cast<std::size_t>(max + 1));
  for (std::size_t k = 0; k < table.size(); ++k) table[k] = std::lgamma(static_cast<double>(k) + 1.0);
  return table;
}

// x ln y with 0 ln 0 = 0, so p = 0 and p = 1 are handled exactly.
double XLogY(double x, double y) { return x == 0.0 ? 0.0 : x * std::log(y); }

class BinomialReference {
 public:
  BinomialReference(std::int64_t n, double p, const std::vector<double>& log_factorial)
      : n_(n), cdf_(static_cast<std::size_t>(n + 1)), survival_(static_cast<std::size_t>(n + 1)) {
    std::vector<double> pmf(static_cast<std::size_t>(n + 1));
    const double log_n_factorial = log_factorial[static_cast<std::size_t>(n)];
    for (std::int64_t k = 0; k <= n; ++k) {
      const auto i = static_cast<std::size_t>(k);
      pmf[i] = std::exp(log_n_factorial - log_factorial[i] - log_factorial[static_cast<std::size_t>(n - k)] +
                        XLogY(static_cast<double>(k), p) + XLogY(static_cast<double>(n - k), 1.0 - p));
    }
    double below = 0.0;
    for (std::size_t i = 0; i < pmf.size(); ++i) cdf_[i] = (below += pmf[i]);
    double above = 0.0;  // summed from the top: the upper tail keeps its relative accuracy
    for (std::size_t i = pmf.size(); i-- > 0;) {
      survival_[i] = above;
      above += pmf[i];
    }
  }
  // P(B <= k).
  double Cdf(std::int64_t k) const { return k < 0 ? 0.0 : k >= n_ ? 1.0 : cdf_[static_cast<std::size_t>(k)]; }
  // P(B > k).
  double Survival(std::int64_t k) const {
    return k < 0 ? 1.0 : k >= n_ ? 0.0 : survival_[static_cast<std::size_t>(k)];
  }

 private:
  std::int64_t n_;
  std::vector<double> cdf_, survival_;
};

// Accuracy of the reference CDF at n <= 1e6: ln n! <= 1.3e7 there, whose ulp is 1.9e-9;
// glibc's lgamma is good to a few ulps, so the three log-factorials put <= ~2e-8 relative
// error on each term, hence on any partial sum of terms <= 1 (summation adds only
// n eps = 2e-10). 1e-7 is a fivefold margin; it is far below the O(1e-4) step one rank
// moves a tail at the largest n checked.
constexpr double kReferenceCdfTolerance = 1e-7;

// [1, 2, ..., n]: order statistic x_(r) is r itself, so intervals read back as ranks.
std::vector<double> Ranks(std::int64_t n) {
  std::vector<double> x(static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = static_cast<double>(i) + 1.0;
  return x;
}

std::string Case(std::int64_t n, double p, double confidence) {
  std::ostringstream s;
  s << "n = " << n << ", p = " << p << ", confidence = " << confidence;
  return s.str();
}

// The ranks (l, u) of EstimateQuantile against the reference law of B, the number of samples
// below the true p-quantile. x_(l) <= q < x_(u) iff l <= B < u, so
//   lower miss  P(B < l)  = F(l - 1)      <= alpha/2, and l is the LARGEST such rank;
//   upper miss  P(B >= u) = 1 - F(u - 1)  <= alpha/2, and u is the SMALLEST such rank;
//   coverage    F(u - 1) - F(l - 1)       >= confidence.
// The interval is the tightest of the equal-tailed form: a rank moved one step inward puts
// more than alpha/2 in its own tail. That need not drop the TOTAL coverage below confidence,
// because the other tail's slack can absorb it (n = 5, p = 0.5 at 95 %: l = 0, u = 6, and
// [x_(1), +inf) still covers 1 - 1/32 = 0.969; this happens in about half of the grid below),
// so each tail is checked on its own, as the header promises.
::testing::AssertionResult RanksAreTightestEqualTailed(const QuantileEstimate& e, std::int64_t n, double p,
                                                       double confidence, const BinomialReference& law) {
  const double tail = 0.5 * (1.0 - confidence);
  const std::int64_t l = e.lower_rank, u = e.upper_rank;
  auto fail = [&]() {
    return ::testing::AssertionFailure() << Case(n, p, confidence) << ": l = " << l << ", u = " << u << ", F(l-1) = "
                                         << law.Cdf(l - 1) << ", F(l) = " << law.Cdf(l)
                                         << ", 1-F(u-1) = " << law.Survival(u - 1)
                                         << ", 1-F(u-2) = " << law.Survival(u - 2) << ", alpha/2 = " << tail << ": ";
  };
  if (l < 0 || l > n || u < 1 || u > n + 1 || l >= u) return fail() << "ranks out of range";
  if (law.Cdf(l - 1) > tail + kReferenceCdfTolerance) return fail() << "lower tail exceeds alpha/2";
  if (l < n && law.Cdf(l) <= tail - kReferenceCdfTolerance) return fail() << "l + 1 would also do";
  if (law.Survival(u - 1) > tail + kReferenceCdfTolerance) return fail() << "upper tail exceeds alpha/2";
  if (u > 1 && law.Survival(u - 2) <= tail - kReferenceCdfTolerance) return fail() << "u - 1 would also do";
  if (law.Cdf(u - 1) - law.Cdf(l - 1) < confidence - 2.0 * kReferenceCdfTolerance) return fail() << "coverage";
  // Read back through the samples x_(r) = r; rank 0 / n + 1 mean unbounded.
  if (e.interval.lower != (l >= 1 ? static_cast<double>(l) : -kInfinity)) return fail() << "lower != x_(l)";
  if (e.interval.upper != (u <= n ? static_cast<double>(u) : kInfinity)) return fail() << "upper != x_(u)";
  if (e.probability != p || e.confidence != confidence) return fail() << "probability/confidence not echoed";
  return ::testing::AssertionSuccess();
}

constexpr double kProbabilities[] = {0.5, 0.9, 0.99, 0.999};
constexpr double kConfidences[] = {0.95, 0.9};

// ---------------------------------------------------------------------------------------
// 1. Quantile ranks against the exact binomial law.

TEST(EstimateQuantile, RanksAreTheTightestEqualTailedOnesForEveryNUpTo2000) {
  constexpr std::int64_t kMaxN = 2000;
  const std::vector<double> log_factorial = LogFactorials(kMaxN);
  const std::vector<double> samples = Ranks(kMaxN);
  for (const double p : kProbabilities) {
    for (std::int64_t n = 1; n <= kMaxN; ++n) {
      const BinomialReference law(n, p, log_factorial);
      const std::span<const double> sorted(samples.data(), static_cast<std::size_t>(n));
      for (const double confidence : kConfidences) {
        ASSERT_TRUE(RanksAreTightestEqualTailed(EstimateQuantile(sorted, p, confidence), n, p, confidence, law));
      }
    }
  }
}

TEST(EstimateQuantile, RanksAreTheTightestEqualTailedOnesAtLargeN) {
  constexpr std::int64_t kLargeN[] = {4999, 100000, 1000000};
  const std::vector<double> log_factorial = LogFactorials(kLargeN[std::size(kLargeN) - 1]);
  for (const std::int64_t n : kLargeN) {
    const std::vector<double> samples = Ranks(n);
    for (const double p : kProbabilities) {
      const BinomialReference law(n, p, log_factorial);
      for (const double confidence : kConfidences) {
        ASSERT_TRUE(RanksAreTightestEqualTailed(EstimateQuantile(samples, p, confidence), n, p, confidence, law));
      }
    }
  }
}

// An estimate bounded by the order statistics of ranks l and u, whose values are the
// interval's ends.
::testing::Matcher<const QuantileEstimate&> RanksAndInterval(std::int64_t l, std::int64_t u, double lower,
                                                             double upper) {
  return ::testing::AllOf(
      ::testing::Field("lower_rank", &QuantileEstimate::lower_rank, l),
      ::testing::Field("upper_rank", &QuantileEstimate::upper_rank, u),
      ::testing::Field("interval", &QuantileEstimate::interval,
                       ::testing::AllOf(::testing::Field("lower", &Interval::lower, lower),
                                        ::testing::Field("upper", &Interval::upper, upper))));
}

TEST(EstimateQuantile, MedianOfOneHundredUsesTheTextbookRanks40And61) {
  // Bin(100, 1/2): F(39) = 0.0176 <= 0.025 < F(40) = 0.0284 and, by symmetry, P(B > 60) = F(39),
  // P(B > 59) = F(40): the classic [x_(40), x_(61)] (Conover, Practical Nonparametric
  // Statistics, table A3), coverage 1 - 2 F(39).
  const std::vector<double> x = Ranks(100);
  const QuantileEstimate e = EstimateQuantile(x, 0.5, 0.95);
  EXPECT_THAT(e, RanksAndInterval(40, 61, 40.0, 61.0));
}

// The median needs no sorted input: 3, 1, 2 has the middle value 2, and 4, 1, 3, 2 the mean
// of its two middle values (2 + 3) / 2, both exact in binary.
TEST(Median, IsTheMiddleValueOrTheMeanOfTheTwoMiddleOnesOfUnsortedValues) {
  EXPECT_EQ(Median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(Median({4.0, 1.0, 3.0, 2.0}), 2.5);
  EXPECT_EQ(Median({7.0}), 7.0);
  EXPECT_EQ(Median({4.0, 1.0, 3.0, 2.0}), EstimateQuantile(std::vector<double>{1.0, 2.0, 3.0, 4.0}, 0.5).value);
  EXPECT_TRUE(std::isnan(Median({})));
}

TEST(EstimateQuantile, SampleRangeOfSixIsTheSmallestFiniteMedianIntervalAt95Percent) {
  // n = 5: P(B = 0) = 1/32 = 0.031 > 0.025, so neither side can be bounded; n = 6: 1/64 <= 0.025,
  // and [x_(1), x_(6)] covers the median with probability 1 - 2/64.
  const std::vector<double> five = Ranks(5), six = Ranks(6);
  const QuantileEstimate e5 = EstimateQuantile(five, 0.5, 0.95);
  EXPECT_THAT(e5, RanksAndInterval(0, 6, -kInfinity, kInfinity));
  const QuantileEstimate e6 = EstimateQuantile(six, 0.5, 0.95);
  EXPECT_THAT(e6, RanksAndInterval(1, 6, 1.0, 6.0));
}

TEST(EstimateQuantile, TooFewSamplesLeaveTheFarSideUnbounded) {
  const std::vector<double> x = Ranks(10);
  // p = 0.99: P(B >= 10) = 0.99^10 = 0.904 > 0.025, so no x_(u) bounds the 99 % quantile above.
  // Below: F(8) = 1 - 0.99^10 - 10 0.99^9 0.01 = 0.0043 <= 0.025 < F(9) = 1 - 0.99^10 = 0.096.
  const QuantileEstimate high = EstimateQuantile(x, 0.99, 0.95);
  EXPECT_THAT(high, RanksAndInterval(9, 11, 9.0, kInfinity));
  // p = 0.01 is the mirror image: l = 0 (P(B = 0) = 0.904), u = 2 (P(B > 1) = 0.0043).
  const QuantileEstimate low = EstimateQuantile(x, 0.01, 0.95);
  EXPECT_THAT(low, RanksAndInterval(0, 2, -kInfinity, 2.0));
  // One sample bounds nothing at any useful level: F(0) = 1 - p > alpha/2 and P(B > 0) = p > alpha/2.
  const std::vector<double> one = {3.0};
  const QuantileEstimate single = EstimateQuantile(one, 0.5, 0.9);
  EXPECT_THAT(single, RanksAndInterval(0, 2, -kInfinity, kInfinity));
  EXPECT_EQ(single.value, 3.0);
}

// ---------------------------------------------------------------------------------------
// 2. Coverage by simulation.

// P(X <= k) and P(X >= k) for X ~ Binomial(trials, q), from the reference.
double BinomialAtMost(std::int64_t k, std::int64_t trials, double q, const std::vector<double>& log_factorial) {
  return BinomialReference(trials, q, log_factorial).Cdf(k);
}
double BinomialAtLeast(std::int64_t k, std::int64_t trials, double q, const std::vector<double>& log_factorial) {
  return BinomialReference(trials, q, log_factorial).Survival(k - 1);
}

TEST(EstimateQuantile, SimulatedCoverageOfExponentialQuantilesIsAtLeastNominal) {
  // Samples from Exp(rate) by inverse CDF, x = -ln(1 - U) / rate; true quantile
  // q_p = -ln(1 - p) / rate. The method is distribution-free, so any continuous law will do.
  // For each (n, p), R replications give H hits ~ Binomial(R, c) with c the true coverage.
  //   (a) one-sided exact binomial test of H0: c >= confidence (reject if P(X <= H | confidence)
  //       is small): the method must not under-cover;
  //   (b) two-sided exact binomial test of H0: c = P(l <= B < u) from the reference law at the
  //       ranks returned: the simulation must agree with the order-statistic theory.
  // Family-wise significance 1e-3, Bonferroni over 2 tests x 9 cases: each at 1e-3 / 18.
  // Power: at R = 2000 a true coverage of 0.93 lies 4.1 sigma below 0.95 (sigma = 0.0049),
  // beyond the one-sided critical 3.9 sigma at 5.6e-5, so such an under-coverage is caught.
  constexpr double kRate = 2.5;        // [1/unit], arbitrary
  constexpr double kConfidence = 0.95;
  constexpr std::int64_t kReplications = 2000;
  constexpr std::int64_t kSizes[] = {20, 100, 500};
  constexpr double kQuantiles[] = {0.5, 0.9, 0.99};
  constexpr double kFamilyAlpha = 1e-3;
  constexpr double kTestAlpha = kFamilyAlpha / (2.0 * static_cast<double>(std::size(kSizes) * std::size(kQuantiles)));

  const std::vector<double> log_factorial = LogFactorials(std::max<std::int64_t>(kReplications, 500));
  std::uint64_t seed = 20240611;
  for (const std::int64_t n : kSizes) {
    for (const double p : kQuantiles) {
      SCOPED_TRACE(Case(n, p, kConfidence));
      const double truth = -std::log1p(-p) / kRate;
      std::mt19937_64 rng(seed++);
      std::uniform_real_distribution<double> uniform(0.0, 1.0);
      std::vector<double> x(static_cast<std::size_t>(n));
      std::int64_t hits = 0;
      std::int64_t lower_rank = -1, upper_rank = -1;
      for (std::int64_t r = 0; r < kReplications; ++r) {
        for (double& xi : x) xi = -std::log1p(-uniform(rng)) / kRate;
        std::sort(x.begin(), x.end());
        const QuantileEstimate e = EstimateQuantile(x, p, kConfidence);
        if (e.interval.lower <= truth && truth <= e.interval.upper) ++hits;
        lower_rank = e.lower_rank;  // depend on (n, p, confidence) only
        upper_rank = e.upper_rank;
      }
      const BinomialReference law(n, p, log_factorial);
      const double exact = law.Cdf(upper_rank - 1) - law.Cdf(lower_rank - 1);
      const double below_nominal = BinomialAtMost(hits, kReplications, kConfidence, log_factorial);
      EXPECT_GT(below_nominal, kTestAlpha) << hits << " hits in " << kReplications << ", exact coverage " << exact;
      const double two_sided = 2.0 * std::min(BinomialAtMost(hits, kReplications, exact, log_factorial),
                                              BinomialAtLeast(hits, kReplications, exact, log_factorial));
      EXPECT_GT(two_sided, kTestAlpha) << hits << " hits in " << kReplications << ", exact coverage " << exact;
    }
  }
}

// ---------------------------------------------------------------------------------------
// 3. Clopper-Pearson proportions.

// Boost's inverse incomplete beta is good to a few ulps in p (~1e-15); |dP/dp| <= n = 1000
// makes that <= 1e-12 in a tail probability, and the reference sum adds ~n eps = 2e-13.
// Tenfold margin.
constexpr double kTailProbabilityTolerance = 1e-11;

TEST(EstimateProportion, EndpointsSolveTheClopperPearsonTailEquations) {
  // L(k) solves P(X >= k | L) = alpha/2 and U(k) solves P(X <= k | U) = alpha/2 (k = 0 and
  // k = n take L = 0 and U = 1). A wrong beta parameter or tail breaks these at once.
  const std::vector<double> log_factorial = LogFactorials(1000);
  for (const double confidence : {0.95, 0.9, 0.99}) {
    const double tail = 0.5 * (1.0 - confidence);
    for (const std::int64_t n : {1, 2, 3, 7, 10, 31, 100, 250, 1000}) {
      for (std::int64_t k = 0; k <= n; ++k) {
        SCOPED_TRACE(::testing::Message() << k << " in " << n << ", confidence = " << confidence);
        const ProportionEstimate e = EstimateProportion(k, n, confidence);
        ASSERT_EQ(e.successes, k);
        ASSERT_EQ(e.trials, n);
        ASSERT_EQ(e.confidence, confidence);
        ASSERT_EQ(e.value, static_cast<double>(k) / static_cast<double>(n));
        ASSERT_LE(e.interval.lower, e.value);
        ASSERT_GE(e.interval.upper, e.value);
        if (k > 0) {
          ASSERT_GT(e.interval.lower, 0.0);
          const double upper_tail = BinomialReference(n, e.interval.lower, log_factorial).Survival(k - 1);
          ASSERT_NEAR(upper_tail, tail, kTailProbabilityTolerance);
        }
        if (k < n) {
          ASSERT_LT(e.interval.upper, 1.0);
          const double lower_tail = BinomialReference(n, e.interval.upper, log_factorial).Cdf(k);
          ASSERT_NEAR(lower_tail, tail, kTailProbabilityTolerance);
        }
      }
    }
  }
}

TEST(EstimateProportion, ExactCoverageIsAtLeastConfidenceForEveryTrueProportion) {
  // Coverage(p) = sum of Binomial(n, p) pmf over the k whose interval holds p. It is piecewise
  // smooth, jumping down just outside each endpoint, so besides a uniform grid it is evaluated
  // one ulp beyond every endpoint, where it comes closest to the confidence.
  constexpr int kGrid = 199;
  const std::vector<double> log_factorial = LogFactorials(1000);
  for (const double confidence : {0.95, 0.9}) {
    for (const std::int64_t n : {1, 2, 3, 4, 5, 6, 8, 10, 13, 20, 29, 50, 100, 333, 1000}) {
      std::vector<Interval> intervals;
      for (std::int64_t k = 0; k <= n; ++k) intervals.push_back(EstimateProportion(k, n, confidence).interval);
      std::vector<double> probes;
      for (int i = 1; i <= kGrid; ++i) probes.push_back(static_cast<double>(i) / (kGrid + 1));
      for (const Interval& interval : intervals) {
        if (interval.lower > 0.0) probes.push_back(std::nextafter(interval.lower, 0.0));
        if (interval.upper < 1.0) probes.push_back(std::nextafter(interval.upper, 1.0));
      }
      double worst = 1.0, worst_p = 0.0;
      for (const double p : probes) {
        const BinomialReference law(n, p, log_factorial);
        double coverage = 0.0;
        for (std::int64_t k = 0; k <= n; ++k) {
          const Interval& interval = intervals[static_cast<std::size_t>(k)];
          if (interval.lower <= p && p <= interval.upper) coverage += law.Cdf(k) - law.Cdf(k - 1);
        }
        if (coverage < worst) {
          worst = coverage;
          worst_p = p;
        }
      }
      // Both tails at most alpha/2, each to the tail-equation tolerance.
      EXPECT_GE(worst, confidence - 2.0 * kTailProbabilityTolerance)
          << "n = " << n << ", worst at p = " << worst_p << ", confidence = " << confidence;
    }
  }
}

TEST(EstimateProportion, NoOrAllSuccessesPinOneEndAndHaveTheClosedFormOther) {
  // k = 0: P(X <= 0 | U) = (1 - U)^n = alpha/2, so U = 1 - (alpha/2)^(1/n); k = n mirrors it,
  // L = (alpha/2)^(1/n). Both computed as exp(ln(alpha/2) / n): pow/expm1 are within 1 ulp and
  // Boost's inverse beta within a few; 8 ulp relative.
  constexpr double kClosedFormRelativeTolerance = 8.0 * kEps;
  for (const double confidence : {0.95, 0.9, 0.99}) {
    const double tail = 0.5 * (1.0 - confidence);
    for (const std::int64_t n : {1, 2, 10, 57, 1000, 1000000}) {
      SCOPED_TRACE(::testing::Message() << "n = " << n << ", confidence = " << confidence);
      const double root = std::log(tail) / static_cast<double>(n);
      const ProportionEstimate none = EstimateProportion(0, n, confidence);
      EXPECT_EQ(none.value, 0.0);
      EXPECT_EQ(none.interval.lower, 0.0);
      const double none_upper = -std::expm1(root);
      EXPECT_NEAR(none.interval.upper, none_upper, kClosedFormRelativeTolerance * none_upper);
      const ProportionEstimate all = EstimateProportion(n, n, confidence);
      EXPECT_EQ(all.value, 1.0);
      EXPECT_EQ(all.interval.upper, 1.0);
      const double all_lower = std::exp(root);
      EXPECT_NEAR(all.interval.lower, all_lower, kClosedFormRelativeTolerance * all_lower);
    }
  }
}

TEST(EstimateProportion, NoSuccessInTenTrialsGivesTheTextbookUpperBound) {
  // 1 - 0.025^(1/10) = 0.3085 at 95 % (e.g. Clopper & Pearson's charts, or any table of exact
  // binomial limits), printed to four decimals: half a unit in the fourth decimal.
  constexpr double kFourDecimals = 0.5e-4;
  const ProportionEstimate e = EstimateProportion(0, 10, 0.95);
  EXPECT_NEAR(e.interval.upper, 0.3085, kFourDecimals);
  EXPECT_EQ(e.interval.lower, 0.0);
  // Mirror: ten in ten gives 0.025^(1/10) = 0.6915 below.
  EXPECT_NEAR(EstimateProportion(10, 10, 0.95).interval.lower, 0.6915, kFourDecimals);
}

// ---------------------------------------------------------------------------------------
// 4. The sample quantile (Hyndman & Fan type 7, numpy's and R's default).

// h = (n - 1) p is rounded once (relative eps), which the slope |x_(j+1) - x_(j)| <= max |x|
// carries into the value; the product and the sum round once more each: 4 ulp of max |x|.
constexpr double kInterpolationRelativeTolerance = 4.0 * kEps;

TEST(EstimateQuantile, ValueInterpolatesLinearlyBetweenOrderStatisticsLikeNumpy) {
  struct Expected {
    std::vector<double> sorted;
    double p;
    double value;  // by hand: h = (n - 1) p, x_[floor h] + (h - floor h)(x_[floor h + 1] - x_[floor h])
  };
  const std::vector<Expected> cases = {
      {{1, 2, 3, 4}, 0.5, 2.5},       // h = 1.5
      {{1, 2, 3, 4}, 0.25, 1.75},     // h = 0.75
      {{1, 2, 3, 4}, 0.75, 3.25},     // h = 2.25
      {{1, 2, 3, 4}, 0.1, 1.3},       // h = 0.3
      {{1, 2, 3, 4}, 0.9, 3.7},       // h = 2.7
      {{10, 20, 30, 40, 50}, 0.5, 30},  // h = 2: an order statistic itself
      {{10, 20, 30, 40, 50}, 0.3, 22},  // h = 1.2
      {{0, 1, 10, 100}, 0.5, 5.5},     // h = 1.5, uneven spacing
      {{0, 1, 10, 100}, 0.8, 46},      // h = 2.4
      {{-3, -1}, 0.25, -2.5},          // h = 0.25
      {{7}, 0.5, 7},                   // one sample is every quantile
      {{7}, 0.999, 7},
  };
  for (const Expected& c : cases) {
    const double scale = std::max(std::abs(c.sorted.front()), std::abs(c.sorted.back()));
    EXPECT_NEAR(EstimateQuantile(c.sorted, c.p).value, c.value, kInterpolationRelativeTolerance * scale)
        << "n = " << c.sorted.size() << ", p = " << c.p;
  }
}

TEST(EstimateQuantile, ValueTendsToTheExtremeOrderStatisticsAtTheEndsOfTheUnitInterval) {
  // p one ulp inside (0, 1): h = (n - 1) p sits within rounding of 0 or n - 1, and the value
  // must be x_(1) or x_(n) to the interpolation tolerance, without reading past either end
  // (the sanitizer build would catch such a read; for n = 1 the upper neighbour is clamped).
  const std::vector<double> x = {1.0, 2.0, 3.0, 4.0};
  EXPECT_NEAR(EstimateQuantile(x, std::nextafter(1.0, 0.0)).value, x.back(), kInterpolationRelativeTolerance * x.back());
  EXPECT_NEAR(EstimateQuantile(x, std::numeric_limits<double>::denorm_min()).value, x.front(),
              kInterpolationRelativeTolerance * x.back());
  const std::vector<double> one = {-2.0};
  EXPECT_EQ(EstimateQuantile(one, std::nextafter(1.0, 0.0)).value, -2.0);
}

// ---------------------------------------------------------------------------------------
// 5. Bad input.

TEST(EstimateQuantile, RejectsEmptySamplesAndProbabilitiesOrConfidencesOutsideTheOpenUnitInterval) {
  const std::vector<double> x = {1.0, 2.0, 3.0};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT([] { EstimateQuantile(std::span<const double>(), 0.5); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("no samples")));
  for (const double p : {0.0, 1.0, -0.1, 1.5, nan, kInfinity}) {
    EXPECT_THAT([&] { EstimateQuantile(x, p); }, ThrowsMessage<std::invalid_argument>(HasSubstr("allowed (0, 1)")))
        << "p = " << p;
  }
  for (const double confidence : {0.0, 1.0, -0.5, 95.0, nan}) {
    EXPECT_THAT([&] { EstimateQuantile(x, 0.5, confidence); },
                ThrowsMessage<std::invalid_argument>(HasSubstr("confidence")))
        << "confidence = " << confidence;
  }
}

TEST(EstimateProportion, RejectsImpossibleCountsAndConfidencesOutsideTheOpenUnitInterval) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THAT([] { EstimateProportion(11, 10); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("11 successes in 10 trials")));
  EXPECT_THROW(EstimateProportion(-1, 10), std::invalid_argument);
  EXPECT_THROW(EstimateProportion(0, 0), std::invalid_argument);
  EXPECT_THROW(EstimateProportion(0, -3), std::invalid_argument);
  for (const double confidence : {0.0, 1.0, -0.5, 95.0, nan}) {
    EXPECT_THAT([&] { EstimateProportion(3, 10, confidence); },
                ThrowsMessage<std::invalid_argument>(HasSubstr("confidence")))
        << "confidence = " << confidence;
  }
}

}  // namespace
}  // namespace ringtol::analysis
