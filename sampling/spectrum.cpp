#include "sampling/spectrum.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <queue>
#include <stdexcept>
#include <string>

#include "engine/check.h"
#include "engine/units.h"
#include "sampling/random.h"

namespace ringtol::sampling {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

struct Term {
  int order;
  double amplitude;
  double phase;
};

// The terms a measure sees, the grid MeasureForm evaluates them on, and what bounds need.
struct FormTerms {
  std::vector<Term> terms;
  int top = 0;     // highest order
  int points = 0;  // MeasureForm's grid
  // delta [-]: any evaluation here of sum a_t g(n_t theta + phi_t), g a cosine or sine, is
  // within delta sum|a_t| of the exact sum at its nominal angle. Rotation by one complex
  // product per point drifts by at most (7 points + 19 n + 4) eps |a| (sqrt 5 eps per
  // product, 2 eps in |step|, 3 eps n h in each step's angle); a direct cos, (14 n + 6) eps
  // |a| (the argument n theta + phi to eps (2 pi n + pi)); the sum over terms adds terms
  // eps. 16 eps (points + 2 top + terms + 1) covers all of these at least twice over, and
  // the few eps of each bound's own arithmetic.
  double round_off = 0.0;
  std::array<double, 4> sums{};  // sum n^k |a| for k = 0..3 [m]

