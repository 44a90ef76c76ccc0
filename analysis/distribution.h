// The description of one output's distribution for a campaign report: summary moments,
// quantiles with distribution-free intervals, a histogram and an empirical CDF to plot,
// process capability against spec limits, the yield, and how the estimates converge with
// the number of samples. Written for runout, which is positive, right-skewed and usually
// held to an upper limit only; nothing assumes a distribution except where a normal-theory
// index says so. All values are in the output's own unit (SI inside ringtol, e.g. [m]).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "analysis/order_statistics.h"

namespace ringtol::analysis {

// Bin k covers [lower + k * bin_width, lower + (k + 1) * bin_width), each edge being that
// expression evaluated in double; the last bin is closed and also takes the maximum where
// rounding puts lower + bins * bin_width a hair below it.
struct Histogram {
  double lower = 0.0;      // left edge of bin 0 [unit of the output]
  double bin_width = 0.0;  // > 0 [unit of the output]
  std::vector<std::int64_t> counts;
};

// `sorted`: ascending, finite, n >= 1. bins > 0 splits [min, max] into that many equal
// bins. bins = 0 chooses the count from the Freedman-Diaconis width 2 IQR / n^(1/3) (IQR
// from the type-7 quartiles): ceil((max - min) / width), clamped to [10, 80] (an IQR of 0
// gives 80), then splits [min, max] into that many bins, so the edges start at the minimum
// and the width is at most the Freedman-Diaconis one unless the clamp widened it.
// A sample with zero spread (min = max = v) gets a span of |v| (1 when v = 0) centred on v,
// split into `bins` bins (one when automatic): a width on the value's own scale, since a
// fixed 1 would be a metre for a runout of micrometres.
Histogram MakeHistogram(std::span<const double> sorted, int bins = 0);

struct EcdfPoint {
  double value = 0.0;        // an order statistic x_(i) [unit of the output]
  double probability = 0.0;  // F_n(x_(i)) = #{x_j <= x_(i)} / n, computed as that count / n
};

// Corners of the right-continuous empirical CDF, one per distinct value (at ties the count
// includes the whole tie), in increasing order. With more distinct values than
// max_points (>= 2), keeps max_points of them evenly spaced in corner index (round(j (m - 1)
// / (max_points - 1)) for m corners), which always includes the minimum and the maximum.
// A plotter draws the step as horizontal from each point to the next value.
std::vector<EcdfPoint> EcdfPoints(std::span<const double> sorted, int max_points = 400);

// Either limit may be absent; both finite, lower < upper when both are set.
struct SpecLimits {
  std::optional<double> lower = std::nullopt;  // [unit of the output]
  std::optional<double> upper = std::nullopt;  // [unit of the output]
};

// ISO 22514-2 capability indices. Normal theory, with the sample mean m and standard
// deviation s (absent when s = 0):
//   Cp = (U - L) / (6 s) (both limits only), Cpu = (U - m) / (3 s), Cpl = (m - L) / (3 s),
//   Cpk = the smaller of the defined Cpu, Cpl.
// Percentile (non-normal) method, with the type-7 sample quantiles x_p and median x_0.5:
//   Cpk_percentile = min((U - x_0.5) / (x_0.99865 - x_0.5), (x_0.5 - L) / (x_0.5 - x_0.00135)),
// each term present when its limit is set and its denominator is positive. 0.00135 and
// 0.99865 are the normal's +-3 sigma probabilities, so both methods agree on normal data.
// Runout needs the percentile form: it is a magnitude, bounded below by 0 and skewed to the
// right (nearly Rayleigh for random eccentricities), so mean + 3 s falls short of its true
// 99.865 % point and Cpu overstates the capability against the upper limit that matters,
// while mean - 3 s may even lie below 0, a value runout cannot take.
struct Capability {
  std::optional<double> cp, cpk, cpu, cpl;  // [-]
  std::optional<double> cpk_percentile;     // [-]
  // True when a limit is set and n (1 - 0.99865) < 1, i.e. n <= 740: the sample then
  // holds on average no point beyond x_0.99865, whose estimate is pinned near the sample
  // extreme and biased toward the centre, so Cpk_percentile is optimistic.
  bool percentile_extrapolated = false;
};

// `sorted`: ascending, finite, n >= 1; mean and standard_deviation (>= 0) of the same sample.
Capability EstimateCapability(std::span<const double> sorted, double mean, double standard_deviation,
                              const SpecLimits& limits);

struct DistributionSummary {
  std::int64_t count = 0;
  double mean = 0.0;                        // [unit of the output]
  double standard_deviation = 0.0;          // sample (n - 1 denominator); 0 when n = 1 [unit of the output]
  double min = 0.0, max = 0.0;              // [unit of the output]
  std::vector<QuantileEstimate> quantiles;  // one per requested probability, in the order given
  Histogram histogram;                      // automatic bin count
  std::vector<EcdfPoint> ecdf;              // at most 400 points
  Capability capability;
  std::optional<ProportionEstimate> within_spec;  // L <= x <= U; present when a limit is set
};

// `values`: any order, finite, n >= 1; probabilities in (0, 1); confidence in (0, 1) for
// the quantile and yield intervals. The intervals assume independent draws; for a
// stratified design (Latin hypercube, Sobol') they are usually conservative.
DistributionSummary Describe(std::span<const double> values, std::span<const double> probabilities,
                             const SpecLimits& limits, double confidence = 0.95);

struct ConvergencePoint {
  std::int64_t samples = 0;  // size of the prefix
  QuantileEstimate quantile;
  std::optional<ProportionEstimate> within_spec;  // present when a limit is set
};

// The p-quantile and the yield on the prefixes of sizes 16, 32, 64, ... (every power of two
// from 16 below n) and n itself (n alone when n <= 16): powers of two because a Sobol'
// design is balanced exactly on those prefixes. `values_in_draw_order`: the campaign's
// design order, finite, n >= 1. Each point equals EstimateQuantile / EstimateProportion on
// its prefix.
std::vector<ConvergencePoint> TraceConvergence(std::span<const double> values_in_draw_order, double probability,
                                               const SpecLimits& limits, double confidence = 0.95);

// The number of samples at which the p-quantile's interval would have half-width
// (upper - lower) / 2 <= half_width [unit of the output], at the same confidence:
// ceil(n (h_n / half_width)^2) from the half-width h_n of `at_n`, estimated on n samples.
// The width of an order-statistic interval is 2 z sqrt(p (1 - p) / n) / f(x_p) + o(1 / sqrt(n))
// (asymptotic normality of sample quantiles, f the density), hence the 1 / sqrt(n) scaling;
// the answer is an extrapolation, good when h_n is already well resolved, and may lie below
// n when the current interval is already narrow enough. nullopt when `at_n` is unbounded on
// a side; at least 1.
std::optional<std::int64_t> SamplesForQuantilePrecision(const QuantileEstimate& at_n, std::int64_t n,
                                                        double half_width);

// The number of samples n from which on the Clopper-Pearson interval (EstimateProportion) of
// round(proportion n) successes in n has half-width (upper - lower) / 2 <= half_width, exactly,
// without a normal approximation. That half-width is a sawtooth in n, not monotone: each unit
// step of round(proportion n) widens the interval (by half at the step from 0 to 1 success),
// so a target met at some n can be lost a few samples later, and a bisection would stop at any
// crossing. The result is the smallest n such that every larger n meets the target too: n - 1
// misses it, and planning n or more samples is safe. Larger n are covered by a smooth upper
// envelope of the half-width (see the .cpp) that decreases with n; n itself is found by
// stepping down exactly, about 1 / min(p, 1 - p) interval evaluations at worst (~10 us each).
// proportion in [0, 1], half_width > 0; throws when more than 2^50 samples would be needed.
std::int64_t SamplesForProportionPrecision(double proportion, double half_width, double confidence = 0.95);

}  // namespace ringtol::analysis
