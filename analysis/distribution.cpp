#include "analysis/distribution.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

#include <boost/math/distributions/beta.hpp>

namespace ringtol::analysis {

namespace {

// The normal's +-3 sigma probabilities: Phi(-3) = 0.00135 (to the three digits ISO 22514-2
// uses), so the percentile indices reproduce the normal-theory ones on normal data.
constexpr double kLowerPercentile = 0.00135;
constexpr double kUpperPercentile = 0.99865;

constexpr int kMinAutomaticBins = 10;
constexpr int kMaxAutomaticBins = 80;

// Prefixes below 16 bound no quantile beyond the median at 95 % and only add noise to a plot.
constexpr std::int64_t kFirstConvergencePrefix = 16;

// Doubles hold every integer to 2^53, and nobody runs 2^50 samples.
constexpr std::int64_t kMaxProportionSamples = std::int64_t{1} << 50;

std::string Show(double x) { return std::to_string(x); }

void CheckSample(std::span<const double> values, const char* who) {
  if (values.empty()) throw std::invalid_argument(std::string(who) + ": no samples");
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      throw std::invalid_argument(std::string(who) + ": sample " + std::to_string(i) + " = " + Show(values[i]) +
                                  ": allowed finite values only");
    }
  }
}

void CheckSorted(std::span<const double> sorted, const char* who) {
  CheckSample(sorted, who);
  const auto descent = std::is_sorted_until(sorted.begin(), sorted.end());
  if (descent != sorted.end()) {
    throw std::invalid_argument(std::string(who) + ": samples not in ascending order at index " +
                                std::to_string(descent - sorted.begin()));
  }
}

void CheckLimits(const SpecLimits& limits) {
  if (limits.lower && !std::isfinite(*limits.lower)) {
    throw std::invalid_argument("lower spec limit = " + Show(*limits.lower) + ": allowed finite values only");
  }
  if (limits.upper && !std::isfinite(*limits.upper)) {
    throw std::invalid_argument("upper spec limit = " + Show(*limits.upper) + ": allowed finite values only");
  }
  if (limits.lower && limits.upper && !(*limits.lower < *limits.upper)) {
    throw std::invalid_argument("spec limits lower = " + Show(*limits.lower) + ", upper = " + Show(*limits.upper) +
                                ": allowed lower < upper");
  }
}

bool HasLimit(const SpecLimits& limits) { return limits.lower.has_value() || limits.upper.has_value(); }

void CheckProbability(double probability) {
  if (!(probability > 0.0 && probability < 1.0)) {
    throw std::invalid_argument("quantile probability = " + Show(probability) + ": allowed (0, 1)");
  }
}

// Type-7 sample quantile, the estimator EstimateQuantile reports.
double SampleQuantile(std::span<const double> sorted, double probability) {
  return EstimateQuantile(sorted, probability).value;
}

// Samples of `sorted` with L <= x <= U, either limit possibly absent.
std::int64_t CountWithin(std::span<const double> sorted, const SpecLimits& limits) {
  const auto first = limits.lower ? std::lower_bound(sorted.begin(), sorted.end(), *limits.lower) : sorted.begin();
  const auto last = limits.upper ? std::upper_bound(sorted.begin(), sorted.end(), *limits.upper) : sorted.end();
  return last > first ? static_cast<std::int64_t>(last - first) : 0;
}

double IntervalHalfWidth(const Interval& interval) { return 0.5 * (interval.upper - interval.lower); }

}  // namespace

