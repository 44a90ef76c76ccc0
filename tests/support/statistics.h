// Goodness-of-fit helpers for the statistical tests. Each test states its significance
// level; with several tests in one case the level is divided among them (Bonferroni).
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

namespace ringtol::testing {

// Kolmogorov-Smirnov statistic D_n = sup |F_n(x) - F(x)| of a sample against a continuous CDF.
inline double KolmogorovSmirnovStatistic(std::vector<double> sample, const std::function<double(double)>& cdf) {
  std::sort(sample.begin(), sample.end());
  const double n = static_cast<double>(sample.size());
  double d = 0.0;
  for (std::size_t i = 0; i < sample.size(); ++i) {
    const double f = cdf(sample[i]);
    d = std::max({d, (static_cast<double>(i) + 1.0) / n - f, f - static_cast<double>(i) / n});
  }
  return d;
}

// P(sqrt(n) D_n > x) for large n: Kolmogorov's series 2 sum_k (-1)^(k-1) exp(-2 k^2 x^2).
// With Stephens' correction sqrt(n) + 0.12 + 0.11/sqrt(n) it is accurate to < 1 % in the
// tail for n >= 35 (Stephens 1970).
inline double KolmogorovSmirnovPValue(double d, std::size_t n) {
  const double root = std::sqrt(static_cast<double>(n));
  const double x = (root + 0.12 + 0.11 / root) * d;
  double p = 0.0;
  for (int k = 1; k <= 100; ++k) {
    const double term = std::exp(-2.0 * k * k * x * x);
    p += (k % 2 == 1 ? 2.0 : -2.0) * term;
    if (term < 1e-16) break;
  }
  return std::clamp(p, 0.0, 1.0);
}

// Two-sided normal quantile for a tail probability alpha (z with P(|Z| > z) = alpha),
// by bisection on erfc: tests need a handful, not speed.
inline double TwoSidedNormalQuantile(double alpha) {
  double low = 0.0, high = 40.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (low + high);
    (std::erfc(mid / std::sqrt(2.0)) > alpha ? low : high) = mid;
  }
  return 0.5 * (low + high);
}

}  // namespace ringtol::testing
