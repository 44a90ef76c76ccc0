#include "sampling/spectrum.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>
#include <string>

#include "sampling/random.h"

namespace ringtol::sampling {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

struct Term {
  int order;
  double amplitude;
  double phase;
};

// The deviation f(theta) = sum C cos(n theta + phi) and its first two derivatives.
struct Value {
  double f, df, ddf;
};
Value Evaluate(const std::vector<Term>& terms, double theta) {
  Value v{0.0, 0.0, 0.0};
  for (const Term& t : terms) {
    const double a = t.order * theta + t.phase;
    const double c = std::cos(a), s = std::sin(a);
    const double n = t.order;
    v.f += t.amplitude * c;
    v.df -= n * t.amplitude * s;
    v.ddf -= n * n * t.amplitude * c;
  }
  return v;
}

// Newton on f' = 0 from a grid extreme, steps kept within one grid spacing so it stays in the
// extreme's basin; `sign` is +1 for a maximum, -1 for a minimum.
double Polish(const std::vector<Term>& terms, double theta, double spacing, double sign) {
  Value v = Evaluate(terms, theta);
  double best = v.f;
  for (int iteration = 0; iteration < 8; ++iteration) {
    if (sign * v.ddf >= 0.0) break;  // not curving the right way: the grid value stands
    const double step = std::clamp(-v.df / v.ddf, -spacing, spacing);
    theta += step;
    v = Evaluate(terms, theta);
    if (sign * v.f > sign * best) best = v.f;
    if (std::abs(step) < 1e-13) break;
  }
  return best;
}

}  // namespace

const char* FormMeasureName(FormMeasure measure) {
  return measure == FormMeasure::kRoundness ? "roundness (RONt, least-squares circle)" : "two-point variation (VDsp)";
}

double SpectrumShape::RelativeScale(int order) const {
  if (order < min_order || order > max_order) return 0.0;
  if (!relative_scales.empty()) return relative_scales[static_cast<std::size_t>(order - min_order)];
  return std::pow(static_cast<double>(order), -exponent);
}

void CheckSpectrumShape(const SpectrumShape& shape) {
  if (shape.min_order < 1)
    throw std::invalid_argument("lowest harmonic order " + std::to_string(shape.min_order) + ": allowed: >= 1");
  if (shape.max_order < shape.min_order)
    throw std::invalid_argument("harmonic cutoff " + std::to_string(shape.max_order) + " is below the lowest order " +
                                std::to_string(shape.min_order) + "; allowed: >= " + std::to_string(shape.min_order));
  if (!(shape.exponent >= 0.0) || !std::isfinite(shape.exponent))
    throw std::invalid_argument("spectrum exponent " + std::to_string(shape.exponent) + ": allowed: >= 0");
  if (!shape.relative_scales.empty()) {
    if (static_cast<int>(shape.relative_scales.size()) != shape.order_count())
      throw std::invalid_argument("spectrum table has " + std::to_string(shape.relative_scales.size()) +
                                  " relative scales for " + std::to_string(shape.order_count()) + " orders");
    bool any = false;
    for (const double s : shape.relative_scales) {
      if (!(s >= 0.0) || !std::isfinite(s))
        throw std::invalid_argument("spectrum table scales must be finite and >= 0");
      any = any || s > 0.0;
    }
    if (!any) throw std::invalid_argument("spectrum table scales are all zero");
  }
}

std::vector<engine::Harmonic> DrawHarmonics(const SpectrumShape& shape, double scale, std::span<const double> u,
                                            std::span<const double> v) {
  std::vector<engine::Harmonic> harmonics;
  harmonics.reserve(u.size());
  for (int n = shape.min_order; n <= shape.max_order; ++n) {
    const auto k = static_cast<std::size_t>(n - shape.min_order);
    const double amplitude = scale * shape.RelativeScale(n) * std::sqrt(-2.0 * std::log(u[k]));
    harmonics.push_back({n, amplitude, kTwoPi * v[k] - std::numbers::pi});
  }
  return harmonics;
}