Histogram MakeHistogram(std::span<const double> sorted, int bins) {
  CheckSorted(sorted, "MakeHistogram");
  if (bins < 0) {
    throw std::invalid_argument("histogram bins = " + std::to_string(bins) + ": allowed >= 0 (0: automatic)");
  }
  const double min = sorted.front();
  const double max = sorted.back();
  const double range = max - min;
  if (!std::isfinite(range)) {
    throw std::invalid_argument("MakeHistogram: range " + Show(min) + " .. " + Show(max) + " overflows a double");
  }
  Histogram histogram;
  int count = bins;
  if (range == 0.0) {
    if (count == 0) count = 1;
    const double span = min != 0.0 ? std::abs(min) : 1.0;
    histogram.bin_width = span / count;
    histogram.lower = min - 0.5 * span;
  } else {
    if (count == 0) {
      const double iqr = SampleQuantile(sorted, 0.75) - SampleQuantile(sorted, 0.25);
      const double fd_width = 2.0 * iqr / std::cbrt(static_cast<double>(sorted.size()));
      const double fd_bins = fd_width > 0.0 ? std::ceil(range / fd_width) : kMaxAutomaticBins;
      count = static_cast<int>(std::clamp<double>(fd_bins, kMinAutomaticBins, kMaxAutomaticBins));
    }
    histogram.bin_width = range / count;
    histogram.lower = min;
  }
  histogram.counts.assign(static_cast<std::size_t>(count), 0);
  const auto edge = [&](int k) { return histogram.lower + k * histogram.bin_width; };
  for (const double x : sorted) {
    // The division only guesses the bin; the comparisons against the edges as defined decide
    // it, so the counts agree with the documented edges whatever the division rounds to.
    double guess = (x - histogram.lower) / histogram.bin_width;
    if (!(guess >= 0.0)) guess = 0.0;  // also catches NaN from a zero width
    int k = static_cast<int>(std::min<double>(guess, count - 1));
    while (k + 1 < count && x >= edge(k + 1)) ++k;
    while (k > 0 && x < edge(k)) --k;
    ++histogram.counts[static_cast<std::size_t>(k)];
  }
  return histogram;
}

std::vector<EcdfPoint> EcdfPoints(std::span<const double> sorted, int max_points) {
  CheckSorted(sorted, "EcdfPoints");
  if (max_points < 2) {
    throw std::invalid_argument("ECDF max_points = " + std::to_string(max_points) + ": allowed >= 2");
  }
  const double n = static_cast<double>(sorted.size());
  // The last index of each run of equal values is where F_n steps to its new level.
  std::vector<std::size_t> corners;
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    if (i + 1 == sorted.size() || sorted[i + 1] != sorted[i]) corners.push_back(i);
  }
  const auto m = static_cast<std::int64_t>(corners.size());
  const std::int64_t kept = std::min<std::int64_t>(m, max_points);
  std::vector<EcdfPoint> points;
  points.reserve(static_cast<std::size_t>(kept));
  for (std::int64_t j = 0; j < kept; ++j) {
    // Integer rounding of j (m - 1) / (kept - 1): exact, and the identity when kept = m.
    const std::int64_t c = kept == 1 ? 0 : (j * (m - 1) + (kept - 1) / 2) / (kept - 1);
    const std::size_t i = corners[static_cast<std::size_t>(c)];
    points.push_back({sorted[i], static_cast<double>(i + 1) / n});
  }
  return points;
}

Capability EstimateCapability(std::span<const double> sorted, double mean, double standard_deviation,
                              const SpecLimits& limits) {
  CheckSorted(sorted, "EstimateCapability");
  CheckLimits(limits);
  if (!std::isfinite(mean)) {
    throw std::invalid_argument("EstimateCapability: mean = " + Show(mean) + ": allowed finite");
  }
  if (!(standard_deviation >= 0.0 && std::isfinite(standard_deviation))) {
    throw std::invalid_argument("EstimateCapability: standard deviation = " + Show(standard_deviation) +
                                ": allowed finite and >= 0");
  }
  Capability capability;
  if (!HasLimit(limits)) return capability;

  // s = 0 would divide by zero: no index rather than an infinite one.
  if (standard_deviation > 0.0) {
    const double s = standard_deviation;
    if (limits.upper) capability.cpu = (*limits.upper - mean) / (3.0 * s);
    if (limits.lower) capability.cpl = (mean - *limits.lower) / (3.0 * s);
    if (limits.lower && limits.upper) capability.cp = (*limits.upper - *limits.lower) / (6.0 * s);
    capability.cpk = capability.cpu && capability.cpl ? std::min(*capability.cpu, *capability.cpl)
                                                      : (capability.cpu ? capability.cpu : capability.cpl);
  }

  const double median = SampleQuantile(sorted, 0.5);
  std::optional<double> upper_term, lower_term;
  if (limits.upper) {
    const double spread = SampleQuantile(sorted, kUpperPercentile) - median;
    if (spread > 0.0) upper_term = (*limits.upper - median) / spread;
  }
  if (limits.lower) {
    const double spread = median - SampleQuantile(sorted, kLowerPercentile);
    if (spread > 0.0) lower_term = (median - *limits.lower) / spread;
  }
  capability.cpk_percentile =
      upper_term && lower_term ? std::min(*upper_term, *lower_term) : (upper_term ? upper_term : lower_term);
  capability.percentile_extrapolated = static_cast<double>(sorted.size()) * (1.0 - kUpperPercentile) < 1.0;
  return capability;
}

