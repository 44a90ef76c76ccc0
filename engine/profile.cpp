#include "engine/profile.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <numbers>
#include <limits>
#include <mutex>
#include <stdexcept>

#include <Eigen/Core>
#include <boost/math/tools/minima.hpp>
#include <complex>
#include <unsupported/Eigen/FFT>

namespace ringtol::engine {

// r, h r' and h^2 r'' at the grid angles theta_j = j h, h = 2 pi / count, for
// j = 0 .. count (the last a copy of the first, so an interval never wraps), and the
// quintic Hermite interpolant of r between neighbours, differentiated for r' and r''.
struct PolarProfile::SampleTable {
  struct Node {
    double r = 0.0;    // [m]
    double dr = 0.0;   // [m] r' h
    double ddr = 0.0;  // [m] r'' h^2
  };
  int count = 0;
  double per_step = 0.0;  // [1/rad] 1 / h
  std::vector<Node> nodes;

  RadiusDerivatives At(double theta) const {
    const double u = theta * per_step;
    // floor(u) without libm's call (baseline x86-64 has no rounding instruction): the
    // truncated integer, one less where truncation rounded a negative u up; exact, as
    // floor is, for |u| < 2^63.
    long cell = static_cast<long>(u);
    if (static_cast<double>(cell) > u) --cell;
    const double t = u - static_cast<double>(cell);
    // count is a power of two (SampleCount): the mask is the cell's remainder in
    // [0, count) for either sign (two's complement), without the integer division of %.
    const auto j = static_cast<std::size_t>(cell & static_cast<long>(count - 1));
    const Node& a = nodes[j];
    const Node& b = nodes[j + 1];
    // The quintic with these values, slopes and curvatures at t = 0 and 1, as a
    // polynomial in t.
    const double rise = b.r - a.r;
    const double c2 = 0.5 * a.ddr;
    const double c3 = 10.0 * rise - 6.0 * a.dr - 4.0 * b.dr - 1.5 * a.ddr + 0.5 * b.ddr;
    const double c4 = -15.0 * rise + 8.0 * a.dr + 7.0 * b.dr + 1.5 * a.ddr - b.ddr;
    const double c5 = 6.0 * rise - 3.0 * a.dr - 3.0 * b.dr - 0.5 * a.ddr + 0.5 * b.ddr;
    RadiusDerivatives d;
    d.r = a.r + t * (a.dr + t * (c2 + t * (c3 + t * (c4 + t * c5))));
    d.dr = (a.dr + t * (2.0 * c2 + t * (3.0 * c3 + t * (4.0 * c4 + t * 5.0 * c5)))) * per_step;
    d.ddr = (2.0 * c2 + t * (6.0 * c3 + t * (12.0 * c4 + t * 20.0 * c5))) * per_step * per_step;
    return d;
  }
};

namespace {

// Samples per revolution for a table of r exact to `tolerance` [m]: the quintic Hermite
// error bound h^6 / 46080 max |r^(6)| with max |r^(6)| <= sum_n n^6 |C_n|, at least eight
// per undulation of the highest order, rounded up to a power of two for the FFT.
int SampleCount(const std::vector<double>& a, const std::vector<double>& b, double tolerance) {
  double sixth_derivative = 0.0;
  for (std::size_t n = 1; n < a.size(); ++n) {
    sixth_derivative += std::pow(static_cast<double>(n), 6) * std::hypot(a[n], b[n]);
  }
  const double step = std::pow(46080.0 * tolerance / sixth_derivative, 1.0 / 6.0);
  const double wanted = std::max(2.0 * std::numbers::pi / step, 8.0 * static_cast<double>(a.size() - 1));
  // A convex outline's amplitudes fall as 1 / n^2 at least, which keeps this to a few
  // hundred thousand samples even at order 10^4; the cap only guards the loop.
  constexpr int kMaxCount = 1 << 24;
  int count = 64;
  while (count < wanted && count < kMaxCount) count *= 2;
  return count;
}

// cos and sin of the scan angles k step, k = 0 .. samples - 1, as std::cos(k * step) gives
// them, for a summed profile of highest order `order` (< kSampledOrders): kept per thread
// and order for the next such profile (a campaign's rollers share theirs), whose scan
// would otherwise spend most of its time in libm.
struct ScanAngles {
  std::vector<double> cos;
  std::vector<double> sin;
};

const ScanAngles& ScanAnglesOf(int order, int samples, double step) {
  thread_local std::array<ScanAngles, PolarProfile::kSampledOrders> kept;
  ScanAngles& angles = kept[static_cast<std::size_t>(order)];
  if (angles.cos.size() != static_cast<std::size_t>(samples)) {
    angles.cos.resize(static_cast<std::size_t>(samples));
    angles.sin.resize(static_cast<std::size_t>(samples));
    for (int k = 0; k < samples; ++k) {
      angles.cos[static_cast<std::size_t>(k)] = std::cos(k * step);
      angles.sin[static_cast<std::size_t>(k)] = std::sin(k * step);
    }
  }
  return angles;
}

}  // namespace

// What a profile that is not a circle builds on demand: each part once, published by an
// atomic pointer whose acquire load is all that later readers pay.
struct PolarProfile::Derived {
  std::once_flag table_once;
  std::atomic<const SampleTable*> table{nullptr};
  SampleTable table_storage;
  std::once_flag extremes_once;
  std::atomic<const OutlineExtremes*> extremes{nullptr};
  OutlineExtremes extremes_storage;
};

PolarProfile::PolarProfile(double radius, double mean_deviation, std::vector<Harmonic> harmonics)
    : radius_(radius), mean_deviation_(mean_deviation), harmonics_(std::move(harmonics)) {
  if (!(radius > 0.0) || !std::isfinite(radius)) {
    throw std::invalid_argument("PolarProfile: radius must be positive and finite");
  }
  int max_order = 0;
  for (const Harmonic& h : harmonics_) {
    if (h.order < 1) throw std::invalid_argument("PolarProfile: harmonic order must be >= 1");
    if (h.amplitude != 0.0) max_order = std::max(max_order, h.order);
  }
  cos_coefficients_.assign(static_cast<std::size_t>(max_order) + 1, 0.0);
  sin_coefficients_.assign(static_cast<std::size_t>(max_order) + 1, 0.0);
  for (const Harmonic& h : harmonics_) {
    if (h.amplitude == 0.0) continue;
    const auto n = static_cast<std::size_t>(h.order);
    cos_coefficients_[n] += h.amplitude * std::cos(h.phase);
    sin_coefficients_[n] += h.amplitude * std::sin(h.phase);
  }
  double moments[4] = {0.0, 0.0, 0.0, 0.0};
  double sixth = 0.0;
  terms_.reserve(static_cast<std::size_t>(max_order));
  for (std::size_t n = 1; n < cos_coefficients_.size(); ++n) {
    const double a = cos_coefficients_[n];
    const double b = sin_coefficients_[n];
    const auto order = static_cast<double>(n);
    terms_.push_back({a, b, order * a, order * b, order * order * a, order * order * b, order * order * order * a,
                      order * order * order * b});
    const double amplitude = std::hypot(a, b);
    support_bound_.odd += (order * order * order + 3.0 * order) * amplitude;
    support_bound_.even += (3.0 * order * order + 1.0) * amplitude;
    support_bound_.fourth += order * order * order * order * amplitude;
    support_bound_.series +=
        (order * order * order * order * order / 24.0 + 5.0 * order * order * order / 12.0 + 5.0 * order / 24.0) *
        amplitude;
    moments[0] += amplitude;
    moments[1] += order * amplitude;
    moments[2] += order * order * amplitude;
    moments[3] += order * order * order * amplitude;
    sixth += (order * order * order) * (order * order * order) * amplitude;
  }
  support_bound_.even += radius_ + mean_deviation_;
  if (sampled()) sample_count_ = SampleCount(cos_coefficients_, sin_coefficients_, kSampleTolerance);
  BoundExtremes(moments, sixth);
  if (!is_circle()) derived_.state = std::make_shared<Derived>();
}

void PolarProfile::BoundExtremes(const double (&moments)[4], double sixth) {
  const double rho = radius_ + mean_deviation_;
  if (is_circle()) {
    // FindExtremes' answer for a circle, exactly.
    bounds_.min_radius = bounds_.max_radius = rho;
    bounds_.min_curvature = bounds_.max_curvature = 1.0 / rho;
    return;
  }
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  const double orders = max_order();
  // How far an evaluated r, r', r'' [m, m/rad, m/rad^2] may be from the true one. Summed:
  // the angle-addition recurrence drifts by a few roundings per order and the sum rounds
  // once per term, each relative to its running size (rho for r): 16 max_order eps times
  // the moment. Interpolated from the table (sampled profiles; the scan reads it): the
  // quintic Hermite error h^6 f6 / 46080 for r and, by Rolle, the derivatives' error
  // vanishing at 5 and 4 points of the cell, h^5 f6 / 1920 and h^4 f6 / 96, f6 <= sum n^6
  // C_n; the nodes' round-off (radius added once, the FFT's log2 count stages, each a few
  // roundings of the spectrum's size <= sum C_n since n h < 1) times what the interpolant
  // makes of it, 64, 240 and 720 (its coefficients' absolute sums, in units of h^k); and the
  // cell position's rounding, 2 pi eps of angle, times the next moment.
  double error[3];
  for (int k = 0; k < 3; ++k) error[k] = 16.0 * orders * kEps * (moments[k] + (k == 0 ? std::abs(rho) : 0.0));
  if (sample_count_ > 0) {
    const double h = 2.0 * std::numbers::pi / sample_count_;
    const double node = kEps * (std::abs(rho) + moments[0]) + 8.0 * (std::log2(sample_count_) + 4.0) * kEps * moments[0];
    const double h4 = h * h * h * h;
    const double interpolation[3] = {h4 * h * h * sixth / 46080.0, h4 * h * sixth / 1920.0, h4 * sixth / 96.0};
    const double propagation[3] = {64.0 * node, 240.0 * node / h, 720.0 * node / (h * h)};
    for (int k = 0; k < 3; ++k) error[k] += interpolation[k] + propagation[k] + 16.0 * kEps * moments[k + 1];
  }
  const double r_lo = rho - moments[0] - error[0];
  const double r_hi = rho + moments[0] + error[0];
  const double slope = moments[1] + error[1];      // >= |r'|
  const double bend = moments[2] + error[2];       // >= |r''|
  // r - r'' = rho + sum (n^2 + 1) C_n cos(...) lies in [rho - spread, rho + spread]; the
  // curvature's numerator r (r - r'') + 2 r'^2 then lies in [r_lo m, r_hi M + 2 r'^2], its
  // denominator (r^2 + r'^2)^(3/2) in [r_lo^3, (r_hi^2 + r'^2)^(3/2)], and Curvature's own
  // round-off is a few eps of the numerator's terms.
  const double spread = moments[0] + moments[2] + error[0] + error[2];
  const double m = rho - spread;
  const double rounding = 8.0 * kEps * (r_hi * r_hi + 2.0 * slope * slope + r_hi * bend);
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  // A final 64 eps, outward, for the roundings of the bounds themselves and of the
  // curvature's denominator and division.
  constexpr double kOutward = 64.0 * kEps;
  bounds_.min_radius = r_lo - kOutward * std::abs(r_lo);
  bounds_.max_radius = r_hi + kOutward * std::abs(r_hi);
  bounds_.min_curvature = -kInfinity;
  bounds_.max_curvature = kInfinity;
  if (r_lo > 0.0) {
    const double high = (r_hi * (rho + spread) + 2.0 * slope * slope + rounding) / (r_lo * r_lo * r_lo);
    bounds_.max_curvature = high + kOutward * std::abs(high);
    if (m > 0.0) {
      const double q = r_hi * r_hi + slope * slope;
      const double low = (r_lo * m - rounding) / (q * std::sqrt(q));
      bounds_.min_curvature = low - kOutward * std::abs(low);
    }
  }
}

const PolarProfile::SampleTable& PolarProfile::Table() const {
  Derived& derived = *derived_.state;
  if (const SampleTable* table = derived.table.load(std::memory_order_acquire)) return *table;
  std::call_once(derived.table_once, [&] {
    SampleTable& table = derived.table_storage;
    table.count = sample_count_;
    const int count = table.count;
    const double step = 2.0 * std::numbers::pi / count;
    table.per_step = 1.0 / step;
    // r = Re sum_n c_n e^{i n theta} with c_n = a_n + i b_n: the half spectrum c_n / 2 of
    // an unscaled inverse real FFT; r' and r'' multiply c_n by i n and -n^2. One FFT
    // plan per size and thread, kept for the next profile.
    thread_local Eigen::FFT<double> fft(Eigen::default_fft_impl<double>(),
                                        static_cast<Eigen::FFT<double>::Flag>(Eigen::FFT<double>::Unscaled |
                                                                              Eigen::FFT<double>::HalfSpectrum));
    // Buffers kept per thread with the plan: fresh ones cost page faults at every profile.
    thread_local std::vector<std::complex<double>> spectrum;
    thread_local std::vector<double> samples[3];
    spectrum.resize(static_cast<std::size_t>(count / 2 + 1));
    for (int derivative = 0; derivative < 3; ++derivative) {
      std::fill(spectrum.begin(), spectrum.end(), std::complex<double>(0.0));
      for (std::size_t n = 1; n < cos_coefficients_.size(); ++n) {
        const std::complex<double> c(cos_coefficients_[n], sin_coefficients_[n]);
        const double scaled_order = static_cast<double>(n) * step;  // n h: derivatives in units of a step
        const std::complex<double> factor = derivative == 0   ? 1.0
                                            : derivative == 1 ? std::complex<double>(0.0, scaled_order)
                                                              : std::complex<double>(-scaled_order * scaled_order);
        spectrum[n] = 0.5 * factor * c;
      }
      samples[derivative].resize(static_cast<std::size_t>(count));
      fft.inv(samples[derivative].data(), spectrum.data(), count);
    }
    table.nodes.resize(static_cast<std::size_t>(count) + 1);
    for (std::size_t j = 0; j <= static_cast<std::size_t>(count); ++j) {
      const std::size_t k = j < static_cast<std::size_t>(count) ? j : 0;
      table.nodes[j] = {radius_ + mean_deviation_ + samples[0][k], samples[1][k], samples[2][k]};
    }
    derived.table.store(&table, std::memory_order_release);
  });
  return derived.table_storage;
}

const OutlineExtremes& PolarProfile::Extremes() const {
  // A circle's bounds are its extremes; a default-made profile's are zeros, as they were.
  if (!derived_.state) return bounds_;
  Derived& derived = *derived_.state;
  if (const OutlineExtremes* extremes = derived.extremes.load(std::memory_order_acquire)) return *extremes;
  std::call_once(derived.extremes_once, [&] {
    derived.extremes_storage = FindExtremes();
    derived.extremes.store(&derived.extremes_storage, std::memory_order_release);
  });
  return derived.extremes_storage;
}

double PolarProfile::cos_coefficient(int n) const {
  return n >= 0 && n <= max_order() ? cos_coefficients_[static_cast<std::size_t>(n)] : 0.0;
}

double PolarProfile::sin_coefficient(int n) const {
  return n >= 0 && n <= max_order() ? sin_coefficients_[static_cast<std::size_t>(n)] : 0.0;
}

RadiusDerivatives PolarProfile::Evaluate(double theta) const {
  return EvaluateAt(std::cos(theta), std::sin(theta));
}

RadiusDerivatives PolarProfile::EvaluateAt(double theta, double cos_theta, double sin_theta) const {
  if (!sampled()) return EvaluateAt(cos_theta, sin_theta);
  RadiusDerivatives d = Table().At(theta);
  d.cos_theta = cos_theta;
  d.sin_theta = sin_theta;
  return d;
}

template <bool kThird>
RadiusDerivatives PolarProfile::Sum(double cos_theta, double sin_theta, double& dddr) const {
  RadiusDerivatives d{radius_ + mean_deviation_, 0.0, 0.0, cos_theta, sin_theta};
  // cos(n theta), sin(n theta) by the angle-addition recurrence: no sincos per order,
  // which would dominate the cost of a contact search.
  double cn = cos_theta;
  double sn = sin_theta;
  double third = 0.0;
  for (const Term& t : terms_) {
    d.r += t.a * cn - t.b * sn;
    d.dr -= t.na * sn + t.nb * cn;
    d.ddr -= t.nna * cn - t.nnb * sn;
    if constexpr (kThird) third += t.nnna * sn + t.nnnb * cn;
    const double next_c = cn * cos_theta - sn * sin_theta;
    sn = sn * cos_theta + cn * sin_theta;
    cn = next_c;
  }
  dddr = third;
  return d;
}

RadiusDerivatives PolarProfile::EvaluateAt(double cos_theta, double sin_theta) const {
  double unused;
  return Sum<false>(cos_theta, sin_theta, unused);
}

RadiusDerivatives PolarProfile::EvaluateWithThirdAt(double cos_theta, double sin_theta, double& dddr) const {
  return Sum<true>(cos_theta, sin_theta, dddr);
}

void PolarProfile::EvaluateFourAt(const double (&cos_theta)[4], const double (&sin_theta)[4],
                                  RadiusDerivatives (&out)[4]) const {
  using Pair = Eigen::Array2d;
  const Pair c1(cos_theta[0], cos_theta[1]);
  const Pair s1(sin_theta[0], sin_theta[1]);
  const Pair c2(cos_theta[2], cos_theta[3]);
  const Pair s2(sin_theta[2], sin_theta[3]);
  Pair r1 = Pair::Constant(radius_ + mean_deviation_), r2 = r1;
  Pair dr1 = Pair::Zero(), dr2 = dr1;
  Pair ddr1 = Pair::Zero(), ddr2 = ddr1;
  Pair cn1 = c1, sn1 = s1, cn2 = c2, sn2 = s2;
  for (const Term& t : terms_) {
    r1 += t.a * cn1 - t.b * sn1;
    r2 += t.a * cn2 - t.b * sn2;
    dr1 -= t.na * sn1 + t.nb * cn1;
    dr2 -= t.na * sn2 + t.nb * cn2;
    ddr1 -= t.nna * cn1 - t.nnb * sn1;
    ddr2 -= t.nna * cn2 - t.nnb * sn2;
    const Pair next_c1 = cn1 * c1 - sn1 * s1;
    const Pair next_c2 = cn2 * c2 - sn2 * s2;
    sn1 = sn1 * c1 + cn1 * s1;
    sn2 = sn2 * c2 + cn2 * s2;
    cn1 = next_c1;
    cn2 = next_c2;
  }
  for (int k = 0; k < 2; ++k) {
    out[k] = {r1[k], dr1[k], ddr1[k], cos_theta[k], sin_theta[k]};
    out[k + 2] = {r2[k], dr2[k], ddr2[k], cos_theta[k + 2], sin_theta[k + 2]};
  }
}

double Curvature(const RadiusDerivatives& d) {
  const double q = d.r * d.r + d.dr * d.dr;
  return (q + d.dr * d.dr - d.r * d.ddr) / (q * std::sqrt(q));
}

SupportPoint PolarProfile::Support(double phi, double theta_guess) const {
  SupportPoint support =
      SupportToward(std::cos(phi), std::sin(phi), std::remainder(theta_guess - phi, 2.0 * std::numbers::pi));
  support.theta += phi;
  return support;
}

SupportPoint PolarProfile::SupportToward(double cos_phi, double sin_phi, double offset_guess) const {
  if (is_circle()) {
    const double r = radius_ + mean_deviation_;
    return {0.0, r, 0.0, r, 0};
  }
  // The touching point maximises r(theta) cos(theta - phi): solve its derivative
  //   f(delta) = r' cos(delta) - r sin(delta) = 0,  delta = theta - phi.
  // f > 0 at delta = -pi/2 and f < 0 at +pi/2 while r > 0, and f is monotone between for
  // a convex outline: a bracket that makes the safeguarded Newton iteration converge for
  // any amplitude. Iterating on the offset rather than on theta keeps the tolerance above
  // round-off however far a spinning roller has turned (its body angles reach hundreds of
  // radians, where 1e-14 rad is below one ulp), and for a nearly round outline delta
  // stays small enough for its cos and sin to come from a short series, not from libm.
  constexpr double kHalfPi = std::numbers::pi / 2.0;
  constexpr double kOffsetTolerance = 1e-14;  // [rad] ~ 10 ulp of pi / 2
  constexpr int kMaxIterations = 100;         // bisection alone needs < 60 from width pi
  double lo = -kHalfPi;
  double hi = kHalfPi;
  double delta = offset_guess > lo && offset_guess < hi ? offset_guess : 0.0;
  RadiusDerivatives d{};
  double c = 1.0;  // cos(delta)
  double s = 0.0;  // sin(delta)
  int evaluations = 0;
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    CosSinOfSmallAngle(delta, c, s);
    double dddr = 0.0;
    d = EvaluateWithThirdAt(cos_phi * c - sin_phi * s, sin_phi * c + cos_phi * s, dddr);
    ++evaluations;
    const double f = d.dr * c - d.r * s;
    const double df = (d.ddr - d.r) * c - 2.0 * d.dr * s;  // < 0 near the root
    if (f > 0.0) lo = delta; else hi = delta;
    const double step = -f / df;
    if (df < 0.0 && std::abs(step) <= kOffsetTolerance) break;  // h is stationary in theta
    // Newton's next correction would be at most |f''| / (2 |f'|) step^2, with
    // f'' = (r''' - 3 r') cos - (3 r'' - r) sin bounded by the harmonics' moments: once
    // that is within the tolerance, this step is the last one needed, and is taken by
    // Taylor series from this evaluation, which carries r''' for it: what that leaves out
    // is r'''' step^4 / 24 of r (~1e-30 m for a step of ~1e-7 rad) and r'''' step^2 / 2 of
    // the curvature's r''.
    const double curvature_bound = support_bound_.odd + support_bound_.even * std::abs(s);
    const double step_squared = step * step;
    if (df < 0.0 && curvature_bound * step_squared <= -2.0 * df * kOffsetTolerance &&
        support_bound_.fourth * step_squared <= 2.0 * kOffsetTolerance * d.r && delta + step > lo &&
        delta + step < hi) {
      double cos_step;
      double sin_step;
      CosSinOfSmallAngle(step, cos_step, sin_step);
      const double r = d.r + step * (d.dr + step * (0.5 * d.ddr + (1.0 / 6.0) * step * dddr));
      const double dr = d.dr + step * (d.ddr + 0.5 * step * dddr);
      const double ddr = d.ddr + step * dddr;
      const double next_c = c * cos_step - s * sin_step;
      const double next_s = s * cos_step + c * sin_step;
      const double q = r * r + dr * dr;
      return {delta + step, r * next_c, r * next_s, q * std::sqrt(q) / (q + dr * dr - r * ddr), evaluations};
    }
    double next = delta + step;
    if (!(df < 0.0) || !(next > lo && next < hi)) next = 0.5 * (lo + hi);
    delta = next;
  }
  const double q = d.r * d.r + d.dr * d.dr;
  return {delta, d.r * c, d.r * s, q * std::sqrt(q) / (q + d.dr * d.dr - d.r * d.ddr), evaluations};
}

