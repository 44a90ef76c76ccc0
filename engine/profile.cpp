#include "engine/profile.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <limits>
#include <stdexcept>

#include <Eigen/Core>
#include <boost/math/tools/minima.hpp>

namespace ringtol::engine {

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
  for (std::size_t n = 1; n < cos_coefficients_.size(); ++n) {
    const double a = cos_coefficients_[n];
    const double b = sin_coefficients_[n];
    const auto order = static_cast<double>(n);
    terms_.push_back({a, b, order * a, order * b, order * order * a, order * order * b});
  }
  FindExtremes();
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

RadiusDerivatives PolarProfile::EvaluateAt(double cos_theta, double sin_theta) const {
  RadiusDerivatives d{radius_ + mean_deviation_, 0.0, 0.0, cos_theta, sin_theta};
  // cos(n theta), sin(n theta) by the angle-addition recurrence: no sincos per order,
  // which would dominate the cost of a contact search.
  double cn = cos_theta;
  double sn = sin_theta;
  for (const Term& t : terms_) {
    d.r += t.a * cn - t.b * sn;
    d.dr -= t.na * sn + t.nb * cn;
    d.ddr -= t.nna * cn - t.nnb * sn;
    const double next_c = cn * cos_theta - sn * sin_theta;
    sn = sn * cos_theta + cn * sin_theta;
    cn = next_c;
  }
  return d;
}

void PolarProfile::EvaluatePairAt(const double (&cos_theta)[2], const double (&sin_theta)[2],
                                  RadiusDerivatives (&out)[2]) const {
  using Pair = Eigen::Array2d;
  const Pair c1(cos_theta[0], cos_theta[1]);
  const Pair s1(sin_theta[0], sin_theta[1]);
  Pair r = Pair::Constant(radius_ + mean_deviation_);
  Pair dr = Pair::Zero();
  Pair ddr = Pair::Zero();
  Pair cn = c1;
  Pair sn = s1;
  for (const Term& t : terms_) {
    r += t.a * cn - t.b * sn;
    dr -= t.na * sn + t.nb * cn;
    ddr -= t.nna * cn - t.nnb * sn;
    const Pair next_c = cn * c1 - sn * s1;
    sn = sn * c1 + cn * s1;
    cn = next_c;
  }
  for (int k = 0; k < 2; ++k) out[k] = {r[k], dr[k], ddr[k], cos_theta[k], sin_theta[k]};
}

void NearbyAngle::Evaluate(double theta, double& cos_theta, double& sin_theta) {
  double delta = theta - reference_;
  if (!(std::abs(delta) <= kReach)) {
    reference_ = theta;
    cos_reference_ = std::cos(theta);
    sin_reference_ = std::sin(theta);
    delta = 0.0;
  }
  const double d2 = delta * delta;
  const double cos_delta = 1.0 - d2 / 2.0 * (1.0 - d2 / 12.0 * (1.0 - d2 / 30.0 * (1.0 - d2 / 56.0)));
  const double sin_delta = delta * (1.0 - d2 / 6.0 * (1.0 - d2 / 20.0 * (1.0 - d2 / 42.0 * (1.0 - d2 / 72.0))));
  cos_theta = cos_reference_ * cos_delta - sin_reference_ * sin_delta;
  sin_theta = sin_reference_ * cos_delta + cos_reference_ * sin_delta;
}

double Curvature(const RadiusDerivatives& d) {
  const double q = d.r * d.r + d.dr * d.dr;
  return (q + d.dr * d.dr - d.r * d.ddr) / (q * std::sqrt(q));
}

SupportPoint PolarProfile::Support(double phi, double theta_guess) const {
  if (is_circle()) {
    const double r = radius_ + mean_deviation_;
    return {phi, r, 0.0, r};
  }
  // The touching point maximises r(theta) cos(theta - phi): solve its derivative
  //   f(theta) = r' cos(theta - phi) - r sin(theta - phi) = 0.
  // f > 0 at phi - pi/2 and f < 0 at phi + pi/2 while r > 0, and f is monotone between
  // for a convex outline: a bracket that makes the safeguarded Newton iteration converge
  // for any amplitude.
  constexpr double kHalfPi = std::numbers::pi / 2.0;
  constexpr double kThetaTolerance = 1e-14;  // [rad] ~ 50 ulp of 2 pi
  constexpr int kMaxIterations = 100;        // bisection alone needs < 60 from width pi
  const double cos_phi = std::cos(phi);
  const double sin_phi = std::sin(phi);
  double lo = phi - kHalfPi;
  double hi = phi + kHalfPi;
  double theta = theta_guess;
  if (!(theta > lo && theta < hi)) theta = phi + std::remainder(theta_guess - phi, 2.0 * std::numbers::pi);
  if (!(theta > lo && theta < hi)) theta = phi;
  RadiusDerivatives d{};
  double c = 1.0;  // cos(theta - phi)
  double s = 0.0;  // sin(theta - phi)
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    d = Evaluate(theta);
    c = d.cos_theta * cos_phi + d.sin_theta * sin_phi;
    s = d.sin_theta * cos_phi - d.cos_theta * sin_phi;
    const double f = d.dr * c - d.r * s;
    const double df = (d.ddr - d.r) * c - 2.0 * d.dr * s;  // < 0 near the root
    if (f > 0.0) lo = theta; else hi = theta;
    const double step = -f / df;
    if (df < 0.0 && std::abs(step) <= kThetaTolerance) break;  // h is stationary in theta
    double next = theta + step;
    if (!(df < 0.0) || !(next > lo && next < hi)) next = 0.5 * (lo + hi);
    theta = next;
  }
  const double q = d.r * d.r + d.dr * d.dr;
  return {theta, d.r * c, d.r * s, q * std::sqrt(q) / (q + d.dr * d.dr - d.r * d.ddr)};
}

void PolarProfile::FindExtremes() {
  if (is_circle()) {
    min_radius_ = max_radius_ = radius_ + mean_deviation_;
    min_curvature_ = max_curvature_ = 1.0 / min_radius_;
    return;
  }
  const int samples = 64 * max_order();
  const double step = 2.0 * std::numbers::pi / samples;
  // One pass finds the best sample of all four quantities; each is then refined.
  struct Extreme {
    double sign;  // +1 to find a minimum, -1 a maximum
    bool curvature;
    int best = 0;
    double value = 0.0;
  };
  Extreme extremes[4] = {{1.0, true}, {-1.0, true}, {1.0, false}, {-1.0, false}};
  for (int k = 0; k < samples; ++k) {
    const RadiusDerivatives d = Evaluate(k * step);
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
  min_curvature_ = extremes[0].value;
  max_curvature_ = extremes[1].value;
  min_radius_ = extremes[2].value;
  max_radius_ = extremes[3].value;
}

}  // namespace ringtol::engine