DistributionSummary Describe(std::span<const double> values, std::span<const double> probabilities,
                             const SpecLimits& limits, double confidence) {
  CheckSample(values, "Describe");
  for (const double p : probabilities) CheckProbability(p);
  CheckLimits(limits);
  CheckConfidence(confidence);
  std::vector<double> sorted(values.begin(), values.end());
  std::sort(sorted.begin(), sorted.end());

  DistributionSummary summary;
  summary.count = static_cast<std::int64_t>(sorted.size());
  const double n = static_cast<double>(sorted.size());
  summary.min = sorted.front();
  summary.max = sorted.back();
  // Corrected two-pass algorithm (Chan, Golub & LeVeque 1983): the second pass removes the
  // first mean's rounding, and deviations from it keep the variance free of the
  // cancellation that sum(x^2) - n m^2 suffers when the spread is small beside the mean.
  double sum = 0.0;
  for (const double x : sorted) sum += x;
  double mean = sum / n;
  double deviation_sum = 0.0, square_sum = 0.0;
  for (const double x : sorted) {
    deviation_sum += x - mean;
    square_sum += (x - mean) * (x - mean);
  }
  if (sorted.size() > 1) {
    const double variance = (square_sum - deviation_sum * deviation_sum / n) / (n - 1.0);
    summary.standard_deviation = std::sqrt(std::max(variance, 0.0));
  }
  mean += deviation_sum / n;
  // Rounding may leave a mean of equal values an ulp outside them; a report should never show it.
  summary.mean = std::clamp(mean, summary.min, summary.max);

  summary.quantiles.reserve(probabilities.size());
  for (const double p : probabilities) summary.quantiles.push_back(EstimateQuantile(sorted, p, confidence));
  summary.histogram = MakeHistogram(sorted);
  summary.ecdf = EcdfPoints(sorted);
  summary.capability = EstimateCapability(sorted, summary.mean, summary.standard_deviation, limits);
  if (HasLimit(limits)) {
    summary.within_spec = EstimateProportion(CountWithin(sorted, limits), summary.count, confidence);
  }
  return summary;
}

std::vector<ConvergencePoint> TraceConvergence(std::span<const double> values_in_draw_order, double probability,
                                               const SpecLimits& limits, double confidence) {
  CheckSample(values_in_draw_order, "TraceConvergence");
  CheckProbability(probability);
  CheckLimits(limits);
  CheckConfidence(confidence);
  const auto n = static_cast<std::int64_t>(values_in_draw_order.size());
  std::vector<std::int64_t> sizes;
  for (std::int64_t size = kFirstConvergencePrefix; size < n; size *= 2) sizes.push_back(size);
  sizes.push_back(n);

  // Each prefix is the previous one plus a sorted block merged in: O(n log n) in all,
  // rather than a fresh sort per prefix.
  std::vector<double> sorted;
  sorted.reserve(values_in_draw_order.size());
  std::vector<ConvergencePoint> points;
  points.reserve(sizes.size());
  for (const std::int64_t size : sizes) {
    const auto middle = static_cast<std::ptrdiff_t>(sorted.size());
    sorted.insert(sorted.end(), values_in_draw_order.begin() + middle, values_in_draw_order.begin() + size);
    std::sort(sorted.begin() + middle, sorted.end());
    std::inplace_merge(sorted.begin(), sorted.begin() + middle, sorted.end());
    ConvergencePoint point;
    point.samples = size;
    point.quantile = EstimateQuantile(sorted, probability, confidence);
    if (HasLimit(limits)) point.within_spec = EstimateProportion(CountWithin(sorted, limits), size, confidence);
    points.push_back(point);
  }
  return points;
}

