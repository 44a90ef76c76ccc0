#include "engine/sensor.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <vector>

#include <unsupported/Eigen/FFT>

namespace ringtol::engine {

SensorReading ReadSensor(const PolarProfile& ring, const BodyPose& ring_pose, double sensor_angle,
                         double theta_guess, SensorTrack* track) {
  SensorTrack local;
  SensorTrack& trig = track != nullptr ? *track : local;
  // f(theta) = cross(e_s, c + r(theta) e(theta + psi)): the bore point's offset from the
  // ray. With the centre near the origin, f changes sign within +-90 deg of the ray.
  constexpr double kTolerance = 1e-14;  // [rad]
  constexpr int kMaxIterations = 100;
  double cs = 1.0;
  double ss = 0.0;
  trig.sensor.Evaluate(sensor_angle, cs, ss);
  const double centre_cross = cs * ring_pose.centre.y() - ss * ring_pose.centre.x();
  const double aim = sensor_angle - ring_pose.angle;
  double lo = aim - std::numbers::pi / 2.0;
  double hi = aim + std::numbers::pi / 2.0;
  double theta = theta_guess;
  if (!(theta > lo && theta < hi)) theta = aim + std::remainder(theta_guess - aim, 2.0 * std::numbers::pi);
  if (!(theta > lo && theta < hi)) theta = aim;
  double cos_aim = 1.0;
  double sin_aim = 0.0;
  trig.aim.Evaluate(aim, cos_aim, sin_aim);
  RadiusDerivatives d;
  double s = 0.0;  // sin(theta - aim) = cross(e_s, e(theta + psi))
  double c = 1.0;  // cos(theta - aim)
  double step = 0.0;
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    double cos_theta = 1.0;
    double sin_theta = 0.0;
    trig.bore.Evaluate(theta, cos_theta, sin_theta);
    d = ring.EvaluateAt(theta, cos_theta, sin_theta);
    s = sin_theta * cos_aim - cos_theta * sin_aim;
    c = cos_theta * cos_aim + sin_theta * sin_aim;
    const double f = centre_cross + d.r * s;
    const double df = d.dr * s + d.r * c;
    if (f < 0.0) lo = theta; else hi = theta;
    step = -f / df;
    // Newton's next correction would be about f'' / (2 f') step^2 (plus ~step^3 / 6
    // where f'' vanishes, as on a circle): once that is below the tolerance, this step
    // is the last one needed, and is taken by Taylor series below.
    constexpr double kShortStep = 1e-5;  // [rad] step^3 / 6 ~ 2e-16
    const double ddf = (d.ddr - d.r) * s + 2.0 * d.dr * c;
    if (df > 0.0 && std::abs(step) <= kShortStep && std::abs(ddf / (2.0 * df)) * step * step <= kTolerance) break;
    double next = theta + step;
    if (!(df > 0.0) || !(next > lo && next < hi)) next = 0.5 * (lo + hi);
    theta = next;
    step = 0.0;
  }
  // The last Newton step taken by Taylor series rather than another evaluation: the
  // terms left out are third order in it, ~r step^3 / 6 < 1e-16 m.
  const double half_step2 = 0.5 * step * step;
  const double r = d.r + d.dr * step + d.ddr * half_step2;
  const double along = cs * ring_pose.centre.x() + ss * ring_pose.centre.y() + r * (c * (1.0 - half_step2) - s * step);
  return {along, theta + step};
}