  double Sum(int power) const { return sums[static_cast<std::size_t>(power)]; }
};

FormTerms TermsOf(FormMeasure measure, std::span<const engine::Harmonic> harmonics) {
  FormTerms p;
  for (const engine::Harmonic& h : harmonics) {
    if (h.amplitude == 0.0) continue;
    if (measure == FormMeasure::kRoundness && h.order >= 2) p.terms.push_back({h.order, h.amplitude, h.phase});
    // r(theta) + r(theta + pi): even orders double, odd orders cancel.
    if (measure == FormMeasure::kTwoPointVariation && h.order % 2 == 0)
      p.terms.push_back({h.order, 2.0 * h.amplitude, h.phase});
    if (!p.terms.empty()) p.top = std::max(p.top, p.terms.back().order);
  }
  for (const Term& t : p.terms) {
    double weight = t.amplitude;
    for (double& sum : p.sums) {
      sum += weight;
      weight *= t.order;
    }
  }
  p.points = std::max(64, 8 * p.top);
  p.round_off = 16.0 * kEps * (p.points + 2.0 * p.top + static_cast<double>(p.terms.size()) + 1.0);
  return p;
}

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

// Adds kLanes terms to f at points m h: cos(n theta_m + phi) by rotation, one complex product
// per point instead of a cos. The lanes' products are independent, so they overlap in the
// pipeline, where one term's chain of products waits on each; each point still adds the
// terms in their order and each product is the one a term-by-term loop computes, so the sums
// are the same bits as adding one term at a time.
template <std::size_t kLanes>
void AddRotated(const Term* terms, double spacing, std::vector<double>& f) {
  std::array<std::complex<double>, kLanes> z, step;
  for (std::size_t j = 0; j < kLanes; ++j) {
    z[j] = std::polar(terms[j].amplitude, terms[j].phase);
    step[j] = std::polar(1.0, terms[j].order * spacing);
  }
  for (double& value : f) {
    for (std::size_t j = 0; j < kLanes; ++j) {
      value += z[j].real();
      z[j] *= step[j];
    }
  }
}

// f on MeasureForm's grid of p.points points.
std::vector<double> DenseGrid(const FormTerms& p) {
  constexpr std::size_t kLanes = 4;
  const double spacing = units::kRadiansPerRevolution / p.points;
  std::vector<double> f(static_cast<std::size_t>(p.points), 0.0);
  std::size_t t = 0;
  for (; t + kLanes <= p.terms.size(); t += kLanes) AddRotated<kLanes>(&p.terms[t], spacing, f);
  for (; t < p.terms.size(); ++t) AddRotated<1>(&p.terms[t], spacing, f);
  return f;
}

// MeasureForm's value from its grid f: polish every basin that may hold an extreme.
double PolishedRange(const FormTerms& p, const std::vector<double>& f) {
  const double spacing = units::kRadiansPerRevolution / p.points;
  // A grid value is within max|f''| h^2 / 8 of the extreme of its basin, so any basin whose grid
  // value is that close to the grid's best may hold the true extreme: polish each such candidate,
  // keep the best.
  double curvature = 0.0;
  for (const Term& t : p.terms) curvature += static_cast<double>(t.order) * t.order * t.amplitude;
  const double margin = curvature * spacing * spacing / 8.0;
  const auto [low, high] = std::minmax_element(f.begin(), f.end());
  double max = *high, min = *low;
  const std::size_t n = f.size();
  for (std::size_t m = 0; m < n; ++m) {
    const double before = f[(m + n - 1) % n], here = f[m], after = f[(m + 1) % n];
    const double theta = spacing * static_cast<double>(m);
    if (here >= before && here >= after && here >= *high - margin)
      max = std::max(max, Polish(p.terms, theta, spacing, +1.0));
    if (here <= before && here <= after && here <= *low + margin)
      min = std::min(min, Polish(p.terms, theta, spacing, -1.0));
  }
  return max - min;
}

double Exact(const FormTerms& p) { return p.terms.empty() ? 0.0 : PolishedRange(p, DenseGrid(p)); }

FormBounds AmplitudeBounds(const FormTerms& p) {
  if (p.terms.empty()) return {};
  const double sum = p.Sum(0);
  double largest = 0.0;
  for (const Term& t : p.terms) largest = std::max(largest, t.amplitude);
  // The computed value is at least its grid's range (its extremes start there), which is within
  // the grid's curvature margin max|f''| h^2 / 4 of the true peak-to-valley.
  const double spacing = units::kRadiansPerRevolution / p.points;
  const double grid_margin = p.Sum(2) * spacing * spacing / 4.0;
  return {std::max(0.0, std::numbers::pi / 2.0 * largest - grid_margin - 4.0 * p.round_off * sum),
          2.0 * sum + 4.0 * p.round_off * sum};
}

// max over |t| <= r of d t + dd t^2 / 2.
double LargestQuadratic(double d, double dd, double r) {
  double best = std::max(d * r, -d * r) + dd * r * r / 2.0;
  if (dd < 0.0) {
    const double t = -d / dd;
    if (std::abs(t) <= r) best = std::max(best, -d * d / (2.0 * dd));
  }
  return best;
}

// r, r' and r'' at points m h, by rotation as in AddRotated; the product is written out (no
// NaN check: the amplitudes are finite) since only the bounds' margin, not bits, matters here.
template <std::size_t kLanes>
void AddRotatedWithSlopes(const Term* terms, double spacing, std::vector<Value>& f) {
  std::array<double, kLanes> re, im, step_re, step_im, n, n2;
  for (std::size_t j = 0; j < kLanes; ++j) {
    re[j] = terms[j].amplitude * std::cos(terms[j].phase);
    im[j] = terms[j].amplitude * std::sin(terms[j].phase);
    step_re[j] = std::cos(terms[j].order * spacing);
    step_im[j] = std::sin(terms[j].order * spacing);
    n[j] = terms[j].order;
    n2[j] = n[j] * n[j];
  }
  for (Value& value : f) {
    double v = 0.0, dv = 0.0, ddv = 0.0;
    for (std::size_t j = 0; j < kLanes; ++j) {
      v += re[j];
      dv -= n[j] * im[j];
      ddv -= n2[j] * re[j];
      const double next_re = re[j] * step_re[j] - im[j] * step_im[j];
      im[j] = re[j] * step_im[j] + im[j] * step_re[j];
      re[j] = next_re;
    }
    value.f += v;
    value.df += dv;
    value.ddf += ddv;
  }
}

FormBounds CoarseBounds(const FormTerms& p) {
  FormBounds bounds = AmplitudeBounds(p);
  if (p.terms.empty()) return bounds;
  constexpr int kStride = 4;  // every fourth point of the dense grid (points is 64 or 8 top)
  const int points = p.points / kStride;
  const double spacing = units::kRadiansPerRevolution / points, reach = spacing / 2.0;
  constexpr std::size_t kLanes = 4;
  std::vector<Value> f(static_cast<std::size_t>(points), Value{0.0, 0.0, 0.0});
  std::size_t t = 0;
  for (; t + kLanes <= p.terms.size(); t += kLanes) AddRotatedWithSlopes<kLanes>(&p.terms[t], spacing, f);
  for (; t < p.terms.size(); ++t) AddRotatedWithSlopes<1>(&p.terms[t], spacing, f);

  double value_max = -std::numeric_limits<double>::infinity(), value_min = -value_max;
  double upper_max = value_max, lower_min = value_min;
  for (const Value& v : f) {
    value_max = std::max(value_max, v.f);
    value_min = std::min(value_min, v.f);
    upper_max = std::max(upper_max, v.f + LargestQuadratic(v.df, v.ddf, reach));
    lower_min = std::min(lower_min, v.f - LargestQuadratic(-v.df, -v.ddf, reach));
  }
  // Every angle is within `reach` of a coarse point, where r = r_g + r'_g t + r''_g t^2 / 2 + R,
  // |R| <= sum n^3 |a| |t|^3 / 6.
  const double s0 = p.Sum(0), s1 = p.Sum(1), s2 = p.Sum(2), s3 = p.Sum(3);
  const double remainder = s3 * reach * reach * reach / 6.0;
  const double round_off =
      4.0 * p.round_off * (2.0 * s0 + reach * s1 + reach * reach * s2 + reach * reach * reach * s3);
  bounds.upper = std::min(bounds.upper, upper_max - lower_min + 2.0 * remainder + round_off);
  // The coarse points are points of the dense grid, whose range the exact value never undercuts.
  bounds.lower = std::max(bounds.lower, value_max - value_min - 8.0 * p.round_off * s0);
  return bounds;
}

// The terms of calibration draw i at unit scale.
FormTerms CalibrationDraw(const SpectrumShape& shape, std::span<const double> relative_scales, FormMeasure measure,
                          const CalibrationOptions& options, std::size_t i, std::vector<double>& u,
                          std::vector<double>& v) {
  for (std::size_t k = 0; k < u.size(); ++k) {
    u[k] = RandomUnit(options.seed, RandomStream::kCalibration, i, 2 * k, 0);
    v[k] = RandomUnit(options.seed, RandomStream::kCalibration, i, 2 * k + 1, 0);
  }
  return TermsOf(measure, DrawHarmonics(shape, relative_scales, 1.0, u, v));
}

// The values at 1-based ranks `ranks` (ascending) of the sorted exact measures of draws
// 0..count-1, measuring exactly only the draws whose bounds reach the ranks' window. With
// bounds lo_i <= x_i <= hi_i, the r-th smallest x lies in [r-th smallest lo, r-th smallest hi]:
// a draw whose bounds miss the window [L, H] spanned by the first and last rank is below or
// above all of them. The first pass takes a draw's coarse bounds only when its amplitude bound
// reaches the running L (the (count - first + 1)-th largest lower bound so far, never above
// the final L); rounds then measure exactly every draw meeting [L, H] until none is left
// inexact, and the window's sorted values hold the ranks, offset by the count below it.
std::vector<double> SelectRanks(std::size_t count, const std::vector<std::size_t>& ranks,
                                const std::function<FormTerms(std::size_t)>& draw) {
  enum Level : std::uint8_t { kAmplitude, kCoarse, kExact };
  const std::size_t first = ranks.front(), last = ranks.back();
  const std::size_t above = count - first + 1;  // L is the above-th largest lower bound
  std::vector<double> lo(count), hi(count);
  std::vector<Level> level(count, kAmplitude);
  std::priority_queue<double, std::vector<double>, std::greater<>> largest_lower;  // the above largest
  for (std::size_t i = 0; i < count; ++i) {
    const FormTerms p = draw(i);
    FormBounds b = AmplitudeBounds(p);
    if (largest_lower.size() < above || b.upper >= largest_lower.top()) {
      b = CoarseBounds(p);
      level[i] = kCoarse;
    }
    lo[i] = b.lower;
    hi[i] = b.upper;
    largest_lower.push(b.lower);
    if (largest_lower.size() > above) largest_lower.pop();
  }
  std::vector<double> scratch;
  auto smallest = [&scratch](const std::vector<double>& x, std::size_t rank) {
    scratch = x;
    const auto at = scratch.begin() + static_cast<std::ptrdiff_t>(rank - 1);
    std::nth_element(scratch.begin(), at, scratch.end());
    return *at;
  };
  double window_low = 0.0, window_high = 0.0;
  for (bool refined = true; refined;) {
    window_low = smallest(lo, first);
    window_high = smallest(hi, last);
    refined = false;
    for (std::size_t i = 0; i < count; ++i) {
      if (level[i] == kExact || hi[i] < window_low || lo[i] > window_high) continue;
      const FormTerms p = draw(i);
      if (level[i] == kAmplitude) {
        const FormBounds b = CoarseBounds(p);
        lo[i] = b.lower;
        hi[i] = b.upper;
      } else {
        lo[i] = hi[i] = Exact(p);
      }
      level[i] = level[i] == kAmplitude ? kCoarse : kExact;
      refined = true;
    }
  }
  std::size_t below = 0;
  std::vector<double> window;
  for (std::size_t i = 0; i < count; ++i) {
    if (hi[i] < window_low)
      ++below;
    else if (lo[i] <= window_high)
      window.push_back(lo[i]);
  }
  std::sort(window.begin(), window.end());
  std::vector<double> values;
  for (const std::size_t rank : ranks) {
    RINGTOL_CHECK(rank > below && rank - below <= window.size(), rank, below, window.size());
    values.push_back(window[rank - below - 1]);
  }
  return values;
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

std::span<const TabulatedCalibration> TabulatedCalibrations() {
  // erf(3 / sqrt 2), as Capability::Coverage computes it at Cp 1.
  constexpr double kCoverageAtCp1 = 0x1.fe9e21e067a4ap-1;
  static const std::array<TabulatedCalibration, 2> kRows = {{
      {{2, 50, 1.0, {}},
       FormMeasure::kRoundness,
       kCoverageAtCp1,
       {0x1.5f6844ecbed8ep-3, 0x1.74fddec5bea5p+2, 0x1.6fac427600297p+2, 0x1.7bc28dad398c5p+2, 16384}},
      {{2, 8, 1.0, {}},
       FormMeasure::kTwoPointVariation,
       kCoverageAtCp1,
       {0x1.05efd1a0ca02ep-3, 0x1.f465416fc53a2p+2, 0x1.ec9f8a0086846p+2, 0x1.fd98d95bb941ap+2, 16384}},
  }};
  return kRows;
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

std::vector<double> RelativeScales(const SpectrumShape& shape) {
  std::vector<double> scales;
  for (int n = shape.min_order; n <= shape.max_order; ++n) scales.push_back(shape.RelativeScale(n));
  return scales;
}

std::vector<engine::Harmonic> DrawHarmonics(const SpectrumShape& shape, double scale, std::span<const double> u,
                                            std::span<const double> v) {
  return DrawHarmonics(shape, RelativeScales(shape), scale, u, v);
}

std::vector<engine::Harmonic> DrawHarmonics(const SpectrumShape& shape, std::span<const double> relative_scales,
                                            double scale, std::span<const double> u, std::span<const double> v) {
  std::vector<engine::Harmonic> harmonics;
  harmonics.reserve(u.size());
  for (int n = shape.min_order; n <= shape.max_order; ++n) {
    const auto k = static_cast<std::size_t>(n - shape.min_order);
    const double amplitude = scale * relative_scales[k] * std::sqrt(-2.0 * std::log(u[k]));
    harmonics.push_back({n, amplitude, units::kRadiansPerRevolution * v[k] - std::numbers::pi});
  }
  return harmonics;
}

double MeasureForm(FormMeasure measure, std::span<const engine::Harmonic> harmonics) {
  return Exact(TermsOf(measure, harmonics));
}

FormBounds BoundForm(FormMeasure measure, std::span<const engine::Harmonic> harmonics, FormBoundLevel level) {
  const FormTerms p = TermsOf(measure, harmonics);
  return level == FormBoundLevel::kAmplitudes ? AmplitudeBounds(p) : CoarseBounds(p);
}

bool FormWithin(FormMeasure measure, std::span<const engine::Harmonic> harmonics, double limit) {
  const FormTerms p = TermsOf(measure, harmonics);
  if (p.terms.empty()) return 0.0 <= limit;
  for (const FormBounds& b : {AmplitudeBounds(p), CoarseBounds(p)}) {
    if (b.upper <= limit) return true;
    if (b.lower > limit) return false;
  }
  const std::vector<double> f = DenseGrid(p);
  // The exact value is max - min with max at least the grid's largest value and min at most its
  // smallest, and rounding is monotone: it is at least the grid's rounded range.
  const auto [low, high] = std::minmax_element(f.begin(), f.end());
  if (*high - *low > limit) return false;
  return PolishedRange(p, f) <= limit;
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

  if (options.tabulated) {
    const CalibrationOptions defaults;
    for (const TabulatedCalibration& row : TabulatedCalibrations()) {
      if (row.shape == shape && row.measure == measure && row.coverage == coverage &&
          options.min_draws == defaults.min_draws && options.max_draws == defaults.max_draws &&
          options.seed == defaults.seed) {
        SpectrumCalibration result = row.calibration;
        result.scale = tolerance / result.unit_quantile;
        return result;
      }
    }
  }
  const auto orders = static_cast<std::size_t>(shape.order_count());
  std::vector<double> u(orders), v(orders);
  const std::vector<double> relative_scales = RelativeScales(shape);
  auto draw = [&](std::size_t i) { return CalibrationDraw(shape, relative_scales, measure, options, i, u, v); };
  // Order statistic k = ceil(n p) (Hyndman & Fan type 1) and its binomial rank interval.
  const double n = draws;
  auto rank_of = [&](double rank) { return static_cast<std::size_t>(std::clamp(std::ceil(rank), 1.0, n)); };
  const double spread = 1.959964 * std::sqrt(n * coverage * (1.0 - coverage));
  const std::vector<std::size_t> ranks = {rank_of(n * coverage - spread), rank_of(n * coverage),
                                          rank_of(n * coverage + spread)};
  std::vector<double> at_ranks;
  const auto count = static_cast<std::size_t>(draws);
  if (options.exact_every_draw) {
    std::vector<double> values(count);
    for (std::size_t i = 0; i < count; ++i) values[i] = Exact(draw(i));
    std::sort(values.begin(), values.end());
    for (const std::size_t rank : ranks) at_ranks.push_back(values[rank - 1]);
  } else {
    at_ranks = SelectRanks(count, ranks, draw);
  }
  SpectrumCalibration result;
  result.draws = draws;
  result.unit_quantile_low = at_ranks[0];
  result.unit_quantile = at_ranks[1];
  result.unit_quantile_high = at_ranks[2];
  result.scale = tolerance / result.unit_quantile;
  return result;
}

}  // namespace ringtol::sampling