std::optional<std::int64_t> SamplesForQuantilePrecision(const QuantileEstimate& at_n, std::int64_t n,
                                                        double half_width) {
  if (n < 1) throw std::invalid_argument("SamplesForQuantilePrecision: n = " + std::to_string(n) + ": allowed >= 1");
  if (!(half_width > 0.0 && std::isfinite(half_width))) {
    throw std::invalid_argument("quantile half_width = " + Show(half_width) + ": allowed finite and > 0");
  }
  if (!std::isfinite(at_n.interval.lower) || !std::isfinite(at_n.interval.upper)) return std::nullopt;
  if (!(at_n.interval.lower <= at_n.interval.upper)) {
    throw std::invalid_argument("SamplesForQuantilePrecision: interval " + Show(at_n.interval.lower) + " .. " +
                                Show(at_n.interval.upper) + ": allowed lower <= upper");
  }
  const double ratio = IntervalHalfWidth(at_n.interval) / half_width;
  const double needed = std::ceil(static_cast<double>(n) * ratio * ratio);
  // 2^62 keeps the conversion exact and far from overflow; nobody runs that many samples.
  constexpr auto kMaxSamples = static_cast<double>(std::int64_t{1} << 62);
  if (!(needed < kMaxSamples)) {
    throw std::invalid_argument("quantile half_width = " + Show(half_width) + " would need " + Show(needed) +
                                " samples: allowed < 2^62");
  }
  return std::max<std::int64_t>(static_cast<std::int64_t>(needed), 1);
}

std::int64_t SamplesForProportionPrecision(double proportion, double half_width, double confidence) {
  if (!(proportion >= 0.0 && proportion <= 1.0)) {
    throw std::invalid_argument("proportion = " + Show(proportion) + ": allowed [0, 1]");
  }
  if (!(half_width > 0.0 && std::isfinite(half_width))) {
    throw std::invalid_argument("proportion half_width = " + Show(half_width) + ": allowed finite and > 0");
  }
  CheckConfidence(confidence);
  const double tail = 0.5 * (1.0 - confidence);
  const auto meets = [&](std::int64_t n) {
    const auto successes = static_cast<std::int64_t>(std::round(proportion * static_cast<double>(n)));
    return IntervalHalfWidth(EstimateProportion(successes, n, confidence).interval) <= half_width;
  };
  // Half the Clopper-Pearson width at real k, the formulas of EstimateProportion, so that it
  // equals the exact half-width at integer k.
  const auto half_width_at = [&](double k, double n) {
    const double lower =
        k <= 0.0 ? 0.0 : boost::math::quantile(boost::math::beta_distribution<double>(k, n - k + 1.0), tail);
    const double upper =
        k >= n ? 1.0 : boost::math::quantile(boost::math::beta_distribution<double>(k + 1.0, n - k), 1.0 - tail);
    return 0.5 * (upper - lower);
  };
  // round(p n) lies in [p n - 1/2, p n + 1/2], and the width is symmetric about k = n / 2 and
  // grows with k up to there, so its largest value on that range bounds the half-width at n.
  // Unlike the half-width itself this envelope is smooth and decreasing in n. (Both checked
  // numerically: the growth in k for n <= 1000, the decrease for every n <= 1e5 on a grid of p
  // from 0 to 1 at confidences 0.9, 0.95 and 0.99.)
  const auto envelope = [&](std::int64_t count) {
    const double n = static_cast<double>(count);
    const double low = std::max(proportion * n - 0.5, 0.0), high = std::min(proportion * n + 0.5, n);
    return half_width_at(high <= 0.5 * n ? high : (low >= 0.5 * n ? low : 0.5 * n), n);
  };
  const auto too_many = [&]() {
    return std::invalid_argument("proportion half_width = " + Show(half_width) + " at proportion " + Show(proportion) +
                                 " would need more than 2^50 samples");
  };

  // The first n where the envelope meets the target, by doubling and bisection: every larger
  // n meets it too. Then step down to the last n that misses; the steps number about the
  // envelope's excess over the half-width divided by its slope, O(1 / min(p, 1 - p)) at most.
  std::int64_t miss = 0, hit = 1;
  while (envelope(hit) > half_width) {
    miss = hit;
    hit *= 2;
    if (hit > kMaxProportionSamples) throw too_many();
  }
  while (hit - miss > 1) {
    const std::int64_t middle = miss + (hit - miss) / 2;
    (envelope(middle) <= half_width ? hit : miss) = middle;
  }
  while (!meets(hit)) ++hit;  // only against rounding: the envelope bounds the half-width
  while (hit > 1 && meets(hit - 1)) --hit;
  return hit;
}

}  // namespace ringtol::analysis
