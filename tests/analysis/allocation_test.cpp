#include "analysis/allocation.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iostream>
#include <limits>
#include <optional>
#include <random>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "analysis/order_statistics.h"
#include "tests/support/statistics.h"

namespace ringtol::analysis {
namespace {

using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---------------------------------------------------------------------------------------
// A toy allocation whose every verdict is known exactly: component c at option o
// contributes a spread s_c[o] that falls as the option tightens, the output is their
// root sum of squares f = sqrt(sum_c s_c^2), and the candidate is feasible when f <=
// limit - band, infeasible when f >= limit + band and undecided between (the band plays
// the confidence interval straddling the limit). Both monotone facts hold exactly.

// Portable draws from a fixed seed: the raw 64-bit output, never a library distribution.
class Draws {
 public:
  explicit Draws(std::uint64_t seed) : engine_(seed) {}
  double Unit() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  int Below(int n) { return static_cast<int>(engine_() % static_cast<std::uint64_t>(n)); }

 private:
  std::mt19937_64 engine_;
};

struct Toy {
  std::vector<std::vector<double>> costs;
  std::vector<std::vector<double>> spread;
  double limit = 0.0;
  double band = 0.0;
};

// Costs nondecreasing per component: integer steps (many ties, which test the tie rule)
// for even tables, real steps for odd ones. The limit is the output of a random candidate,
// so the optimum lies anywhere in the space.
Toy MakeToy(const std::vector<int>& shape, std::uint64_t seed, double band_fraction = 0.0) {
  Draws draws(seed);
  Toy toy;
  const bool integer_costs = seed % 2 == 0;
  for (const int options : shape) {
    std::vector<double> cost;
    std::vector<double> spread;
    double c = integer_costs ? draws.Below(4) : draws.Unit();
    double s = 1.0 + draws.Unit();
    for (int o = 0; o < options; ++o) {
      cost.push_back(c);
      spread.push_back(s);
      c += integer_costs ? draws.Below(4) : 3.0 * draws.Unit();
      s *= 0.5 + 0.45 * draws.Unit();
    }
    toy.costs.push_back(cost);
    toy.spread.push_back(spread);
  }
  std::vector<int> at(shape.size());
  double sum = 0.0;
  for (std::size_t c = 0; c < shape.size(); ++c) {
    const double s = toy.spread[c][static_cast<std::size_t>(draws.Below(shape[c]))];
    sum += s * s;
  }
  toy.limit = std::sqrt(sum);
  toy.band = band_fraction * toy.limit;
  return toy;
}

double Output(const Toy& toy, const AllocationSpace& space, std::int64_t candidate) {
  const std::vector<int> options = space.Options(candidate);
  double sum = 0.0;
  for (std::size_t c = 0; c < options.size(); ++c) {
    const double s = toy.spread[c][static_cast<std::size_t>(options[c])];
    sum += s * s;
  }
  return std::sqrt(sum);
}

Verdict ToyVerdict(const Toy& toy, const AllocationSpace& space, std::int64_t candidate) {
  const double f = Output(toy, space, candidate);
  if (f <= toy.limit - toy.band) return Verdict::kFeasible;
  if (f >= toy.limit + toy.band) return Verdict::kInfeasible;
  return Verdict::kUndecided;
}

// The cheapest feasible candidate by brute force, ties to the lower index.
std::optional<std::int64_t> CheapestFeasible(const Toy& toy, const AllocationSpace& space) {
  std::optional<std::int64_t> best;
  for (std::int64_t x = 0; x < space.size(); ++x) {
    if (ToyVerdict(toy, space, x) != Verdict::kFeasible) continue;
    if (!best || space.Cost(x) < space.Cost(*best)) best = x;
  }
  return best;
}

struct SearchRun {
  std::optional<std::int64_t> best;
  std::int64_t simulated = 0;
  std::vector<std::vector<std::int64_t>> batches;
};

// Drives a search to its end as the allocation driver does, checking the batch contract
// on the way; `reverse` reports each batch's verdicts last first.
SearchRun Drive(AllocationSearch& search, const SearchOptions& options,
          const std::function<Verdict(std::int64_t)>& oracle, bool reverse = false) {
  SearchRun run;
  std::set<std::int64_t> asked;
  while (!search.done()) {
    std::vector<std::int64_t> batch = search.Next();
    EXPECT_FALSE(batch.empty());
    EXPECT_LE(batch.size(), static_cast<std::size_t>(options.batch));
    EXPECT_TRUE(std::is_sorted(batch.begin(), batch.end()));
    for (const std::int64_t x : batch) EXPECT_TRUE(asked.insert(x).second) << "candidate " << x << " asked twice";
    run.batches.push_back(batch);
    if (reverse) std::reverse(batch.begin(), batch.end());
    for (const std::int64_t x : batch) search.Report(x, oracle(x));
  }
  EXPECT_TRUE(search.Next().empty());
  run.best = search.best();
  run.simulated = search.simulated();
  return run;
}

SearchRun Search(const Toy& toy, SearchOptions options, bool reverse = false) {
  const AllocationSpace space(toy.costs);
  AllocationSearch search(space, options);
  return Drive(search, options, [&](std::int64_t x) { return ToyVerdict(toy, space, x); }, reverse);
}

const std::vector<std::vector<int>> kShapes = {{5, 5, 5, 2}, {10, 10, 10, 10}, {3, 7}, {4}, {2, 3, 2, 3, 2}};
constexpr int kTables = 200;

// ---------------------------------------------------------------------------------------
// The candidates and their costs.

TEST(AllocationSpace, MixedRadixRoundTripsWithTheLastComponentFastest) {
  const AllocationSpace space({{0.0, 1.0, 2.0}, {0.0, 1.0, 1.0, 5.0}, {1.0, 2.0}});
  ASSERT_EQ(space.size(), 24);
  EXPECT_EQ(space.Options(0), (std::vector<int>{0, 0, 0}));
  EXPECT_EQ(space.Options(1), (std::vector<int>{0, 0, 1}));
  EXPECT_EQ(space.Options(2), (std::vector<int>{0, 1, 0}));
  EXPECT_EQ(space.Options(23), (std::vector<int>{2, 3, 1}));
  for (std::int64_t x = 0; x < space.size(); ++x) EXPECT_EQ(space.Candidate(space.Options(x)), x);
  EXPECT_EQ(space.Cost(23), 2.0 + 5.0 + 2.0);
  EXPECT_TRUE(space.AtLeastAsTight(23, 0));
  EXPECT_TRUE(space.AtLeastAsTight(5, 5));
  EXPECT_FALSE(space.AtLeastAsTight(0, 1));
  // {0, 3, 0} against {1, 0, 0}: tighter in one component, looser in the other.
  EXPECT_FALSE(space.AtLeastAsTight(6, 8));
  EXPECT_FALSE(space.AtLeastAsTight(8, 6));
}

TEST(AllocationSpace, RejectsBadCostTablesNamingComponentAndOption) {
  using Costs = std::vector<std::vector<double>>;
  EXPECT_THAT([] { AllocationSpace(Costs{}); }, ThrowsMessage<std::invalid_argument>(HasSubstr("no component")));
  EXPECT_THAT([] { AllocationSpace(Costs{{1.0}, {}}); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("component 1 has no option")));
  EXPECT_THAT([] { AllocationSpace(Costs{{1.0, -1.0}}); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("component 0, option 1")));
  EXPECT_THAT([] { AllocationSpace(Costs{{1.0}, {0.0, kNaN}}); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("component 1, option 1")));
  EXPECT_THAT([] { AllocationSpace(Costs{{kInfinity}}); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("component 0, option 0")));
  EXPECT_THAT([] { AllocationSpace(Costs{{0.0, 1.0}, {1.0, 3.0, 2.0}}); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("component 1, option 2")));
}

TEST(CostModel, EvaluatesBothFormsAndDoublesTheDefaultCostPerHalving) {
  EXPECT_EQ((CostModel{CostForm::kReciprocalPower, 0.5, 2.0, 2.0}.Cost(4.0)), 0.5 + 2.0 / 16.0);
  EXPECT_DOUBLE_EQ((CostModel{CostForm::kExponential, 1.0, 3.0, 0.5}.Cost(2.0)), 1.0 + 3.0 * std::exp(-1.0));
  const CostModel standard;
  EXPECT_EQ(standard.Cost(5.0), 2.0 * standard.Cost(10.0));
}

TEST(CostModel, RejectsNonPositiveTolerancesAndParametersOutOfRange) {
  const CostModel standard;
  for (const double t : {0.0, -1.0, kNaN, kInfinity}) {
    EXPECT_THAT([&] { (void)standard.Cost(t); }, ThrowsMessage<std::invalid_argument>(HasSubstr("tolerance")));
  }
  for (const CostModel bad : {CostModel{CostForm::kReciprocalPower, -1.0, 1.0, 1.0},
                              CostModel{CostForm::kExponential, 0.0, 0.0, 1.0},
                              CostModel{CostForm::kReciprocalPower, 0.0, 1.0, 0.0}}) {
    EXPECT_THAT([&] { (void)bad.Cost(1.0); }, ThrowsMessage<std::invalid_argument>(HasSubstr("allowed a >= 0")));
  }
}

// ---------------------------------------------------------------------------------------
// Judgement.

std::vector<double> Spaced(int n, double from, double to) {
  std::vector<double> values;
  for (int i = 0; i < n; ++i) values.push_back(from + (to - from) * i / std::max(1, n - 1));
  return values;
}

ConstraintJudgement JudgeAccurate(const Constraint& constraint, const std::vector<double>& values,
                                  double confidence = 0.95) {
  return JudgeConstraint(constraint, values, values, values, confidence);
}

TEST(JudgeConstraint, QuantileFarFromTheLimitIsDecidedOnceTheIntervalIsBounded) {
  // The upper end of the 0.99-quantile's 95 % interval exists once 0.99^n <= 0.025:
  // n >= ln 0.025 / ln 0.99 = 367.04, so 368 samples.
  const Constraint constraint{"runout_mm", ConstraintKind::kQuantile, 0.99, 10.0};
  const auto bounded = static_cast<int>(std::ceil(std::log(0.025) / std::log(0.99)));
  ASSERT_EQ(bounded, 368);
  const ConstraintJudgement too_few = JudgeAccurate(constraint, Spaced(bounded - 1, 0.0, 1.0));
  EXPECT_EQ(too_few.verdict, Verdict::kUndecided);
  EXPECT_EQ(too_few.interval.upper, kInfinity);
  EXPECT_EQ(too_few.samples_to_decide, bounded);
  const ConstraintJudgement below = JudgeAccurate(constraint, Spaced(bounded, 0.0, 1.0));
  EXPECT_EQ(below.verdict, Verdict::kFeasible);
  EXPECT_EQ(below.samples, bounded);
  EXPECT_EQ(below.samples_to_decide, 0);
  EXPECT_EQ(below.interval.upper, 1.0);
  const std::vector<double> above = Spaced(bounded, 20.0, 21.0);
  const ConstraintJudgement high = JudgeAccurate(constraint, above);
  EXPECT_EQ(high.verdict, Verdict::kInfeasible);
  EXPECT_EQ(high.estimate, EstimateQuantile(above, 0.99).value);
  EXPECT_EQ(high.interval.lower, EstimateQuantile(above, 0.99).interval.lower);
}

TEST(JudgeConstraint, YieldWithoutFailuresIsFeasibleExactlyFromTheClopperPearsonSampleCount) {
  // With n of n within, the Clopper-Pearson lower bound is ((1 - confidence)/2)^(1/n):
  // feasible for level 0.9973 once n >= ln 0.025 / ln 0.9973 = 1364.4.
  const Constraint constraint{"runout_mm", ConstraintKind::kYield, 0.9973, 1.0};
  const auto n = static_cast<int>(std::ceil(std::log(0.025) / std::log(0.9973)));
  ASSERT_EQ(n, 1365);
  EXPECT_EQ(JudgeAccurate(constraint, Spaced(n, 0.0, 0.5)).verdict, Verdict::kFeasible);
  const ConstraintJudgement short_by_one = JudgeAccurate(constraint, Spaced(n - 1, 0.0, 0.5));
  EXPECT_EQ(short_by_one.verdict, Verdict::kUndecided);
  EXPECT_EQ(short_by_one.estimate, 1.0);
  EXPECT_EQ(short_by_one.interval.upper, 1.0);
  const std::vector<double> beyond(static_cast<std::size_t>(n), 2.0);
  EXPECT_EQ(JudgeAccurate(constraint, beyond).verdict, Verdict::kInfeasible);
}

// JudgeYield on counts is JudgeConstraint's yield: the same verdict, interval and samples
// to decide on the samples the counts describe, and pass exactly from the Clopper-Pearson
// count.
TEST(JudgeYield, IsTheConstraintsYieldOnItsCounts) {
  const Constraint constraint{"runout_mm", ConstraintKind::kYield, 0.99, 1.0};
  for (const auto& [within, n] : {std::pair{1024, 1024}, {1015, 1024}, {900, 1000}, {5, 5}}) {
    SCOPED_TRACE(std::to_string(within) + " of " + std::to_string(n));
    std::vector<double> values(static_cast<std::size_t>(n), 2.0);
    std::fill_n(values.begin(), within, 0.5);
    const ConstraintJudgement expected = JudgeAccurate(constraint, values);
    const ConstraintJudgement counted = JudgeYield({within, within, within, n}, 0.99, 0.95);
    EXPECT_EQ(counted.verdict, expected.verdict);
    EXPECT_EQ(counted.estimate, expected.estimate);
    EXPECT_EQ(counted.interval.lower, expected.interval.lower);
    EXPECT_EQ(counted.interval.upper, expected.interval.upper);
    EXPECT_EQ(counted.samples_to_decide, expected.samples_to_decide);
  }
  // n of n within passes from n >= ln 0.025 / ln 0.99 = 367.04.
  EXPECT_EQ(JudgeYield({368, 368, 368, 368}, 0.99, 0.95).verdict, Verdict::kFeasible);
  EXPECT_EQ(JudgeYield({367, 367, 367, 367}, 0.99, 0.95).verdict, Verdict::kUndecided);
  EXPECT_EQ(JudgeYield({900, 900, 900, 1000}, 0.99, 0.95).verdict, Verdict::kInfeasible);
  EXPECT_GT(JudgeYield({1015, 1015, 1015, 1024}, 0.99, 0.95).samples_to_decide, 1024);
  EXPECT_THROW(JudgeYield({5, 4, 5, 10}, 0.99, 0.95), std::invalid_argument);
  EXPECT_THROW(JudgeYield({0, 0, 0, 0}, 0.99, 0.95), std::invalid_argument);
  EXPECT_THROW(JudgeYield({1, 1, 1, 1}, 1.0, 0.95), std::invalid_argument);
}

TEST(JudgeConstraint, FailedSamplesCountAsBeyondTheLimit) {
  // 1000 samples all within: the 0.99 quantile is bounded (n >= 368) and the yield's lower
  // bound 0.025^(1/1000) = 0.9963 clears 0.99. Failing 50 of them puts ranks 951..1000
  // at +inf, above the quantile's lower rank (about 990 - 2 sqrt(9.9)), and caps the
  // yield's upper bound near 0.95 + 2 sqrt(0.95 0.05 / 1000) = 0.964.
  std::vector<double> values = Spaced(1000, 0.0, 0.5);
  const Constraint quantile{"runout_mm", ConstraintKind::kQuantile, 0.99, 1.0};
  const Constraint yield{"runout_mm", ConstraintKind::kYield, 0.99, 1.0};
  EXPECT_EQ(JudgeAccurate(quantile, values).verdict, Verdict::kFeasible);
  EXPECT_EQ(JudgeAccurate(yield, values).verdict, Verdict::kFeasible);
  for (std::size_t i = 0; i < values.size(); i += 20) values[i] = kNaN;
  const ConstraintJudgement q = JudgeAccurate(quantile, values);
  EXPECT_EQ(q.verdict, Verdict::kInfeasible);
  EXPECT_EQ(q.estimate, kInfinity);
  const ConstraintJudgement y = JudgeAccurate(yield, values);
  EXPECT_EQ(y.verdict, Verdict::kInfeasible);
  EXPECT_EQ(y.estimate, 0.95);
}

TEST(JudgeConstraint, ScreenedIntervalsStraddlingTheLimitLeaveTheVerdictUndecided) {
  const std::vector<double> values = Spaced(1000, 0.0, 0.9);
  constexpr double kBound = 0.2;  // a screen's error bound wider than the 0.1 margin to the limit
  std::vector<double> lower;
  std::vector<double> upper;
  for (const double v : values) {
    lower.push_back(v - kBound);
    upper.push_back(v + kBound);
  }
  const Constraint quantile{"d_trajectory_mm", ConstraintKind::kQuantile, 0.99, 1.0};
  EXPECT_EQ(JudgeAccurate(quantile, values).verdict, Verdict::kFeasible);
  const ConstraintJudgement screened = JudgeConstraint(quantile, values, lower, upper, 0.95);
  EXPECT_EQ(screened.verdict, Verdict::kUndecided);
  EXPECT_EQ(screened.estimate, EstimateQuantile(values, 0.99).value);
  EXPECT_LT(screened.interval.lower, quantile.upper);
  EXPECT_GT(screened.interval.upper, quantile.upper);

  const std::vector<double> within(1000, 0.9);
  const Constraint yield{"d_trajectory_mm", ConstraintKind::kYield, 0.9, 1.0};
  std::vector<double> yield_lower(within.size(), 0.9 - kBound);
  std::vector<double> yield_upper(within.size(), 0.9 + kBound);
  EXPECT_EQ(JudgeAccurate(yield, within).verdict, Verdict::kFeasible);
  const ConstraintJudgement screened_yield = JudgeConstraint(yield, within, yield_lower, yield_upper, 0.95);
  EXPECT_EQ(screened_yield.verdict, Verdict::kUndecided);
  EXPECT_EQ(screened_yield.interval.lower, 0.0);
  EXPECT_EQ(screened_yield.interval.upper, 1.0);
}

TEST(JudgeConstraint, SamplesToDecideShrinksTheHalfWidthFacingTheLimitToTheMargin) {
  // 95 of 100 within, level 0.9: the estimate 0.95 clears the level by 0.05 but the
  // Clopper-Pearson lower end does not; n (half-width / margin)^2 samples bring the
  // half-width, shrinking as 1/sqrt(n), down to the margin.
  std::vector<double> values(100, 0.5);
  std::fill(values.begin(), values.begin() + 5, 2.0);
  const Constraint yield{"runout_mm", ConstraintKind::kYield, 0.9, 1.0};
  const ConstraintJudgement judgement = JudgeAccurate(yield, values);
  ASSERT_EQ(judgement.verdict, Verdict::kUndecided);
  const double half_width = 0.95 - EstimateProportion(95, 100).interval.lower;
  const double margin = 0.95 - 0.9;
  EXPECT_EQ(judgement.samples_to_decide, static_cast<std::int64_t>(std::ceil(100.0 * std::pow(half_width / margin, 2))));
  EXPECT_GT(judgement.samples_to_decide, 100);

  // The median of 0, 0.001, ..., 1 is 0.5 exactly: on a limit of 0.5 no count decides it.
  const Constraint median{"runout_mm", ConstraintKind::kQuantile, 0.5, 0.5};
  const ConstraintJudgement on_limit = JudgeAccurate(median, Spaced(1001, 0.0, 1.0));
  EXPECT_EQ(on_limit.verdict, Verdict::kUndecided);
  EXPECT_EQ(on_limit.samples_to_decide, -1);
}

TEST(JudgeConstraint, RejectsMismatchedSamplesAndLevelsOutsideTheOpenUnitInterval) {
  const std::vector<double> three(3, 0.0);
  const std::vector<double> two(2, 0.0);
  const Constraint good{"runout_mm", ConstraintKind::kQuantile, 0.5, 1.0};
  EXPECT_THROW((void)JudgeConstraint(good, three, two, three, 0.95), std::invalid_argument);
  EXPECT_THROW((void)JudgeConstraint(good, {}, {}, {}, 0.95), std::invalid_argument);
  EXPECT_THROW((void)JudgeConstraint(good, three, three, three, 1.0), std::invalid_argument);
  EXPECT_THROW((void)JudgeConstraint(Constraint{"runout_mm", ConstraintKind::kYield, 1.0, 1.0}, three, three, three, 0.95),
               std::invalid_argument);
}

TEST(CombineVerdicts, InfeasibleWinsThenUnknownThenUndecided) {
  using V = Verdict;
  EXPECT_EQ(CombineVerdicts(std::vector<V>{V::kFeasible, V::kFeasible}), V::kFeasible);
  EXPECT_EQ(CombineVerdicts(std::vector<V>{V::kFeasible, V::kUndecided}), V::kUndecided);
  EXPECT_EQ(CombineVerdicts(std::vector<V>{V::kUndecided, V::kUnknown}), V::kUnknown);
  EXPECT_EQ(CombineVerdicts(std::vector<V>{V::kUnknown, V::kInfeasible, V::kUndecided}), V::kInfeasible);
  EXPECT_EQ(CombineVerdicts(std::vector<V>{}), V::kFeasible);
}

// ---------------------------------------------------------------------------------------
// The search.

TEST(AllocationSearch, BothSearchesFindTheBruteForceOptimumOnRandomCostTables) {
  for (const std::vector<int>& shape : kShapes) {
    for (int table = 0; table < kTables; ++table) {
      const Toy toy = MakeToy(shape, 1000 + static_cast<std::uint64_t>(table));
      const std::optional<std::int64_t> expected = CheapestFeasible(toy, AllocationSpace(toy.costs));
      const SearchRun exhaustive = Search(toy, {SearchKind::kExhaustive, 8});
      const SearchRun bnb = Search(toy, {SearchKind::kBranchAndBound, 8});
      ASSERT_EQ(exhaustive.best, expected) << "shape of " << shape.size() << ", table " << table;
      ASSERT_EQ(bnb.best, expected) << "shape of " << shape.size() << ", table " << table;
      ASSERT_EQ(exhaustive.simulated, AllocationSpace(toy.costs).size());
    }
  }
}

TEST(AllocationSearch, BranchAndBoundFindsTheOptimumOfAHundredThousandCandidateSpace) {
  for (int table = 0; table < 10; ++table) {
    const Toy toy = MakeToy({10, 10, 10, 10, 10}, 700 + static_cast<std::uint64_t>(table), table % 2 == 0 ? 0.0 : 0.03);
    const AllocationSpace space(toy.costs);
    const SearchOptions options{SearchKind::kBranchAndBound, 8};
    AllocationSearch search(space, options);
    const SearchRun run = Drive(search, options, [&](std::int64_t x) { return ToyVerdict(toy, space, x); });
    ASSERT_EQ(run.best, CheapestFeasible(toy, space)) << "table " << table;
    EXPECT_NE(search.settlement(0), Settlement::kNotVisited);
  }
}

TEST(AllocationSearch, BranchAndBoundSimulatesASmallFractionOfATenThousandCandidateSpace) {
  // Measured over these 200 tables (10 x 10 x 10 x 10, batch 8): mean 2.43 %, largest
  // 9.22 % of the 10^4 candidates simulated. The bounds, about 1.6 times those, leave
  // room for changes in the order of asking, not for a search that walks the space.
  constexpr double kMeanFractionBound = 0.04;
  constexpr double kLargestFractionBound = 0.15;
  const std::vector<int> shape = {10, 10, 10, 10};
  double total = 0.0;
  double largest = 0.0;
  for (int table = 0; table < kTables; ++table) {
    const Toy toy = MakeToy(shape, 5000 + static_cast<std::uint64_t>(table));
    const SearchRun bnb = Search(toy, {SearchKind::kBranchAndBound, 8});
    const double fraction = static_cast<double>(bnb.simulated) / 1e4;
    total += fraction;
    largest = std::max(largest, fraction);
  }
  const double mean = total / kTables;
  RecordProperty("mean_fraction_simulated", std::to_string(mean));
  RecordProperty("largest_fraction_simulated", std::to_string(largest));
  std::cout << "branch and bound simulated " << 100.0 * mean << " % of 10^4 candidates on average, at most "
            << 100.0 * largest << " %\n";
  EXPECT_LT(mean, kMeanFractionBound);
  EXPECT_LT(largest, kLargestFractionBound);
}

TEST(AllocationSearch, UndecidedCandidatesAreNeverBestAndNeverPruneOrImply) {
  constexpr double kBandFraction = 0.05;  // 5 % of the limit either side is undecided
  for (const std::vector<int>& shape : kShapes) {
    for (int table = 0; table < kTables; ++table) {
      const Toy toy = MakeToy(shape, 9000 + static_cast<std::uint64_t>(table), kBandFraction);
      const AllocationSpace space(toy.costs);
      const std::optional<std::int64_t> expected = CheapestFeasible(toy, space);
      const SearchRun exhaustive = Search(toy, {SearchKind::kExhaustive, 8});
      const SearchOptions options{SearchKind::kBranchAndBound, 8};
      AllocationSearch search(space, options);
      const SearchRun bnb = Drive(search, options, [&](std::int64_t x) { return ToyVerdict(toy, space, x); });
      ASSERT_EQ(exhaustive.best, expected);
      ASSERT_EQ(bnb.best, expected);
      if (bnb.best) {
        ASSERT_EQ(ToyVerdict(toy, space, *bnb.best), Verdict::kFeasible);
      }
      // An implication drawn from an undecided candidate would mark some candidate of the
      // band, or one whose true verdict differs, as implied.
      for (std::int64_t x = 0; x < space.size(); ++x) {
        if (search.settlement(x) != Settlement::kImplied) continue;
        ASSERT_NE(ToyVerdict(toy, space, x), Verdict::kUndecided) << "candidate " << x;
        ASSERT_EQ(search.verdict(x), ToyVerdict(toy, space, x)) << "candidate " << x;
      }
    }
  }
}

TEST(AllocationSearch, EveryCandidateEndsSimulatedImpliedOrCostlier) {
  const Toy toy = MakeToy({10, 10, 10, 10}, 77, 0.02);
  const AllocationSpace space(toy.costs);
  const SearchOptions options{SearchKind::kBranchAndBound, 8};
  AllocationSearch search(space, options);
  const SearchRun run = Drive(search, options, [&](std::int64_t x) { return ToyVerdict(toy, space, x); });
  ASSERT_TRUE(run.best);
  std::int64_t simulated = 0;
  for (std::int64_t x = 0; x < space.size(); ++x) {
    const Settlement settlement = search.settlement(x);
    ASSERT_NE(settlement, Settlement::kNotVisited) << "candidate " << x;
    if (settlement == Settlement::kSimulated) {
      ++simulated;
      EXPECT_EQ(search.verdict(x), ToyVerdict(toy, space, x));
    }
    if (settlement == Settlement::kCostlier) {
      EXPECT_GE(space.Cost(x), space.Cost(*run.best));
      EXPECT_EQ(search.verdict(x), Verdict::kUnknown);
    }
  }
  EXPECT_EQ(simulated, run.simulated);
  EXPECT_EQ(search.settlement(*run.best), Settlement::kSimulated);
}

TEST(AllocationSearch, BatchesDependOnTheVerdictsNotOnTheOrderTheyAreReported) {
  for (const SearchKind kind : {SearchKind::kBranchAndBound, SearchKind::kExhaustive}) {
    for (int table = 0; table < 20; ++table) {
      const Toy toy = MakeToy({5, 5, 5, 2}, 300 + static_cast<std::uint64_t>(table), 0.03);
      const SearchRun forward = Search(toy, {kind, 8});
      const SearchRun backward = Search(toy, {kind, 8}, /*reverse=*/true);
      ASSERT_EQ(forward.batches, backward.batches);
      ASSERT_EQ(forward.best, backward.best);
    }
  }
}

TEST(AllocationSearch, BestIsTheSameForEveryBatchSize) {
  for (int table = 0; table < 50; ++table) {
    const Toy toy = MakeToy({5, 5, 5, 2}, 400 + static_cast<std::uint64_t>(table), table % 2 == 0 ? 0.0 : 0.03);
    const std::optional<std::int64_t> expected = CheapestFeasible(toy, AllocationSpace(toy.costs));
    for (const int batch : {1, 3, 8, 64}) {
      ASSERT_EQ(Search(toy, {SearchKind::kBranchAndBound, batch}).best, expected) << "batch " << batch;
      ASSERT_EQ(Search(toy, {SearchKind::kExhaustive, batch}).best, expected) << "batch " << batch;
    }
  }
}

TEST(AllocationSearch, WithoutAFeasibleCandidateBranchAndBoundStopsAfterTheTightest) {
  Toy toy = MakeToy({10, 10, 10, 10}, 11);
  toy.limit = 0.0;  // every output is positive
  const AllocationSpace space(toy.costs);
  const SearchOptions options{SearchKind::kBranchAndBound, 8};
  AllocationSearch search(space, options);
  EXPECT_EQ(search.Next(), (std::vector<std::int64_t>{space.size() - 1}));
  search.Report(space.size() - 1, Verdict::kInfeasible);
  EXPECT_TRUE(search.done());
  EXPECT_TRUE(search.Next().empty());
  EXPECT_EQ(search.simulated(), 1);
  EXPECT_FALSE(search.best());
  EXPECT_EQ(search.settlement(0), Settlement::kImplied);
  EXPECT_EQ(search.verdict(0), Verdict::kInfeasible);
}

TEST(AllocationSearch, RejectsReportsOfCandidatesNotAskedForAndEarlyNextCalls) {
  const AllocationSpace space({{0.0, 1.0}, {0.0, 2.0}});
  AllocationSearch search(space, {SearchKind::kExhaustive, 2});
  const std::vector<std::int64_t> first = search.Next();
  ASSERT_EQ(first, (std::vector<std::int64_t>{0, 1}));
  EXPECT_THROW(search.Report(3, Verdict::kFeasible), std::logic_error);
  EXPECT_THROW(search.Report(0, Verdict::kUnknown), std::invalid_argument);
  search.Report(0, Verdict::kInfeasible);
  EXPECT_THROW(search.Next(), std::logic_error);
  EXPECT_THROW(search.Report(0, Verdict::kInfeasible), std::logic_error);
  EXPECT_THROW(AllocationSearch(space, {SearchKind::kExhaustive, 0}), std::invalid_argument);
}

// The refusal is an invariant check (engine/check.h): it says where, and which candidate
// against how many outstanding.
TEST(AllocationSearch, ARefusedReportNamesTheCandidateAndTheOutstandingBatch) {
  const AllocationSpace space({{0.0, 1.0}, {0.0, 2.0}});
  AllocationSearch search(space, {SearchKind::kExhaustive, 2});
  ASSERT_EQ(search.Next().size(), 2u);
  EXPECT_THAT([&] { search.Report(3, Verdict::kFeasible); },
              ThrowsMessage<std::logic_error>(::testing::AllOf(HasSubstr("analysis/allocation.cpp:"),
                                                               HasSubstr("Report: check failed"),
                                                               HasSubstr("candidate = 3, s.outstanding.size() = 2"))));
}

// ---------------------------------------------------------------------------------------
// Pareto front and common random numbers.

TEST(ParetoFront, KeepsTheUndominatedPointsByCostAndLeavesOutNaNMerits) {
  const std::vector<std::int64_t> candidates = {10, 11, 12, 13, 14, 15, 16, 17};
  const std::vector<double> cost = {1.0, 2.0, 2.0, 3.0, 4.0, 5.0, 6.0, 4.0};
  const std::vector<double> merit = {0.5, 0.7, 0.6, 0.7, 0.9, kNaN, 0.9, 0.9};
  // 12: same cost as 11, less merit; 13: dearer than 11 for the same merit; 16: dearer
  // than 14 and 17 for the same merit; 14 and 17 are equal and dominate neither way.
  EXPECT_EQ(ParetoFront(candidates, cost, merit), (std::vector<std::int64_t>{10, 11, 14, 17}));
  EXPECT_TRUE(ParetoFront({}, {}, {}).empty());
}

TEST(CommonRandomNumbersGain, IsInfiniteForAConstantDifferenceAndNaNForFewerThanTwoPairs) {
  std::vector<double> a;
  std::vector<double> b;
  for (int i = 0; i < 64; ++i) {
    a.push_back(i * 0.125);  // dyadic: a + 2 and its difference are exact
    b.push_back(i * 0.125 + 2.0);
  }
  b[5] = kNaN;  // a NaN pair is left out
  EXPECT_EQ(CommonRandomNumbersGain(a, b), kInfinity);
  EXPECT_TRUE(std::isnan(CommonRandomNumbersGain(std::vector<double>{1.0, kNaN}, std::vector<double>{2.0, 3.0})));
}

TEST(CommonRandomNumbersGain, IsNearOneForIndependentStreamsAndLargeForSmallNoise) {
  // Independent a, b of equal variance: gain = 1 / (1 - r) with r the sample correlation,
  // sd 1/sqrt(n) = 0.01; five of them: two-sided significance 6e-7.
  constexpr int kPairs = 10000;
  constexpr double kIndependentTolerance = 5.0 / 100.0;
  // b = a + noise of sd s: gain = (2 var a + s^2) / s^2 = 20001 for var a = 1, s = 0.01;
  // the sample variances of the noise and of a each have relative sd sqrt(2 / n) = 1.4 %,
  // so their ratio about 2 %; five of them: 10 %.
  constexpr double kNoise = 0.01;
  constexpr double kNoisyRelativeTolerance = 5.0 * 0.02;
  std::mt19937_64 engine(2024);
  std::normal_distribution<double> normal;
  std::vector<double> a;
  std::vector<double> independent;
  std::vector<double> noisy;
  for (int i = 0; i < kPairs; ++i) {
    a.push_back(normal(engine));
    independent.push_back(normal(engine));
    noisy.push_back(a.back() + kNoise * normal(engine));
  }
  EXPECT_NEAR(CommonRandomNumbersGain(a, independent), 1.0, kIndependentTolerance);
  const double expected = (2.0 + kNoise * kNoise) / (kNoise * kNoise);
  EXPECT_NEAR(CommonRandomNumbersGain(a, noisy) / expected, 1.0, kNoisyRelativeTolerance);
}

}  // namespace
}  // namespace ringtol::analysis