SupportPoint PolarProfile::SupportTowardNearlyRound(double cos_phi, double sin_phi, double offset_tolerance) const {
  if (is_circle()) return SupportToward(cos_phi, sin_phi, 0.0);
  // r and its derivatives R0 .. R4 along the normal, in one pass over the harmonics.
  double derivative[5] = {radius_ + mean_deviation_, 0.0, 0.0, 0.0, 0.0};
  double cn = cos_phi;
  double sn = sin_phi;
  double order = 0.0;
  for (const Term& t : terms_) {
    order += 1.0;
    const double p = t.a * cn - t.b * sn;  // the harmonic's cosine part
    const double q = t.a * sn + t.b * cn;  // and its sine part
    const double order_squared = order * order;
    derivative[0] += p;
    derivative[1] -= order * q;
    derivative[2] -= order_squared * p;
    derivative[3] += order_squared * order * q;
    derivative[4] += order_squared * order_squared * p;
    const double next_c = cn * cos_phi - sn * sin_phi;
    sn = sn * cos_phi + cn * sin_phi;
    cn = next_c;
  }
  const auto& [r0, r1, r2, r3, r4] = derivative;
  // f(delta) = r'(phi + delta) cos delta - r(phi + delta) sin delta = F0 + F1 delta +
  // F2 delta^2 + F3 delta^3 + F4 delta^4 + ..., reverted: delta = d1 + a2 d1^2 + a3 d1^3,
  // d1 = -F0 / F1, with error c4 d1^4, |c4| <= 5 |F2/F1|^3 + 5 |F2/F1| |F3/F1| + |F4| / |F1|.
  const double f1 = r2 - r0;
  const double f2 = 0.5 * (r3 - 3.0 * r1);
  const double f3 = (1.0 / 6.0) * r4 - r2 + (1.0 / 6.0) * r0;
  const double d1 = -r1 / f1;
  const double ratio2 = f2 / f1;
  const double ratio3 = f3 / f1;
  const double d1_squared = d1 * d1;
  const double delta = d1 + d1_squared * (-ratio2 + d1 * (2.0 * ratio2 * ratio2 - ratio3));
  const double c4 = 5.0 * std::abs(ratio2) * (ratio2 * ratio2 + std::abs(ratio3)) + support_bound_.series / std::abs(f1);
  // f' < 0 at the touching point of a convex outline; a margin of two on the error.
  if (!(f1 < 0.0) || !(2.0 * c4 * d1_squared * d1_squared <= offset_tolerance)) {
    return SupportToward(cos_phi, sin_phi, std::isfinite(delta) ? delta : 0.0);
  }
  double c;
  double s;
  CosSinOfSmallAngle(delta, c, s);
  // r, r', r'' at the touching point by Taylor series: what they leave out is
  // r^(5) delta^5 / 120 and below, ~1e-17 m for a roller's lobes.
  const double r = r0 + delta * (r1 + delta * (0.5 * r2 + delta * ((1.0 / 6.0) * r3 + (1.0 / 24.0) * delta * r4)));
  const double dr = r1 + delta * (r2 + delta * (0.5 * r3 + (1.0 / 6.0) * delta * r4));
  const double ddr = r2 + delta * (r3 + 0.5 * delta * r4);
  const double q = r * r + dr * dr;
  return {delta, r * c, r * s, q * std::sqrt(q) / (q + dr * dr - r * ddr), 1};
}

