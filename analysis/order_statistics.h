// Distribution-free confidence statements from a sample: quantiles from order statistics
// and proportions (yield) from the binomial law. Nothing here assumes a distribution for
// the outputs, only that the samples are independent and identically distributed.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace ringtol::analysis {

struct Interval {
  double lower = 0.0;
  double upper = 0.0;
};

struct QuantileEstimate {
  double probability = 0.0;  // p in (0, 1)
  double value = 0.0;        // the sample quantile
  Interval interval;         // confidence interval for the true p-quantile; -inf / +inf where
                             // n is too small to bound that side at the stated confidence
  double confidence = 0.0;   // nominal two-sided level, e.g. 0.95
  std::int64_t lower_rank = 0;  // 1-based order statistics bounding the interval; 0 / n + 1 when unbounded
  std::int64_t upper_rank = 0;
};

// Throws std::invalid_argument naming the value unless 0 < confidence < 1: the check of
// every confidence level a caller passes to this folder's estimators.
void CheckConfidence(double confidence);

// The p-quantile of `sorted` (ascending, finite, n >= 1) and a distribution-free
// confidence interval [x_(l), x_(u)] whose ranks come from the Binomial(n, p) law, each
// tail holding at most (1 - confidence) / 2.
QuantileEstimate EstimateQuantile(std::span<const double> sorted, double probability, double confidence = 0.95);

struct ProportionEstimate {
  std::int64_t successes = 0;
  std::int64_t trials = 0;
  double value = 0.0;   // successes / trials
  Interval interval;    // Clopper-Pearson (exact) interval: coverage >= confidence for every p
  double confidence = 0.0;
};

// trials >= 1, 0 <= successes <= trials.
ProportionEstimate EstimateProportion(std::int64_t successes, std::int64_t trials, double confidence = 0.95);

// The sample median of `values` (any order): the middle value, or the mean of the two
// middle ones for an even count, EstimateQuantile's value at p = 0.5; NaN for no values.
double Median(std::vector<double> values);

}  // namespace ringtol::analysis
