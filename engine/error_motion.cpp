#include "engine/error_motion.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/sensor.h"

namespace ringtol::engine {

namespace {

// Calls at(j, cos psi_j, sin psi_j) for psi_j = 2 pi j / steps, j < steps: a phasor turned
// from one angle to the next, from libm again every 256 angles.
template <typename At>
void ForEachAngle(std::size_t steps, At at) {
  const double dpsi = 2.0 * std::numbers::pi / static_cast<double>(steps);
  const double turn_cos = std::cos(dpsi), turn_sin = std::sin(dpsi);
  double c = 1.0, s = 0.0;
  for (std::size_t j = 0; j < steps; ++j) {
    if (j % 256 == 0) {
      c = std::cos(dpsi * static_cast<double>(j));
      s = std::sin(dpsi * static_cast<double>(j));
    }
    at(j, c, s);
    const double turned = c * turn_cos - s * turn_sin;
    s = s * turn_cos + c * turn_sin;
    c = turned;
  }
}

std::size_t RevolutionsOf(std::span<const double> motion, int steps) {
  if (steps < 3) throw std::invalid_argument("error motion: a revolution needs at least 3 samples");
  const auto n = static_cast<std::size_t>(steps);
  if (motion.empty() || motion.size() % n != 0) {
    throw std::invalid_argument("error motion: the samples are not whole revolutions of " + std::to_string(steps));
  }
  return motion.size() / n;
}

}  // namespace

double ErrorMotionFilter::Transmission(double undulations) const {
  return filtered() ? GaussianTransmission(undulations, cutoff_upr) : 1.0;
}

int ErrorMotionFilter::MarginRevolutions() const {
  if (!filtered()) return 0;
  // The weighting function exp(-pi (x / (alpha / cutoff))^2) keeps erfc(6) < 1e-16 of its
  // weight beyond x = 6 alpha / (sqrt(pi) cutoff) revolutions.
  const double alpha = std::sqrt(std::numbers::ln2 / std::numbers::pi);
  return static_cast<int>(std::ceil(6.0 * alpha / (std::sqrt(std::numbers::pi) * cutoff_upr)));
}

std::vector<double> FilterErrorMotion(std::span<const double> motion, int steps, const ErrorMotionFilter& filter) {
  const std::size_t revolutions = RevolutionsOf(motion, steps);
  const auto margin = static_cast<std::size_t>(filter.MarginRevolutions());
  if (revolutions <= 2 * margin) {
    throw std::invalid_argument("error motion: " + std::to_string(revolutions) + " revolutions leave none to read beside the filter's " +
                                std::to_string(margin) + " on either side");
  }
  if (!filter.filtered()) return {motion.begin(), motion.end()};
  // The record closed on itself: its join lies in the margins, which the weighting
  // function does not reach from the revolutions read. Harmonic m of the record is m /
  // revolutions undulations a revolution.
  const std::vector<double> filtered = GaussianFilterClosed(motion, filter.cutoff_upr * static_cast<double>(revolutions));
  const auto n = static_cast<std::ptrdiff_t>(steps);
  return {filtered.begin() + static_cast<std::ptrdiff_t>(margin) * n,
          filtered.end() - static_cast<std::ptrdiff_t>(margin) * n};
}

double Fundamental::At(double psi) const { return cosine * std::cos(psi) + sine * std::sin(psi); }

Fundamental FundamentalOf(std::span<const double> revolution) {
  const std::size_t steps = revolution.size();
  if (steps < 3) throw std::invalid_argument("error motion: a revolution needs at least 3 samples");
  // On equispaced angles cos and sin are orthogonal to each other and to a constant, so
  // the least-squares coefficients are the discrete Fourier ones.
  Fundamental f;
  ForEachAngle(steps, [&](std::size_t j, double c, double s) {
    f.cosine += revolution[j] * c;
    f.sine += revolution[j] * s;
  });
  f.cosine *= 2.0 / static_cast<double>(steps);
  f.sine *= 2.0 / static_cast<double>(steps);
  return f;
}

ErrorMotionBand ErrorMotionBandOf(std::span<const double> motion, int steps) {
  const std::size_t revolutions = RevolutionsOf(motion, steps);
  const auto n = static_cast<std::size_t>(steps);
  ErrorMotionBand band{std::vector<double>(n, std::numeric_limits<double>::infinity()),
                       std::vector<double>(n, -std::numeric_limits<double>::infinity()), std::vector<double>(n, 0.0),
                       0.0};
  for (std::size_t k = 0; k < revolutions; ++k) {
    for (std::size_t j = 0; j < n; ++j) {
      const double x = motion[k * n + j];
      band.average[j] += x;
      band.lowest[j] = std::min(band.lowest[j], x);
      band.highest[j] = std::max(band.highest[j], x);
    }
  }
  for (double& x : band.average) x /= static_cast<double>(revolutions);
  const Fundamental fundamental = FundamentalOf(band.average);
  band.fundamental = std::hypot(fundamental.cosine, fundamental.sine);
  ForEachAngle(n, [&](std::size_t j, double c, double s) {
    const double f = fundamental.cosine * c + fundamental.sine * s;
    band.average[j] -= f;
    band.lowest[j] -= f;
    band.highest[j] -= f;
  });
  return band;
}

ErrorMotion MeasureErrorMotion(std::span<const double> motion, int steps) {
  const ErrorMotionBand band = ErrorMotionBandOf(motion, steps);
  ErrorMotion result;
  result.fundamental = band.fundamental;
  const auto [sync_low, sync_high] = std::ranges::minmax(band.average);
  result.synchronous = sync_high - sync_low;
  result.total = std::ranges::max(band.highest) - std::ranges::min(band.lowest);
  for (std::size_t j = 0; j < band.average.size(); ++j) {
    result.asynchronous = std::max(result.asynchronous, band.highest[j] - band.lowest[j]);
  }
  return result;
}

}  // namespace ringtol::engine
