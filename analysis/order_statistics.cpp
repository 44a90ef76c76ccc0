#include "analysis/order_statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <boost/math/distributions/beta.hpp>
#include <boost/math/distributions/binomial.hpp>

namespace ringtol::analysis {

void CheckConfidence(double confidence) {
  if (!(confidence > 0.0 && confidence < 1.0)) {
    throw std::invalid_argument("confidence = " + std::to_string(confidence) + ": allowed (0, 1)");
  }
}

QuantileEstimate EstimateQuantile(std::span<const double> sorted, double probability, double confidence) {
  if (sorted.empty()) throw std::invalid_argument("EstimateQuantile: no samples");
  if (!(probability > 0.0 && probability < 1.0)) {
    throw std::invalid_argument("quantile probability = " + std::to_string(probability) + ": allowed (0, 1)");
  }
  CheckConfidence(confidence);
  const auto n = static_cast<std::int64_t>(sorted.size());
  QuantileEstimate estimate;
  estimate.probability = probability;
  estimate.confidence = confidence;
  // Hyndman & Fan type 7 (linear between order statistics), as numpy and R do by default.
  const double h = (static_cast<double>(n) - 1.0) * probability;
  const auto below = static_cast<std::size_t>(std::floor(h));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  estimate.value = sorted[below] + (h - static_cast<double>(below)) * (sorted[above] - sorted[below]);

  // The number B of samples below the true quantile is Binomial(n, p), so
  // P(x_(l) <= q_p < x_(u)) = P(l <= B < u) = F(u - 1) - F(l - 1). Choose l as the largest
  // rank with F(l - 1) <= alpha/2 and u as the smallest with 1 - F(u - 1) <= alpha/2.
  const double tail = 0.5 * (1.0 - confidence);
  const boost::math::binomial_distribution<double> law(static_cast<double>(n), probability);
  // Start from the binomial quantiles and step to the exact ranks: O(1) cdf calls at any n.
  const auto cdf = [&](std::int64_t k) { return boost::math::cdf(law, static_cast<double>(k)); };
  const auto survival = [&](std::int64_t k) {
    return boost::math::cdf(boost::math::complement(law, static_cast<double>(k)));
  };
  std::int64_t lower = std::clamp<std::int64_t>(static_cast<std::int64_t>(boost::math::quantile(law, tail)), 0, n);
  while (lower >= 1 && cdf(lower - 1) > tail) --lower;
  while (lower + 1 <= n && cdf(lower) <= tail) ++lower;  // 0 leaves it unbounded below
  std::int64_t upper = std::clamp<std::int64_t>(
      static_cast<std::int64_t>(boost::math::quantile(boost::math::complement(law, tail))) + 1, 1, n + 1);
  while (upper >= 2 && survival(upper - 2) <= tail) --upper;
  while (upper <= n && survival(upper - 1) > tail) ++upper;  // n + 1 leaves it unbounded above
  estimate.lower_rank = lower;
  estimate.upper_rank = upper;
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  estimate.interval.lower = lower >= 1 ? sorted[static_cast<std::size_t>(lower - 1)] : -kInfinity;
  estimate.interval.upper = upper <= n ? sorted[static_cast<std::size_t>(upper - 1)] : kInfinity;
  return estimate;
}

ProportionEstimate EstimateProportion(std::int64_t successes, std::int64_t trials, double confidence) {
  if (trials < 1 || successes < 0 || successes > trials) {
    throw std::invalid_argument("EstimateProportion: " + std::to_string(successes) + " successes in " +
                                std::to_string(trials) + " trials; allowed 0 <= successes <= trials, trials >= 1");
  }
  CheckConfidence(confidence);
  ProportionEstimate estimate;
  estimate.successes = successes;
  estimate.trials = trials;
  estimate.confidence = confidence;
  const double k = static_cast<double>(successes);
  const double n = static_cast<double>(trials);
  estimate.value = k / n;
  // Clopper & Pearson (1934): the exact binomial interval through beta quantiles.
  const double tail = 0.5 * (1.0 - confidence);
  estimate.interval.lower = successes == 0 ? 0.0 : boost::math::quantile(boost::math::beta_distribution<double>(k, n - k + 1.0), tail);
  estimate.interval.upper =
      successes == trials ? 1.0 : boost::math::quantile(boost::math::beta_distribution<double>(k + 1.0, n - k), 1.0 - tail);
  return estimate;
}

double Median(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  return EstimateQuantile(values, 0.5).value;
}

}  // namespace ringtol::analysis