double Swing(std::span<const double> signal, double resolution) {
  if (signal.empty()) return 0.0;
  const auto [min_it, max_it] = std::minmax_element(signal.begin(), signal.end());
  const double total = *max_it - *min_it;
  // The signal's extremes at this resolution, walking once around from the global maximum
  // and back to it: a running extreme becomes one when the signal has turned away from it
  // by more than the resolution. Peaks sit at even positions, valleys at odd ones.
  const std::size_t n = signal.size();
  const auto start = static_cast<std::size_t>(max_it - signal.begin());
  std::vector<double> extremes{signal[start]};
  bool falling = true;
  double running = signal[start];
  for (std::size_t k = 1; k <= n; ++k) {
    const double value = signal[(start + k) % n];
    if (falling ? value < running : value > running) {
      running = value;
    } else if (std::abs(value - running) > resolution) {
      extremes.push_back(running);
      falling = !falling;
      running = value;
    }
  }
  if (!falling) extremes.push_back(running);
  // Only ripples within the resolution: nothing is charged, the swing is the whole range.
  if (extremes.size() < 3) return total;

  // Neither an optimal rise nor an optimal fall needs to pass the global maximum, where the
  // walk starts and ends, so the arcs are the intervals of this list.
  double swing = 0.0;
  const std::size_t m = extremes.size();
  const auto charge = [resolution](double counter_move) { return std::max(0.0, counter_move - resolution); };
  for (std::size_t a = 0; a + 1 < m; ++a) {
    const bool from_valley = a % 2 == 1;
    const double sign = from_valley ? 1.0 : -1.0;  // rises from valleys, falls from peaks
    // No arc from e_a reaches past the signal's own extremes, and its charge only grows
    // along the walk: once that reach less the charge cannot beat the best swing, no later
    // arc can, and skipping them leaves the maximum as it is, to the bit.
    const double reach_bound = from_valley ? *max_it - extremes[a] : extremes[a] - *min_it;
    if (reach_bound <= swing) continue;
    double farthest = -std::numeric_limits<double>::infinity();  // signed, beyond e_a
    double counter_move = 0.0;
    for (std::size_t b = a + 1; b < m; ++b) {
      const double reach = sign * (extremes[b] - extremes[a]);
      if ((b - a) % 2 == 1) {
        swing = std::max(swing, reach - charge(counter_move));
        farthest = std::max(farthest, reach);
      } else {
        counter_move = std::max(counter_move, farthest - reach);
      }
      if (charge(counter_move) >= total || reach_bound - charge(counter_move) <= swing) break;
    }
  }
  return swing;
}

double GaussianTransmission(double undulations, double cutoff_upr) {
  static const double alpha = std::sqrt(std::numbers::ln2 / std::numbers::pi);
  const double ratio = alpha * undulations / cutoff_upr;
  return std::exp(-std::numbers::pi * ratio * ratio);
}

std::vector<double> GaussianFilterClosed(std::span<const double> period, double cutoff_upr) {
  const std::size_t n = period.size();
  if (n == 0) return {};
  // A revolution's plan (its twiddle factors, n sines and cosines, two thirds of a
  // filtered revolution's cost) is kept per thread and made once per size: a campaign's
  // samples share a few sizes. A record of many revolutions plans afresh, so that its
  // plan does not stay in memory for the rest of the run.
  constexpr std::size_t kLargestKeptPlan = std::size_t{1} << 16;
  thread_local Eigen::FFT<double> kept;
  Eigen::FFT<double> fresh;
  Eigen::FFT<double>& fft = n <= kLargestKeptPlan ? kept : fresh;
  std::vector<std::complex<double>> spectrum;
  fft.fwd(spectrum, std::vector<double>(period.begin(), period.end()));
  for (std::size_t k = 0; k < n; ++k) {
    spectrum[k] *= GaussianTransmission(static_cast<double>(std::min(k, n - k)), cutoff_upr);
  }
  std::vector<double> filtered;
  fft.inv(filtered, spectrum);
  return filtered;
}

Runout MeasureRunout(std::span<const double> signal, const SwingRule& rule) {
  Runout runout;
  if (signal.empty()) return runout;
  const auto [min_it, max_it] = std::minmax_element(signal.begin(), signal.end());
  runout.total = *max_it - *min_it;
  if (rule.cutoff_upr > 0.0 && signal.size() > 1) {
    runout.swing = Swing(GaussianFilterClosed(signal.first(signal.size() - 1), rule.cutoff_upr), rule.resolution);
  } else {
    runout.swing = Swing(signal, rule.resolution);
  }
  return runout;
}

}  // namespace ringtol::engine