double MeasureForm(FormMeasure measure, std::span<const engine::Harmonic> harmonics) {
  std::vector<Term> terms;
  int top = 0;
  for (const engine::Harmonic& h : harmonics) {
    if (h.amplitude == 0.0) continue;
    if (measure == FormMeasure::kRoundness && h.order >= 2) terms.push_back({h.order, h.amplitude, h.phase});
    // r(theta) + r(theta + pi): even orders double, odd orders cancel.
    if (measure == FormMeasure::kTwoPointVariation && h.order % 2 == 0)
      terms.push_back({h.order, 2.0 * h.amplitude, h.phase});
    if (!terms.empty()) top = std::max(top, terms.back().order);
  }
  if (terms.empty()) return 0.0;

  const int points = std::max(64, 8 * top);
  const double spacing = kTwoPi / points;
  std::vector<double> f(static_cast<std::size_t>(points), 0.0);
  for (const Term& t : terms) {
    // cos(n theta_m + phi) by rotation: one complex product per point instead of a cos.
    std::complex<double> z = std::polar(t.amplitude, t.phase);
    const std::complex<double> step = std::polar(1.0, t.order * spacing);
    for (double& value : f) {
      value += z.real();
      z *= step;
    }
  }
  // A grid value is within max|f''| h^2 / 8 of the extreme of its basin, so any basin whose grid
  // value is that close to the grid's best may hold the true extreme: polish each such candidate,
  // keep the best.
  double curvature = 0.0;
  for (const Term& t : terms) curvature += static_cast<double>(t.order) * t.order * t.amplitude;
  const double margin = curvature * spacing * spacing / 8.0;
  const auto [low, high] = std::minmax_element(f.begin(), f.end());
  double max = *high, min = *low;
  const std::size_t n = f.size();
  for (std::size_t m = 0; m < n; ++m) {
    const double before = f[(m + n - 1) % n], here = f[m], after = f[(m + 1) % n];
    const double theta = spacing * static_cast<double>(m);
    if (here >= before && here >= after && here >= *high - margin)
      max = std::max(max, Polish(terms, theta, spacing, +1.0));
    if (here <= before && here <= after && here <= *low + margin)
      min = std::min(min, Polish(terms, theta, spacing, -1.0));
  }
  return max - min;
}

SpectrumCalibration CalibrateSpectrum(const SpectrumShape& shape, FormMeasure measure, double tolerance,
                                      double coverage, const CalibrationOptions& options) {
  CheckSpectrumShape(shape);
  if (!(tolerance > 0.0) || !std::isfinite(tolerance)) throw std::invalid_argument("form tolerance must be > 0");
  if (!(coverage > 0.0 && coverage < 1.0)) throw std::invalid_argument("coverage must be inside (0, 1)");
  if (measure == FormMeasure::kTwoPointVariation) {
    bool even = false;
    for (int n = shape.min_order; n <= shape.max_order; ++n) even = even || (n % 2 == 0 && shape.RelativeScale(n) > 0);
    if (!even)
      throw std::invalid_argument("a two-point variation (VDsp) cannot see odd orders, and orders " +
                                  std::to_string(shape.min_order) + ".." + std::to_string(shape.max_order) +
                                  " have no even one with a non-zero scale: the tolerance cannot set "
                                  "their size");
  }
  constexpr double kBeyond = 40.0;  // draws expected beyond the quantile
  const double wanted = std::ceil(kBeyond / (1.0 - coverage));
  if (wanted > options.max_draws)
    throw std::invalid_argument("coverage " + std::to_string(coverage) + " needs " + std::to_string(wanted) +
                                " calibration draws to resolve its quantile; allowed: up to " +
                                std::to_string(options.max_draws) + " (capability Cp <= about 1.33)");
  const int draws = std::max(options.min_draws, static_cast<int>(wanted));

  const auto orders = static_cast<std::size_t>(shape.order_count());
  std::vector<double> u(orders), v(orders), values(static_cast<std::size_t>(draws));
  for (std::size_t i = 0; i < values.size(); ++i) {
    for (std::size_t k = 0; k < orders; ++k) {
      u[k] = RandomUnit(options.seed, RandomStream::kCalibration, i, 2 * k, 0);
      v[k] = RandomUnit(options.seed, RandomStream::kCalibration, i, 2 * k + 1, 0);
    }
    values[i] = MeasureForm(measure, DrawHarmonics(shape, 1.0, u, v));
  }
  std::sort(values.begin(), values.end());
  // Order statistic k = ceil(n p) (Hyndman & Fan type 1) and its binomial rank interval.
  const double n = draws;
  auto at_rank = [&](double rank) {
    const auto k = static_cast<std::size_t>(std::clamp(std::ceil(rank), 1.0, n));
    return values[k - 1];
  };
  const double spread = 1.959964 * std::sqrt(n * coverage * (1.0 - coverage));
  SpectrumCalibration result;
  result.draws = draws;
  result.unit_quantile = at_rank(n * coverage);
  result.unit_quantile_low = at_rank(n * coverage - spread);
  result.unit_quantile_high = at_rank(n * coverage + spread);
  result.scale = tolerance / result.unit_quantile;
  return result;
}

}  // namespace ringtol::sampling