// For a profile that is not a circle (a circle's are its bounds_).
OutlineExtremes PolarProfile::FindExtremes() const {
  const int samples = 64 * max_order();
  const double step = 2.0 * std::numbers::pi / samples;
  // The scan only ranks samples: a sampled profile interpolates for it. The refinement
  // below sums, so the extremes are exact to round-off either way. A summed profile takes
  // its samples four at a time (EvaluateFourAt, the same bits as one at a time), at angles
  // whose cosines and sines every profile of its order shares.
  thread_local std::vector<RadiusDerivatives> scan;
  scan.resize(static_cast<std::size_t>(samples));
  if (sampled()) {
    const SampleTable& table = Table();
    for (int k = 0; k < samples; ++k) scan[static_cast<std::size_t>(k)] = table.At(k * step);
  } else {
    const ScanAngles& angles = ScanAnglesOf(max_order(), samples, step);
    // samples = 64 max_order: whole groups of four.
    for (std::size_t k = 0; k < scan.size(); k += 4) {
      double cos_theta[4];
      double sin_theta[4];
      RadiusDerivatives four[4];
      std::copy_n(angles.cos.begin() + static_cast<std::ptrdiff_t>(k), 4, cos_theta);
      std::copy_n(angles.sin.begin() + static_cast<std::ptrdiff_t>(k), 4, sin_theta);
      EvaluateFourAt(cos_theta, sin_theta, four);
      std::copy_n(four, 4, scan.begin() + static_cast<std::ptrdiff_t>(k));
    }
  }
  // One pass finds the best sample of all four quantities; each is then refined.
  struct Extreme {
    double sign;  // +1 to find a minimum, -1 a maximum
    bool curvature;
    int best = 0;
    double value = 0.0;
  };
  Extreme extremes[4] = {{1.0, true}, {-1.0, true}, {1.0, false}, {-1.0, false}};
  for (int k = 0; k < samples; ++k) {
    const RadiusDerivatives& d = scan[static_cast<std::size_t>(k)];
    const double kappa = Curvature(d);
    for (Extreme& e : extremes) {
      const double value = e.sign * (e.curvature ? kappa : d.r);
      if (k == 0 || value < e.value) {
        e.value = value;
        e.best = k;
      }
    }
  }
  // Brent's minimisation within the neighbouring samples of each best sample. It places
  // the argument to sqrt(eps); the value, stationary there, is exact to second order.
  for (Extreme& e : extremes) {
    auto f = [&](double t) {
      const RadiusDerivatives d = Evaluate(t);
      return e.sign * (e.curvature ? Curvature(d) : d.r);
    };
    const auto refined = boost::math::tools::brent_find_minima(f, (e.best - 1) * step, (e.best + 1) * step,
                                                               std::numeric_limits<double>::digits);
    e.value = e.sign * std::min(e.value, refined.second);
  }
  return {extremes[0].value, extremes[1].value, extremes[2].value, extremes[3].value};
}

}  // namespace ringtol::engine
